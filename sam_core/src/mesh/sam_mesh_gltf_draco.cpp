// KHR_draco_mesh_compression decoded with the Draco library
// (sam_mesh_gltf_draco.h). Every index and byte range the decoded mesh
// gives is checked before it is read: the bytes come from the file.
#include "sam_mesh_gltf_draco.h"

#include "sam_mesh_gltf_glb.h"

#include <cjson/cJSON.h>
#include <draco/compression/decode.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <memory>

namespace {

const char *draco_type_name(draco::DataType t)
{
    static const char *const names[] = {"no type", "int8",   "uint8",   "int16",   "uint16", "int32",
                                        "uint32",  "int64",  "uint64",  "float32", "float64", "bool"};
    return unsigned(t) < sizeof names / sizeof *names ? names[t] : "an unknown type";
}

// The Draco type that holds glTF component type `t`; DT_INVALID for none.
draco::DataType draco_type(int t)
{
    switch (t) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
        return draco::DT_INT8;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return draco::DT_UINT8;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
        return draco::DT_INT16;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return draco::DT_UINT16;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return draco::DT_UINT32;
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return draco::DT_FLOAT32;
    default:
        return draco::DT_INVALID;
    }
}

bool attribute_bytes(const draco::Mesh &mesh, const SamDracoWant &want, std::vector<uint8_t> &out,
                     std::string &message)
{
    const std::string name = std::string(want.name) + " (Draco attribute " + std::to_string(want.id) + ")";
    if (want.id < 0) {
        message = name + " does not exist";
        return false;
    }
    const draco::PointAttribute *a = mesh.GetAttributeByUniqueId(uint32_t(want.id));
    if (!a) {
        message = name + " is not in the compressed data";
        return false;
    }
    const draco::DataType type = draco_type(want.component_type);
    if (a->num_components() != want.components || a->data_type() != type || type == draco::DT_INVALID) {
        message = name + " holds " + std::to_string(a->num_components()) + " components of " +
                  draco_type_name(a->data_type()) + ", its accessor " + std::to_string(want.components) +
                  " of component type " + std::to_string(want.component_type) +
                  (type == draco::DT_INVALID ? "" : std::string(" (") + draco_type_name(type) + ")");
        return false;
    }
    const draco::DataBuffer *buffer = a->buffer();
    const size_t element = size_t(draco::DataTypeLength(type)) * size_t(want.components);
    const size_t points = mesh.num_points();
    if (!buffer || a->byte_stride() < int64_t(element) || a->byte_offset() < 0) {
        message = name + " has no values";
        return false;
    }
    out.resize(points * element);
    for (size_t p = 0; p < points; ++p) {
        const draco::PointIndex point{uint32_t(p)};
        if (!a->is_mapping_identity() && p >= a->indices_map_size()) {
            message = name + ": point " + std::to_string(p) + " has no value";
            return false;
        }
        const draco::AttributeValueIndex at = a->mapped_index(point);
        const int64_t from = a->GetBytePos(at);
        if (at.value() >= a->size() || from < 0 || uint64_t(from) + element > uint64_t(buffer->data_size())) {
            message = name + ": the value of point " + std::to_string(p) + " lies outside its data";
            return false;
        }
        std::memcpy(out.data() + p * element, buffer->data() + from, element);
    }
    return true;
}

} // namespace

bool sam_mesh_gltf_draco_decode(const uint8_t *data, size_t size, const std::vector<SamDracoWant> &want,
                                SamDracoMesh &out, std::string &message)
{
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char *>(data), size);
    const auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok() || type.value() != draco::TRIANGULAR_MESH) {
        message = type.ok() ? "it holds a point cloud, not triangles"
                            : "it does not decode (" + type.status().error_msg_string() + ")";
        return false;
    }
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) {
        message = "it does not decode (" + decoded.status().error_msg_string() + ")";
        return false;
    }
    const draco::Mesh &mesh = *decoded.value();
    out.points = mesh.num_points();
    out.corners.resize(size_t(mesh.num_faces()) * 3);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
        const draco::Mesh::Face &face = mesh.face(draco::FaceIndex(f));
        for (int c = 0; c < 3; ++c) {
            if (face[c].value() >= out.points) {
                message = "corner " + std::to_string(c) + " of triangle " + std::to_string(f) + " names point " +
                          std::to_string(face[c].value()) + " of " + std::to_string(out.points);
                return false;
            }
            out.corners[3 * size_t(f) + size_t(c)] = face[c].value();
        }
    }
    out.attributes.assign(want.size(), {});
    for (size_t w = 0; w < want.size(); ++w)
        if (!attribute_bytes(mesh, want[w], out.attributes[w], message))
            return false;
    return true;
}

bool sam_mesh_gltf_draco_unindex(std::vector<uint8_t> &file, std::string &message)
{
    const bool glb = sam_glb_is(file.data(), file.size());
    size_t json_at = 0, json_size = file.size();
    if (glb) {
        if (const char *why = sam_glb_json(file.data(), file.size(), &json_size)) {
            message = why;
            return false;
        }
        json_at = 20;
    }
    std::unique_ptr<cJSON, decltype(&cJSON_Delete)> root(
        cJSON_ParseWithLength(reinterpret_cast<const char *>(file.data()) + json_at, json_size), cJSON_Delete);
    if (!cJSON_IsObject(root.get())) {
        message = "its JSON is not a glTF object";
        return false;
    }
    const cJSON *accessors = cJSON_GetObjectItemCaseSensitive(root.get(), "accessors"), *mesh;
    cJSON_ArrayForEach(mesh, cJSON_GetObjectItemCaseSensitive(root.get(), "meshes"))
    {
        cJSON *primitive;
        cJSON_ArrayForEach(primitive, cJSON_GetObjectItemCaseSensitive(mesh, "primitives"))
        {
            // Only what TinyGLTF refuses goes: where the Draco data has
            // uncompressed data beside it, its indices have a view and stay.
            const cJSON *ext = cJSON_GetObjectItemCaseSensitive(primitive, "extensions");
            const cJSON *indices = cJSON_GetObjectItemCaseSensitive(primitive, "indices");
            const cJSON *index = cJSON_IsNumber(indices) ? cJSON_GetArrayItem(accessors, indices->valueint) : nullptr;
            if (cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(ext, "KHR_draco_mesh_compression")) &&
                cJSON_IsObject(index) && !cJSON_HasObjectItem(index, "bufferView"))
                cJSON_DeleteItemFromObjectCaseSensitive(primitive, "indices");
        }
    }
    std::unique_ptr<char, decltype(&cJSON_free)> text(cJSON_PrintUnformatted(root.get()), cJSON_free);
    if (!text)
        throw std::bad_alloc();
    const std::string json(text.get());
    if (!glb) {
        file.assign(json.begin(), json.end());
        return true;
    }
    // The chunks after the JSON, up to the length the header gives.
    const size_t rest = 20 + json_size, end = std::min(size_t(sam_glb_u32(file.data() + 8)), file.size());
    std::vector<uint8_t> out;
    sam_glb_start(out, sam_glb_u32(file.data() + 4), json);
    if (rest < end)
        out.insert(out.end(), file.begin() + std::ptrdiff_t(rest), file.begin() + std::ptrdiff_t(end));
    if (!sam_glb_finish(out)) {
        message = "the GLB would pass 4 GiB";
        return false;
    }
    file = std::move(out);
    return true;
}
