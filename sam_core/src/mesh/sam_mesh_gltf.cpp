// glTF 2.0 (.gltf, .glb) through TinyGLTF behind C functions
// (sam_mesh_soup.h): the triangles of every mesh primitive in the default
// scene with their node transforms applied, TEXCOORD_0, COLOR_0, and the
// base-colour texture. No exception crosses into C.
#include <cjson/cJSON.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "../io/sam_image_internal.h"
#include "sam_mesh_cpp.hpp"
#include "sam_mesh_gltf_draco.h"
#include "sam_mesh_gltf_glb.h"
#include "sam_mesh_gltf_meshopt.h"

namespace {

// What the file holds, checked while it is read: the first problem ends
// the read with its message.
struct Reader {
    const tinygltf::Model &model;
    const char *path;
    std::vector<float> positions, normals, uvs, colors;
    std::vector<uint32_t> corners, face_materials;
    bool all_normals = true, all_uvs = true, any_colors = false, any_material = false;
    uint32_t skipped_primitives = 0; // points and lines
};

struct Problem {
    std::string what;
};

[[noreturn]] void fail(const std::string &what)
{
    throw Problem{what};
}

std::string name_of(const char *kind, int index)
{
    return std::string(kind) + " " + std::to_string(index);
}

// `count` elements `stride` bytes apart from `data`, each `want`
// components of glTF component type `type` (a normalised integer type
// scaled as the specification says; KHR_mesh_quantization's plain integers
// as they are), as floats. The caller has checked the bytes are there.
std::vector<float> to_floats(const unsigned char *data, size_t count, uint64_t stride, int type, bool normalized,
                             int want, const std::string &where)
{
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(type));
    std::vector<float> out(count * size_t(want), 0.0f);
    for (size_t e = 0; e < count; ++e)
        for (int c = 0; c < want; ++c) {
            const unsigned char *p = data + stride * e + uint64_t(size) * c;
            float x;
            switch (type) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT:
                std::memcpy(&x, p, 4);
                break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                x = normalized ? *p / 255.0f : *p;
                break;
            case TINYGLTF_COMPONENT_TYPE_BYTE:
                x = normalized ? std::fmax(int8_t(*p) / 127.0f, -1.0f) : int8_t(*p);
                break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t u;
                std::memcpy(&u, p, 2);
                x = normalized ? u / 65535.0f : u;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                int16_t s;
                std::memcpy(&s, p, 2);
                x = normalized ? std::fmax(s / 32767.0f, -1.0f) : s;
                break;
            }
            default:
                fail(where + ": component type " + std::to_string(type) + " is not a vertex attribute's");
            }
            if (!std::isfinite(x))
                fail(where + ": component " + std::to_string(c) + " of element " + std::to_string(e) +
                     " is not finite");
            out[e * size_t(want) + size_t(c)] = x;
        }
    return out;
}

// Accessor `index`, which must exist and have `want` components per
// element; `where` names it for messages.
const tinygltf::Accessor &accessor(const Reader &r, int index, int want, const char *what, std::string &where)
{
    const tinygltf::Model &m = r.model;
    if (index < 0 || size_t(index) >= m.accessors.size())
        fail(std::string(what) + ": accessor " + std::to_string(index) + " does not exist (" +
             std::to_string(m.accessors.size()) + " accessors)");
    const tinygltf::Accessor &a = m.accessors[size_t(index)];
    where = name_of("accessor", index) + " (" + what + ")";
    if (tinygltf::GetNumComponentsInType(uint32_t(a.type)) != want)
        fail(where + ": expected " + std::to_string(want) + " components per element");
    return a;
}

// Accessor `index` as `want` floats per element, every byte range checked
// against its buffer.
std::vector<float> read_floats(const Reader &r, int index, int want, const char *what)
{
    const tinygltf::Model &m = r.model;
    std::string where;
    const tinygltf::Accessor &a = accessor(r, index, want, what, where);
    if (a.sparse.isSparse || a.bufferView < 0)
        fail(where + ": sparse accessors and accessors without a buffer view are not supported");
    if (size_t(a.bufferView) >= m.bufferViews.size())
        fail(where + ": buffer view " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView &v = m.bufferViews[size_t(a.bufferView)];
    if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
        fail(where + ": buffer " + std::to_string(v.buffer) + " does not exist");
    const std::vector<unsigned char> &data = m.buffers[size_t(v.buffer)].data;
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    const int stride = a.ByteStride(v);
    if (size <= 0 || stride <= 0)
        fail(where + ": component type " + std::to_string(a.componentType) + " or stride " +
             std::to_string(v.byteStride) + " is not valid");
    // Counts and offsets come from the file: bounded by the buffer before
    // any product of them is formed or anything is allocated.
    if (a.count > v.byteLength || a.byteOffset > v.byteLength || v.byteLength > data.size() ||
        v.byteOffset > data.size() - v.byteLength)
        fail(where + ": " + std::to_string(a.count) + " elements at offset " + std::to_string(a.byteOffset) +
             " do not fit buffer view " + std::to_string(a.bufferView) + " (" + std::to_string(v.byteLength) +
             " bytes at " + std::to_string(v.byteOffset) + " of a " + std::to_string(data.size()) + "-byte buffer)");
    const uint64_t start = uint64_t(v.byteOffset) + a.byteOffset;
    const uint64_t need = a.count ? uint64_t(stride) * (a.count - 1) + uint64_t(size) * want : 0;
    if (a.byteOffset + need > v.byteLength)
        fail(where + ": " + std::to_string(a.count) + " elements need " + std::to_string(need) +
             " bytes past offset " + std::to_string(a.byteOffset) + " of buffer view " +
             std::to_string(a.bufferView) + ", which has " + std::to_string(v.byteLength));
    return to_floats(data.data() + start, a.count, uint64_t(stride), a.componentType, a.normalized, want, where);
}

// COLOR_0's components, RGB or RGBA (glTF allows both); a primitive
// without it gives 0.
int color_components(const Reader &r, int index)
{
    if (index < 0)
        return 0;
    if (size_t(index) >= r.model.accessors.size())
        fail("COLOR_0: accessor " + std::to_string(index) + " does not exist (" +
             std::to_string(r.model.accessors.size()) + " accessors)");
    return r.model.accessors[size_t(index)].type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
}

// The index accessor of a primitive, or 0..vertices-1 without one.
std::vector<uint32_t> read_indices(const Reader &r, int index, size_t vertices)
{
    std::vector<uint32_t> out;
    if (index < 0) {
        out.resize(vertices);
        for (size_t i = 0; i < vertices; ++i)
            out[i] = uint32_t(i);
        return out;
    }
    const tinygltf::Model &m = r.model;
    if (size_t(index) >= m.accessors.size())
        fail("indices: accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor &a = m.accessors[size_t(index)];
    const std::string where = name_of("accessor", index) + " (indices)";
    const int t = a.componentType;
    if (a.type != TINYGLTF_TYPE_SCALAR ||
        (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        fail(where + ": indices must be unsigned byte, short or int scalars");
    if (a.sparse.isSparse || a.bufferView < 0 || size_t(a.bufferView) >= m.bufferViews.size())
        fail(where + ": no buffer view to read");
    const tinygltf::BufferView &v = m.bufferViews[size_t(a.bufferView)];
    if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
        fail(where + ": buffer " + std::to_string(v.buffer) + " does not exist");
    const std::vector<unsigned char> &data = m.buffers[size_t(v.buffer)].data;
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(t));
    if (a.count > v.byteLength || a.byteOffset > v.byteLength || v.byteLength > data.size() ||
        v.byteOffset > data.size() - v.byteLength)
        fail(where + ": " + std::to_string(a.count) + " indices do not fit buffer view " +
             std::to_string(a.bufferView));
    const uint64_t start = uint64_t(v.byteOffset) + a.byteOffset, need = uint64_t(size) * a.count;
    if (a.byteOffset + need > v.byteLength)
        fail(where + ": " + std::to_string(a.count) + " indices run past the " + std::to_string(data.size()) +
             "-byte buffer");
    out.resize(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        const unsigned char *p = data.data() + start + uint64_t(size) * i;
        uint32_t x = *p;
        if (size == 2) {
            uint16_t u;
            std::memcpy(&u, p, 2);
            x = u;
        } else if (size == 4) {
            std::memcpy(&x, p, 4);
        }
        if (x >= vertices)
            fail(where + ": index " + std::to_string(x) + " at " + std::to_string(i) + " is out of range (" +
                 std::to_string(vertices) + " vertices)");
        out[i] = x;
    }
    return out;
}

// Column-major 4x4 products and the node's own transform.
using Mat4 = std::vector<double>;

Mat4 multiply(const Mat4 &a, const Mat4 &b)
{
    Mat4 m(16, 0.0);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k)
                m[size_t(4 * c + r)] += a[size_t(4 * k + r)] * b[size_t(4 * c + k)];
    return m;
}

Mat4 local_transform(const tinygltf::Node &n, int index)
{
    if (n.matrix.size() == 16)
        return n.matrix;
    if (!n.matrix.empty())
        fail(name_of("node", index) + ": matrix of " + std::to_string(n.matrix.size()) + " numbers (expected 16)");
    const std::vector<double> &t = n.translation, &q = n.rotation, &s = n.scale;
    if ((!t.empty() && t.size() != 3) || (!q.empty() && q.size() != 4) || (!s.empty() && s.size() != 3))
        fail(name_of("node", index) + ": translation, rotation or scale of the wrong length");
    const double x = q.empty() ? 0 : q[0], y = q.empty() ? 0 : q[1], z = q.empty() ? 0 : q[2],
                 w = q.empty() ? 1 : q[3];
    const double sx = s.empty() ? 1 : s[0], sy = s.empty() ? 1 : s[1], sz = s.empty() ? 1 : s[2];
    Mat4 m = {(1 - 2 * (y * y + z * z)) * sx, 2 * (x * y + z * w) * sx,       2 * (x * z - y * w) * sx,       0,
              2 * (x * y - z * w) * sy,       (1 - 2 * (x * x + z * z)) * sy, 2 * (y * z + x * w) * sy,       0,
              2 * (x * z + y * w) * sz,       2 * (y * z - x * w) * sz,       (1 - 2 * (x * x + y * y)) * sz, 0,
              t.empty() ? 0 : t[0],           t.empty() ? 0 : t[1],           t.empty() ? 0 : t[2],           1};
    return m;
}

// The KHR_texture_transform of the base colour texture of `p`'s material,
// as u' = m[0] u + m[1] v + m[2], v' = m[3] u + m[4] v + m[5] in glTF's UV
// space; the identity without one. gltfpack quantizes UVs by default and
// undoes it here: read without it, the whole texture fell on one texel.
std::array<double, 6> uv_transform(const tinygltf::Model &model, const tinygltf::Primitive &p)
{
    std::array<double, 6> m = {1, 0, 0, 0, 1, 0};
    if (p.material < 0 || size_t(p.material) >= model.materials.size())
        return m;
    const tinygltf::TextureInfo &info = model.materials[size_t(p.material)].pbrMetallicRoughness.baseColorTexture;
    const auto it = info.extensions.find("KHR_texture_transform");
    if (it == info.extensions.end() || !it->second.IsObject())
        return m;
    // A transform of another UV set than the one read leaves this one be.
    const tinygltf::Value &set = it->second.Get("texCoord");
    if ((set.IsNumber() ? set.GetNumberAsDouble() : double(info.texCoord)) != 0)
        return m;
    auto number = [&](const char *key, int i, double fallback) {
        const tinygltf::Value &v = it->second.Get(key);
        const tinygltf::Value &x = i < 0 ? v : v.IsArray() && v.ArrayLen() == 2 ? v.Get(i) : tinygltf::Value();
        return x.IsNumber() && std::isfinite(x.GetNumberAsDouble()) ? x.GetNumberAsDouble() : fallback;
    };
    const double ox = number("offset", 0, 0), oy = number("offset", 1, 0), r = number("rotation", -1, 0);
    const double sx = number("scale", 0, 1), sy = number("scale", 1, 1), c = std::cos(r), s = std::sin(r);
    // The extension's matrix, offset x rotation x scale, its rotation a
    // column-major mat3(cos, sin, 0, -sin, cos, 0, 0, 0, 1).
    m = {c * sx, -s * sy, ox, s * sx, c * sy, oy};
    return m;
}

// A primitive's geometry from its KHR_draco_mesh_compression object `ext`:
// its triangles' corners into `idx`, and of POSITION, NORMAL, TEXCOORD_0
// and COLOR_0 (`color_count` components), those the primitive has, from
// the Draco data where the extension numbers them (as the primitive's
// accessors say they are stored), as usual from their accessors where it
// does not.
template <class Attribute>
void read_draco(const Reader &r, const tinygltf::Value &ext, Attribute attribute, std::vector<float> &pos,
                std::vector<float> &nrm, std::vector<float> &uv, std::vector<float> &col, int color_count,
                std::vector<uint32_t> &idx, const std::string &where)
{
    const tinygltf::Model &m = r.model;
    const std::string at = where + " (KHR_draco_mesh_compression)";
    const tinygltf::Value &view_value = ext.Get("bufferView"), &ids = ext.Get("attributes");
    if (!view_value.IsInt() || !ids.IsObject())
        fail(at + ": no bufferView or attributes");
    const int view = view_value.Get<int>();
    if (view < 0 || size_t(view) >= m.bufferViews.size())
        fail(at + ": buffer view " + std::to_string(view) + " does not exist");
    const tinygltf::BufferView &v = m.bufferViews[size_t(view)];
    if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
        fail(at + ": buffer " + std::to_string(v.buffer) + " does not exist");
    const std::vector<unsigned char> &data = m.buffers[size_t(v.buffer)].data;
    if (v.byteLength > data.size() || v.byteOffset > data.size() - v.byteLength)
        fail(at + ": buffer view " + std::to_string(view) + " (" + std::to_string(v.byteLength) + " bytes at " +
             std::to_string(v.byteOffset) + ") does not fit its " + std::to_string(data.size()) + "-byte buffer");
    // An attribute to take from the Draco data.
    struct Compressed {
        std::vector<float> *into;
        const tinygltf::Accessor *accessor;
        std::string where;
    };
    static const char *const names[] = {"POSITION", "NORMAL", "TEXCOORD_0", "COLOR_0"};
    const int components[] = {3, 3, 2, color_count};
    std::vector<float> *const into[] = {&pos, &nrm, &uv, &col};
    std::vector<SamDracoWant> want;
    std::vector<Compressed> compressed;
    for (int k = 0; k < 4; ++k) {
        if (attribute(names[k]) < 0)
            continue;
        if (!ids.Has(names[k])) {
            *into[k] = read_floats(r, attribute(names[k]), components[k], names[k]);
            continue;
        }
        if (!ids.Get(names[k]).IsInt())
            fail(at + ": the Draco attribute number of " + names[k] + " is not an integer");
        Compressed c{into[k], nullptr, ""};
        c.accessor = &accessor(r, attribute(names[k]), components[k], names[k], c.where);
        compressed.push_back(c);
        want.push_back({names[k], ids.Get(names[k]).Get<int>(), c.accessor->componentType, components[k]});
    }
    SamDracoMesh mesh;
    std::string message;
    if (!sam_mesh_gltf_draco_decode(data.data() + v.byteOffset, v.byteLength, want, mesh, message))
        fail(at + ", buffer view " + std::to_string(view) + ": " + message);
    for (size_t w = 0; w < want.size(); ++w) {
        const Compressed &c = compressed[w];
        if (c.accessor->count != mesh.points)
            fail(at + ": " + c.where + " has " + std::to_string(c.accessor->count) +
                 " elements, the Draco data of buffer view " + std::to_string(view) + " " +
                 std::to_string(mesh.points) + " points");
        const int size = tinygltf::GetComponentSizeInBytes(uint32_t(want[w].component_type));
        *c.into = to_floats(mesh.attributes[w].data(), mesh.points, uint64_t(size) * uint64_t(want[w].components),
                            want[w].component_type, c.accessor->normalized, want[w].components, c.where);
    }
    idx = std::move(mesh.corners);
    // Attributes read as usual index the same points.
    if (pos.size() / 3 != mesh.points)
        fail(at + ": POSITION has " + std::to_string(pos.size() / 3) + " elements, the Draco data " +
             std::to_string(mesh.points) + " points");
}

// One primitive's triangles into the soup, transformed by `world`.
void add_primitive(Reader &r, const tinygltf::Primitive &p, const Mat4 &world, const std::string &where)
{
    if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        p.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        r.skipped_primitives++;
        return;
    }
    auto attribute = [&](const char *name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    if (attribute("POSITION") < 0)
        fail(where + ": no POSITION attribute");
    std::vector<float> pos, nrm, uv, col;
    std::vector<uint32_t> idx;
    const int color_count = color_components(r, attribute("COLOR_0"));
    const auto draco = p.extensions.find("KHR_draco_mesh_compression");
    if (draco != p.extensions.end()) {
        if (p.mode != TINYGLTF_MODE_TRIANGLES)
            fail(where + ": Draco-compressed triangles in mode " + std::to_string(p.mode) +
                 " (only 4, a list, is read)");
        read_draco(r, draco->second, attribute, pos, nrm, uv, col, color_count, idx, where);
    } else {
        pos = read_floats(r, attribute("POSITION"), 3, "POSITION");
        if (attribute("NORMAL") >= 0)
            nrm = read_floats(r, attribute("NORMAL"), 3, "NORMAL");
        if (attribute("TEXCOORD_0") >= 0)
            uv = read_floats(r, attribute("TEXCOORD_0"), 2, "TEXCOORD_0");
        if (color_count)
            col = read_floats(r, attribute("COLOR_0"), color_count, "COLOR_0");
    }
    const size_t n = pos.size() / 3, base = r.positions.size() / 3;
    if (base + n > UINT32_MAX / 4)
        fail(where + ": more vertices than 32-bit indices reach");
    if ((!nrm.empty() && nrm.size() != pos.size()) || (!uv.empty() && uv.size() / 2 != n) ||
        (color_count && col.size() / size_t(color_count) != n))
        fail(where + ": NORMAL, TEXCOORD_0 or COLOR_0 has another count than POSITION's " + std::to_string(n));
    // A primitive without COLOR_0 is white, as glTF says; its colours
    // are linear, and alpha is no colour.
    if (color_count && !r.any_colors) {
        r.colors.assign(r.positions.size(), 1.0f);
        r.any_colors = true;
    }
    for (size_t v = 0; r.any_colors && v < n; ++v)
        for (int k = 0; k < 3; ++k)
            r.colors.push_back(color_count ? std::fmin(std::fmax(col[size_t(color_count) * v + size_t(k)], 0.0f), 1.0f)
                                           : 1.0f);
    r.all_normals = r.all_normals && !nrm.empty();
    r.all_uvs = r.all_uvs && !uv.empty();
    // Normals go through the inverse transpose of the upper 3 x 3.
    const Mat4 &M = world;
    const double a = M[0], b = M[4], c = M[8], d = M[1], e = M[5], f = M[9], g = M[2], h = M[6], i = M[10];
    const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    const double inv_t[9] = {(e * i - f * h), -(d * i - f * g), (d * h - e * g), -(b * i - c * h), (a * i - c * g),
                             -(a * h - b * g), (b * f - c * e), -(a * f - c * d), (a * e - b * d)};
    const std::array<double, 6> t = uv_transform(r.model, p);
    for (size_t v = 0; v < n; ++v) {
        const double x = pos[3 * v], y = pos[3 * v + 1], z = pos[3 * v + 2];
        for (int k = 0; k < 3; ++k)
            r.positions.push_back(float(M[size_t(k)] * x + M[size_t(4 + k)] * y + M[size_t(8 + k)] * z + M[size_t(12 + k)]));
        for (int k = 0; k < 3; ++k)
            r.normals.push_back(nrm.empty() ? 0.0f
                                            : float(inv_t[3 * k] * nrm[3 * v] + inv_t[3 * k + 1] * nrm[3 * v + 1] +
                                                    inv_t[3 * k + 2] * nrm[3 * v + 2]));
        // glTF's v runs down the image, the project's (OBJ's) up.
        const double u0 = uv.empty() ? 0 : uv[2 * v], v0 = uv.empty() ? 0 : uv[2 * v + 1];
        r.uvs.push_back(uv.empty() ? 0.0f : float(t[0] * u0 + t[1] * v0 + t[2]));
        r.uvs.push_back(uv.empty() ? 0.0f : float(1.0 - (t[3] * u0 + t[4] * v0 + t[5])));
    }
    if (draco == p.extensions.end())
        idx = read_indices(r, p.indices, n);
    // A mirroring transform turns the winding; the triangles are turned back.
    const bool flip = det < 0;
    auto triangle = [&](uint32_t i0, uint32_t i1, uint32_t i2) {
        r.corners.insert(r.corners.end(), {uint32_t(base) + i0, uint32_t(base) + (flip ? i2 : i1),
                                           uint32_t(base) + (flip ? i1 : i2)});
    };
    if (p.mode == TINYGLTF_MODE_TRIANGLES) {
        if (idx.size() % 3)
            fail(where + ": " + std::to_string(idx.size()) + " indices is not a whole number of triangles");
        for (size_t t = 0; t + 2 < idx.size(); t += 3)
            triangle(idx[t], idx[t + 1], idx[t + 2]);
    } else if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t t = 0; t + 2 < idx.size(); ++t)
            t % 2 ? triangle(idx[t + 1], idx[t], idx[t + 2]) : triangle(idx[t], idx[t + 1], idx[t + 2]);
    } else {
        for (size_t t = 1; t + 1 < idx.size(); ++t)
            triangle(idx[0], idx[t], idx[t + 1]);
    }
    if (r.corners.size() / 3 > UINT32_MAX / 4)
        fail(where + ": more triangles than 32-bit indices reach");
    r.face_materials.resize(r.corners.size() / 3, p.material >= 0 ? uint32_t(p.material) : SAM_MESH_NO_MATERIAL);
    r.any_material = r.any_material || p.material >= 0;
}

void add_node(Reader &r, int index, const Mat4 &parent, int depth)
{
    const tinygltf::Model &m = r.model;
    if (index < 0 || size_t(index) >= m.nodes.size())
        fail(name_of("node", index) + " does not exist (" + std::to_string(m.nodes.size()) + " nodes)");
    // A tree can be no deeper than it has nodes: deeper is a cycle.
    if (size_t(depth) > m.nodes.size())
        fail(name_of("node", index) + ": the node hierarchy has a cycle");
    const tinygltf::Node &n = m.nodes[size_t(index)];
    const Mat4 world = multiply(parent, local_transform(n, index));
    if (n.mesh >= 0) {
        if (size_t(n.mesh) >= m.meshes.size())
            fail(name_of("node", index) + ": mesh " + std::to_string(n.mesh) + " does not exist");
        const tinygltf::Mesh &mesh = m.meshes[size_t(n.mesh)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p)
            add_primitive(r, mesh.primitives[p], world,
                          name_of("mesh", n.mesh) + " primitive " + std::to_string(p));
    }
    for (int child : n.children)
        add_node(r, child, world, depth + 1);
}

// An image loader that decodes nothing: geometry loads whatever format its
// textures are in (KTX2, WebP...), which TinyGLTF's own loader would refuse
// the whole file for.
bool skip_image(tinygltf::Image *, const int, std::string *, std::string *, int, int, const unsigned char *, int,
                void *)
{
    return true;
}

// TinyGLTF's own image loader, for images whose buffer view fits its
// buffer: TinyGLTF 2.7 hands stb_image a view's bytes without checking
// that they lie in the buffer, and read past it (found by fuzz/fuzz_mesh).
// `model` is the model being read, whose buffers and views come first.
bool checked_image(tinygltf::Image *image, const int index, std::string *err, std::string *warn, int width, int height,
                   const unsigned char *bytes, int size, void *model)
{
    const tinygltf::Model &m = *static_cast<const tinygltf::Model *>(model);
    if (image->bufferView >= 0) {
        // TinyGLTF found the view and its buffer before calling.
        const tinygltf::BufferView &v = m.bufferViews[size_t(image->bufferView)];
        const size_t have = m.buffers[size_t(v.buffer)].data.size();
        if (v.byteOffset > have || v.byteLength > have - v.byteOffset) {
            if (err)
                *err += "image " + std::to_string(index) + ": buffer view " + std::to_string(image->bufferView) +
                        " (" + std::to_string(v.byteLength) + " bytes at " + std::to_string(v.byteOffset) +
                        ") runs past its " + std::to_string(have) + "-byte buffer";
            return false;
        }
    }
    return tinygltf::LoadImageData(image, index, err, warn, width, height, bytes, size, nullptr);
}

// Every file TinyGLTF reads (the .gltf or .glb, its buffers and images)
// goes through sam_read_file, which reads regular files only: TinyGLTF's own
// reader opened a buffer URI that named a directory and sized its buffer
// from the failed tellg (found by fuzz/fuzz_mesh).
bool read_whole_file(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *)
{
    uint8_t *data;
    size_t size;
    sam_error e;
    if (sam_read_file(path.c_str(), &data, &size, &e) != SAM_OK) {
        if (err)
            *err += e.message;
        return false;
    }
    out->assign(data, data + size);
    std::free(data);
    return true;
}

// The JSON parser's message quotes what it last read, which in a .gltf cut
// inside an embedded buffer is a kilobyte of base64: its first 40
// characters and "..." say as much.
std::string short_last_read(std::string message)
{
    const std::string mark = "last read: '";
    const size_t from = message.find(mark);
    if (from == std::string::npos)
        return message;
    const size_t start = from + mark.size(), end = message.find('\'', start);
    const size_t length = (end == std::string::npos ? message.size() : end) - start;
    if (length > 48)
        message.replace(start + 40, length - 40, "...");
    return message;
}

// A glTF file's bytes, read once, and what its geometry needs before
// TinyGLTF reads them.
struct Source {
    std::vector<unsigned char> bytes;
    bool meshopt = false;  // decoded first (EXT_meshopt_compression)
    bool draco = false;    // its primitives' index accessors dropped (KHR_draco_mesh_compression)
    std::string undecoded; // the compressions it requires that this reader does not decode, named
};

// Reads `path` into `s` and names its compressions from its JSON (a .gltf
// whole, of a .glb its JSON chunk). False with `message` when the file
// cannot be read. TinyGLTF refused a meshopt-compressed file with a message
// about buffer sizes, which told a user nothing.
bool read_source(const char *path, Source &s, std::string &message)
{
    std::string err;
    if (!read_whole_file(&s.bytes, &err, path, nullptr)) {
        message = sam_mesh_one_line(err);
        return false;
    }
    const char *json = reinterpret_cast<const char *>(s.bytes.data());
    size_t length = s.bytes.size();
    if (sam_path_has_extension(path, ".glb")) {
        // Header (magic, version, length), then the JSON chunk's length and type.
        length = s.bytes.size() < 20 ? 0 : std::min(size_t(sam_glb_u32(s.bytes.data() + 12)), s.bytes.size() - 20);
        json += 20 * (length > 0);
    }
    std::unique_ptr<cJSON, decltype(&cJSON_Delete)> root(cJSON_ParseWithLength(json, length), cJSON_Delete);
    const cJSON *name;
    cJSON_ArrayForEach(name, cJSON_GetObjectItemCaseSensitive(root.get(), "extensionsRequired"))
    {
        if (!cJSON_IsString(name))
            continue;
        if (!std::strcmp(name->valuestring, "EXT_meshopt_compression"))
            s.meshopt = true;
        else if (!std::strcmp(name->valuestring, "KHR_meshopt_compression"))
            s.undecoded += (s.undecoded.empty() ? "" : ", ") + std::string(name->valuestring);
    }
    // Draco data beside uncompressed geometry is decoded too (its index
    // accessors have buffer views, but need none); a file that names it
    // required but not used is looked at all the same.
    for (const char *list : {"extensionsUsed", "extensionsRequired"})
        cJSON_ArrayForEach(name, cJSON_GetObjectItemCaseSensitive(root.get(), list))
            s.draco |= cJSON_IsString(name) && !std::strcmp(name->valuestring, "KHR_draco_mesh_compression");
    return true;
}

// Parses the file read into `s` (its bytes are used up); with `images` its
// pictures are decoded too (for the base colour). A GLB's chunks are
// checked first (sam_glb_check); a compressed file is then made readable
// (sam_mesh_gltf_meshopt.h, sam_mesh_gltf_draco.h), as a GLB whose chunks
// are whole. Its buffers and images are found beside `path`.
bool load(const char *path, bool images, Source &s, tinygltf::Model &model, std::string &message)
{
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &read_whole_file,
                           &tinygltf::WriteWholeFile, nullptr});
    if (images)
        loader.SetImageLoader(checked_image, &model);
    else
        loader.SetImageLoader(skip_image, nullptr);
    std::vector<unsigned char> &file = s.bytes;
    // The file's own chunks, before any rewrite keeps them, so the
    // message gives the file's numbers.
    if (sam_glb_is(file.data(), file.size())) {
        message = sam_glb_check(file.data(), file.size());
        if (!message.empty())
            return false;
    }
    if (s.meshopt) {
        std::vector<unsigned char> glb;
        if (!sam_mesh_gltf_meshopt_decode(path, file.data(), file.size(), glb, message)) {
            message = "its meshopt-compressed geometry (EXT_meshopt_compression): " + message;
            return false;
        }
        file.swap(glb);
    }
    if (s.draco && !sam_mesh_gltf_draco_unindex(file, message)) {
        message = "its Draco-compressed geometry (KHR_draco_mesh_compression): " + message;
        return false;
    }
    // A .glb goes to the binary reader whatever it holds (which names a
    // wrong magic); decoded data is a GLB when it begins as one.
    const bool glb = s.meshopt || s.draco ? sam_glb_is(file.data(), file.size()) : sam_path_has_extension(path, ".glb");
    const char *slash = std::strrchr(path, '/');
    const std::string dir = slash ? std::string(path, size_t(slash - path)) : ".";
    std::string err, warn;
    const bool ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, file.data(), unsigned(file.size()), dir)
                        : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char *>(file.data()),
                                                     unsigned(file.size()), dir);
    message = short_last_read(sam_mesh_one_line(err.empty() ? warn : err));
    return ok;
}

sam_status read_soup(const char *path, sam_mesh_soup *soup, sam_error *err)
{
    Source source;
    tinygltf::Model model;
    std::string message;
    const bool read = read_source(path, source, message);
    if (read && !source.undecoded.empty())
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "%s: its geometry is compressed (%s, required), which this reader does not decode; export "
                        "it without it (EXT_meshopt_compression, gltfpack's -c and -cc, and Draco are decoded)",
                        path, source.undecoded.c_str());
    if (!read || !load(path, false, source, model, message))
        return sam_fail(err, SAM_ERR_FORMAT, "%s: not a readable glTF file: %s", path,
                        message.empty() ? "TinyGLTF gave no reason" : message.c_str());
    Reader r{model, path, {}, {}, {}, {}, {}, {}};
    try {
        const Mat4 identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        if (!model.scenes.empty()) {
            const int s = model.defaultScene >= 0 ? model.defaultScene : 0;
            if (size_t(s) >= model.scenes.size())
                fail("the default scene " + std::to_string(s) + " does not exist");
            for (int node : model.scenes[size_t(s)].nodes)
                add_node(r, node, identity, 0);
        } else {
            // No scene: every mesh once, as it stands.
            for (size_t m = 0; m < model.meshes.size(); ++m)
                for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p)
                    add_primitive(r, model.meshes[m].primitives[p], identity,
                                  name_of("mesh", int(m)) + " primitive " + std::to_string(p));
        }
    } catch (const Problem &p) {
        return sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, p.what.c_str());
    }
    if (r.corners.empty())
        return sam_fail(err, SAM_ERR_EMPTY, "%s: the default scene has no triangles%s", path,
                        r.skipped_primitives ? " (only points or lines)" : "");
    const uint32_t faces = uint32_t(r.corners.size() / 3);
    std::vector<uint32_t> offsets(size_t(faces) + 1);
    for (uint32_t f = 0; f <= faces; ++f)
        offsets[f] = 3 * f;
    soup->vertex_count = uint32_t(r.positions.size() / 3);
    soup->face_count = faces;
    soup->corner_count = uint32_t(r.corners.size());
    soup->positions = sam_mesh_copy_out(r.positions);
    soup->normals = r.all_normals ? sam_mesh_copy_out(r.normals) : nullptr;
    soup->uvs = r.all_uvs ? sam_mesh_copy_out(r.uvs) : nullptr;
    soup->colors = r.any_colors ? sam_mesh_copy_out(r.colors) : nullptr;
    soup->face_materials = r.any_material ? sam_mesh_copy_out(r.face_materials) : nullptr;
    soup->face_offsets = sam_mesh_copy_out(offsets);
    soup->corners = sam_mesh_copy_out(r.corners);
    return SAM_OK;
}

// The image that base-colour texture `info` reads; -1 for none.
int base_color_source(const tinygltf::Model &model, const tinygltf::TextureInfo &info)
{
    const int t = info.index;
    if (t < 0 || size_t(t) >= model.textures.size())
        return -1;
    const int source = model.textures[size_t(t)].source;
    return source >= 0 && size_t(source) < model.images.size() ? source : -1;
}

// The materials the meshes' primitives use, each once, in first-use order.
std::vector<size_t> used_materials(const tinygltf::Model &model)
{
    std::vector<size_t> used;
    std::vector<bool> listed(model.materials.size());
    for (const tinygltf::Mesh &mesh : model.meshes)
        for (const tinygltf::Primitive &p : mesh.primitives)
            if (p.material >= 0 && size_t(p.material) < listed.size() && !listed[size_t(p.material)]) {
                listed[size_t(p.material)] = true;
                used.push_back(size_t(p.material));
            }
    return used;
}

// How many images other than `source` the base colours of the `used`
// materials read.
uint32_t other_base_colors(const tinygltf::Model &model, const std::vector<size_t> &used, int source)
{
    std::vector<bool> counted(model.images.size());
    uint32_t others = 0;
    for (size_t m : used) {
        const int s = base_color_source(model, model.materials[m].pbrMetallicRoughness.baseColorTexture);
        if (s >= 0 && s != source && !counted[size_t(s)]) {
            counted[size_t(s)] = true;
            ++others;
        }
    }
    return others;
}

// Image `source` of `model` as a linear sam_image.
sam_status image_of(const char *path, const tinygltf::Model &model, int source, sam_image *image, sam_error *err)
{
    // TinyGLTF gives every 8- or 16-bit image as RGBA (its default of
    // not keeping an image's own channels).
    const tinygltf::Image &img = model.images[size_t(source)];
    const size_t pixels = img.width > 0 && img.height > 0 ? size_t(img.width) * size_t(img.height) : 0;
    const size_t bytes = size_t(img.bits / 8), channels = size_t(img.component);
    if ((img.bits != 8 && img.bits != 16) || (channels != 3 && channels != 4) || !pixels ||
        img.image.size() != pixels * channels * bytes)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "%s: base-colour image %d is %d x %d with %d channels of %d bits (8 or 16 bits of RGB or "
                        "RGBA expected)",
                        path, source, img.width, img.height, img.component, img.bits);
    // 16 bits cut to their high byte: an albedo needs no more.
    std::vector<uint8_t> narrow;
    if (bytes == 2) {
        narrow.resize(pixels * channels);
        for (size_t i = 0; i < narrow.size(); ++i) {
            uint16_t wide;
            std::memcpy(&wide, img.image.data() + 2 * i, 2);
            narrow[i] = uint8_t(wide >> 8);
        }
    }
    return sam_image_from_bytes(image, bytes == 2 ? narrow.data() : img.image.data(), uint32_t(img.width),
                                uint32_t(img.height), uint32_t(channels), SAM_PNG_SRGB, err);
}

// The file with its images decoded, for its base colours.
sam_status load_with_images(const char *path, tinygltf::Model &model, sam_error *err)
{
    Source source;
    std::string message;
    if (!read_source(path, source, message) || !load(path, true, source, model, message))
        return sam_fail(err, SAM_ERR_FORMAT, "%s: its textures cannot be read: %s", path,
                        message.empty() ? "TinyGLTF gave no reason" : message.c_str());
    return SAM_OK;
}

// The base colour of every material: its texture times its factor, or
// 1 x 1 of its factor without a texture; an image that cannot be used
// leaves its material's empty and says why in `note`.
sam_status read_base_colors(const char *path, std::vector<sam_image> &images, std::string &note, sam_error *err)
{
    tinygltf::Model model;
    sam_status st = load_with_images(path, model, err);
    if (st != SAM_OK)
        return st;
    images.assign(model.materials.size(), sam_image{});
    for (size_t m = 0; m < model.materials.size(); ++m) {
        const tinygltf::PbrMetallicRoughness &pbr = model.materials[m].pbrMetallicRoughness;
        float factor[3];
        for (int c = 0; c < 3; ++c)
            factor[c] = pbr.baseColorFactor.size() == 4 ? float(pbr.baseColorFactor[size_t(c)]) : 1.0f;
        const int s = base_color_source(model, pbr.baseColorTexture);
        sam_error why;
        st = s >= 0 ? image_of(path, model, s, &images[m], &why) : sam_image_create(&images[m], 1, 1, 3, &why);
        if (st == SAM_ERR_OUT_OF_MEMORY)
            return sam_fail(err, st, "%s", why.message);
        if (st != SAM_OK) {
            if (note.empty())
                note = why.message;
            continue;
        }
        sam_image &im = images[m];
        const size_t texels = size_t(im.width) * im.height;
        for (size_t i = 0; i < texels; ++i)
            for (uint32_t c = 0; c < 3; ++c)
                im.pixels[i * im.channels + c] = (s >= 0 ? im.pixels[i * im.channels + c] : 1.0f) * factor[c];
    }
    return SAM_OK;
}

// The base-colour texture of the first material the meshes' primitives
// use that has one (of any material when none does).
sam_status read_base_color(const char *path, sam_image *image, float factor[4], uint32_t *others, sam_error *err)
{
    tinygltf::Model model;
    sam_status st = load_with_images(path, model, err);
    if (st != SAM_OK)
        return st;
    // Materials in the order the primitives first use them, then the rest.
    const std::vector<size_t> used = used_materials(model);
    std::vector<size_t> order = used;
    std::vector<bool> listed(model.materials.size());
    for (size_t m : used)
        listed[m] = true;
    for (size_t m = 0; m < listed.size(); ++m)
        if (!listed[m])
            order.push_back(m);
    for (size_t m : order) {
        const tinygltf::PbrMetallicRoughness &pbr = model.materials[m].pbrMetallicRoughness;
        const int source = base_color_source(model, pbr.baseColorTexture);
        if (source < 0)
            continue;
        for (int c = 0; c < 4; ++c)
            factor[c] = pbr.baseColorFactor.size() == 4 ? float(pbr.baseColorFactor[size_t(c)]) : 1.0f;
        *others = other_base_colors(model, used, source);
        return image_of(path, model, source, image, err);
    }
    return SAM_OK;
}

} // namespace

extern "C" sam_status sam_mesh_gltf_read(const char *path, sam_mesh_soup *soup, sam_error *err)
{
    std::memset(soup, 0, sizeof *soup);
    sam_status st = sam_mesh_guarded(path, "TinyGLTF", err, [&] { return read_soup(path, soup, err); });
    if (st != SAM_OK)
        sam_mesh_soup_free(soup);
    return st;
}

extern "C" sam_status sam_mesh_gltf_base_colors(const char *path, sam_image **images, uint32_t *count, char *note,
                                                size_t note_size, sam_error *err)
{
    if (!path || !images || !count || !note || !note_size)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "glTF base colours: NULL argument");
    *images = nullptr;
    *count = 0;
    note[0] = '\0';
    std::vector<sam_image> all;
    std::string why;
    sam_status st = sam_mesh_guarded(path, "TinyGLTF", err, [&] { return read_base_colors(path, all, why, err); });
    if (st == SAM_OK && !all.empty()) {
        *images = static_cast<sam_image *>(std::calloc(all.size(), sizeof **images));
        if (!*images)
            st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %zu materials", path, all.size());
    }
    if (st != SAM_OK) {
        for (sam_image &im : all)
            sam_image_destroy(&im);
        return st;
    }
    std::copy(all.begin(), all.end(), *images);
    *count = uint32_t(all.size());
    std::snprintf(note, note_size, "%s", why.c_str());
    return SAM_OK;
}

extern "C" sam_status sam_mesh_gltf_base_color(const char *path, sam_image *image, float factor[4], uint32_t *others,
                                               sam_error *err)
{
    if (!path || !image || !factor || !others)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "glTF base colour: NULL argument");
    std::memset(image, 0, sizeof *image);
    for (int c = 0; c < 4; ++c)
        factor[c] = 1.0f;
    *others = 0;
    return sam_mesh_guarded(path, "TinyGLTF", err, [&] { return read_base_color(path, image, factor, others, err); });
}
