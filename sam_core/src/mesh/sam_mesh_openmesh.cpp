// The project's only C++: OpenMesh's file readers behind a C function.
//
// OpenMesh's readers talk to a BaseImporter. Instead of letting them build an
// OpenMesh mesh (whose add_face silently drops faces on complex edges), this
// importer records the raw polygon soup, so sam_mesh_build.c can weld, repair and
// report every change itself. No exception crosses into C.
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "sam_mesh_cpp.hpp"

namespace {

using namespace OpenMesh;
using OpenMesh::IO::BaseImporter;

class SoupImporter : public BaseImporter {
public:
    std::vector<float> positions, normals, uvs, corner_uvs;
    std::vector<uint8_t> has_normal, has_uv;
    std::vector<uint32_t> face_offsets{0}, corners;
    std::vector<uint8_t> face_has_corner_uvs;
    bool any_normal = false, any_uv = false, any_corner_uv = false;
    std::string first_problem;

    VertexHandle add_vertex(const Vec3f &p) override
    {
        positions.insert(positions.end(), {p[0], p[1], p[2]});
        normals.insert(normals.end(), {0.f, 0.f, 0.f});
        uvs.insert(uvs.end(), {0.f, 0.f});
        has_normal.push_back(0);
        has_uv.push_back(0);
        return VertexHandle(int(n_vertices() - 1));
    }
    VertexHandle add_vertex() override { return add_vertex(Vec3f(0.f, 0.f, 0.f)); }
    HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }

    FaceHandle add_face(const VHandles &indices) override
    {
        for (const VertexHandle &vh : indices) {
            if (!vh.is_valid() || size_t(vh.idx()) >= n_vertices()) {
                note("face " + std::to_string(n_faces()) + " refers to vertex " +
                     std::to_string(vh.idx()) + " but the file has " +
                     std::to_string(n_vertices()) + " vertices");
                return FaceHandle();
            }
        }
        for (const VertexHandle &vh : indices)
            corners.push_back(uint32_t(vh.idx()));
        corner_uvs.resize(corners.size() * 2, 0.f);
        face_offsets.push_back(uint32_t(corners.size()));
        face_has_corner_uvs.push_back(0);
        return FaceHandle(int(n_faces() - 1));
    }
    FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }

    void add_face_texcoords(FaceHandle fh, VertexHandle, const std::vector<Vec2f> &tc) override
    {
        // Readers call this once per texture-coordinate dimension, with an
        // empty list for the one the file lacks. A count that does not
        // match the corners (OpenMesh drops repeated corners before
        // add_face) leaves the face without corner UVs, and then the
        // mesh without UVs, rather than guessing.
        if (!fh.is_valid() || size_t(fh.idx()) >= n_faces() || tc.empty())
            return;
        uint32_t begin = face_offsets[size_t(fh.idx())], end = face_offsets[size_t(fh.idx()) + 1];
        if (tc.size() != end - begin)
            return;
        for (uint32_t k = begin; k < end; ++k) {
            corner_uvs[2 * k] = tc[k - begin][0];
            corner_uvs[2 * k + 1] = tc[k - begin][1];
        }
        face_has_corner_uvs[size_t(fh.idx())] = 1;
        any_corner_uv = true;
    }
    void add_face_texcoords(FaceHandle fh, VertexHandle vh, const std::vector<Vec3f> &tc) override
    {
        std::vector<Vec2f> tc2;
        for (const Vec3f &t : tc)
            tc2.emplace_back(t[0], t[1]);
        add_face_texcoords(fh, vh, tc2);
    }

    void set_point(VertexHandle vh, const Vec3f &p) override
    {
        if (valid(vh))
            std::memcpy(&positions[3 * size_t(vh.idx())], p.data(), 3 * sizeof(float));
    }
    void set_normal(VertexHandle vh, const Vec3f &n) override
    {
        if (!valid(vh))
            return;
        std::memcpy(&normals[3 * size_t(vh.idx())], n.data(), 3 * sizeof(float));
        has_normal[size_t(vh.idx())] = 1;
        any_normal = true;
    }
    void set_normal(VertexHandle vh, const Vec3d &n) override { set_normal(vh, Vec3f(n)); }
    void set_texcoord(VertexHandle vh, const Vec2f &t) override
    {
        if (!valid(vh))
            return;
        uvs[2 * size_t(vh.idx())] = t[0];
        uvs[2 * size_t(vh.idx()) + 1] = t[1];
        has_uv[size_t(vh.idx())] = 1;
        any_uv = true;
    }
    void set_texcoord(VertexHandle vh, const Vec3f &t) override { set_texcoord(vh, Vec2f(t[0], t[1])); }

    // Attributes the project does not use.
    void set_face_texindex(FaceHandle, int) override {}
    void set_halfedge(VertexHandle, HalfedgeHandle) override {}
    void set_color(VertexHandle, const Vec3uc &) override {}
    void set_color(VertexHandle, const Vec4uc &) override {}
    void set_color(VertexHandle, const Vec3f &) override {}
    void set_color(VertexHandle, const Vec4f &) override {}
    void set_status(VertexHandle, const Attributes::StatusInfo &) override {}
    void set_next(HalfedgeHandle, HalfedgeHandle) override {}
    void set_face(HalfedgeHandle, FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HalfedgeHandle, const Vec2f &) override {}
    void set_texcoord(HalfedgeHandle, const Vec3f &) override {}
    void set_status(HalfedgeHandle, const Attributes::StatusInfo &) override {}
    void set_color(EdgeHandle, const Vec3uc &) override {}
    void set_color(EdgeHandle, const Vec4uc &) override {}
    void set_color(EdgeHandle, const Vec3f &) override {}
    void set_color(EdgeHandle, const Vec4f &) override {}
    void set_status(EdgeHandle, const Attributes::StatusInfo &) override {}
    void set_normal(FaceHandle, const Vec3f &) override {}
    void set_normal(FaceHandle, const Vec3d &) override {}
    void set_color(FaceHandle, const Vec3uc &) override {}
    void set_color(FaceHandle, const Vec4uc &) override {}
    void set_color(FaceHandle, const Vec3f &) override {}
    void set_color(FaceHandle, const Vec4f &) override {}
    void set_status(FaceHandle, const Attributes::StatusInfo &) override {}
    void add_texture_information(int, std::string) override {}

    size_t n_vertices() const override { return positions.size() / 3; }
    size_t n_faces() const override { return face_offsets.size() - 1; }
    size_t n_edges() const override { return 0; }

private:
    bool valid(VertexHandle vh) const { return vh.is_valid() && size_t(vh.idx()) < n_vertices(); }
    void note(const std::string &s)
    {
        if (first_problem.empty())
            first_problem = s;
    }
};

// Captures OpenMesh's diagnostics for the duration of one read, so they end
// up in our error message instead of on stderr. OpenMesh's omerr() is a
// process-wide multiplexer feeding std::cerr; reconnecting its targets leaks
// (its disconnect never frees the target), so instead std::cerr's buffer is
// swapped for a string buffer and restored afterwards. Both are process-wide:
// reads take openmesh_read_lock, and a host must not write to std::cerr
// from another thread during a read (sam_mesh.h).
class DiagnosticCapture {
public:
    DiagnosticCapture()
    {
        saved_ = std::cerr.rdbuf(captured_.rdbuf());
        log_was_enabled_ = omlog().is_enabled();
        out_was_enabled_ = omout().is_enabled();
        omlog().disable();
        omout().disable();
    }
    ~DiagnosticCapture()
    {
        omerr().flush();
        std::cerr.rdbuf(saved_);
        if (log_was_enabled_)
            omlog().enable();
        if (out_was_enabled_)
            omout().enable();
    }
    std::string text()
    {
        omerr().flush();
        return sam_mesh_one_line(captured_.str());
    }

private:
    std::ostringstream captured_;
    std::streambuf *saved_;
    bool log_was_enabled_, out_was_enabled_;
};

// One OpenMesh read at a time in the process: its readers are singletons
// of its IOManager that keep the state of the read under way (the OFF
// reader's layout, the OBJ reader's material path), and the capture above
// swaps std::cerr's buffer. The one global here, for libraries' globals.
std::mutex &openmesh_read_lock()
{
    static std::mutex lock;
    return lock;
}

// A file written again by the preflight, held in a private temporary file
// for as long as OpenMesh reads it. Not a stream: OpenMesh's OFF reader
// learns a file's layout (normals, colours, texture coordinates) only when
// it opens it by name, and read from a stream it kept the layout of the OFF
// file read before.
class TemporaryMesh {
public:
    ~TemporaryMesh()
    {
        if (!path_.empty())
            std::remove(path_.c_str());
    }

    // Writes `text` to a file named with `extension` (4 characters: ".off",
    // ".ply", ".obj");
    // SAM_OK with path() naming the file.
    sam_status write(const char *source, const char *text, size_t size, const char *extension, sam_error *err)
    {
        const char *dir = std::getenv("TMPDIR");
        if (!dir || !*dir)
            dir = "/tmp";
        std::string name = std::string(dir) + "/sam_mesh_XXXXXX" + extension;
        std::vector<char> buf(name.begin(), name.end());
        buf.push_back('\0');
        int fd = mkstemps(buf.data(), 4);
        if (fd < 0)
            return sam_fail(err, SAM_ERR_IO, "%s: cannot create a temporary file in %s to read it from: %s", source,
                            dir, std::strerror(errno));
        path_ = buf.data();
        FILE *fp = fdopen(fd, "wb");
        if (!fp) {
            close(fd);
            return sam_fail(err, SAM_ERR_IO, "%s: cannot write the temporary file %s: %s", source, path_.c_str(),
                            std::strerror(errno));
        }
        bool ok = std::fwrite(text, 1, size, fp) == size;
        ok = std::fclose(fp) == 0 && ok;
        if (!ok)
            return sam_fail(err, SAM_ERR_IO, "%s: cannot write the temporary file %s (%zu bytes): %s", source,
                            path_.c_str(), size, std::strerror(errno));
        return SAM_OK;
    }

    const std::string &path() const { return path_; }

private:
    std::string path_;
};

sam_status read_soup(const char *path, const char *text, size_t text_size, const char *extension, sam_mesh_soup *soup,
                     sam_error *err)
{
    static const char *const extensions[] = {".obj", ".ply", ".off", ".stl"};
    bool known = false;
    for (const char *ext : extensions)
        known = known || sam_path_has_extension(path, ext);
    if (!known)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "%s: unsupported mesh format (expected .obj, .ply, .off or .stl)", path);
    FILE *probe = std::fopen(path, "rb");
    if (!probe)
        return sam_fail(err, SAM_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
    int first = std::fgetc(probe);
    std::fclose(probe);
    if (first == EOF)
        return sam_fail(err, SAM_ERR_EMPTY, "%s: file is empty", path);

    TemporaryMesh rewritten;
    if (text) {
        if (!extension || std::strlen(extension) != 4)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: a rewritten mesh needs its extension", path);
        sam_status st = rewritten.write(path, text, text_size, extension, err);
        if (st != SAM_OK)
            return st;
    }
    SoupImporter importer;
    IO::Options options;
    options += IO::Options::VertexNormal;
    options += IO::Options::VertexTexCoord;
    options += IO::Options::FaceTexCoord;
    bool ok;
    std::string diagnostics;
    {
        std::lock_guard<std::mutex> one_at_a_time(openmesh_read_lock());
        DiagnosticCapture capture;
        ok = IO::IOManager().read(text ? rewritten.path() : std::string(path), importer, options);
        diagnostics = capture.text();
    }
    if (!ok)
        return sam_fail(err, SAM_ERR_FORMAT, "%s: OpenMesh could not parse the file%s%s", path,
                        diagnostics.empty() ? "" : ": ", diagnostics.c_str());
    if (!importer.first_problem.empty())
        return sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, importer.first_problem.c_str());
    if (importer.n_vertices() > UINT32_MAX / 4 || importer.corners.size() > UINT32_MAX / 4)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "%s: %zu vertices and %zu face corners exceed the 32-bit index range",
                        path, importer.n_vertices(), importer.corners.size());

    // A file gives UVs either per vertex or per face corner (OBJ vt); keep
    // the finer kind, and only when every element has one.
    bool corner_uvs = importer.any_corner_uv;
    for (uint8_t f : importer.face_has_corner_uvs)
        corner_uvs = corner_uvs && f;
    bool vertex_uvs = !corner_uvs && importer.any_uv;
    for (uint8_t v : importer.has_uv)
        vertex_uvs = vertex_uvs && v;
    bool vertex_normals = importer.any_normal;
    for (uint8_t v : importer.has_normal)
        vertex_normals = vertex_normals && v;

    soup->vertex_count = uint32_t(importer.n_vertices());
    soup->face_count = uint32_t(importer.n_faces());
    soup->corner_count = uint32_t(importer.corners.size());
    soup->positions = sam_mesh_copy_out(importer.positions);
    soup->normals = vertex_normals ? sam_mesh_copy_out(importer.normals) : nullptr;
    soup->uvs = vertex_uvs ? sam_mesh_copy_out(importer.uvs) : nullptr;
    soup->face_offsets = sam_mesh_copy_out(importer.face_offsets);
    soup->corners = sam_mesh_copy_out(importer.corners);
    soup->corner_uvs = corner_uvs ? sam_mesh_copy_out(importer.corner_uvs) : nullptr;
    return SAM_OK;
}

} // namespace

extern "C" sam_status sam_mesh_soup_read(const char *path, const char *text, size_t text_size, const char *extension,
                                         sam_mesh_soup *soup, sam_error *err)
{
    if (!path || !soup)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "mesh read: NULL argument");
    std::memset(soup, 0, sizeof *soup);
    sam_status st = sam_mesh_guarded(path, "OpenMesh", err, [&] { return read_soup(path, text, text_size, extension, soup, err); });
    if (st != SAM_OK)
        sam_mesh_soup_free(soup);
    return st;
}

extern "C" void sam_mesh_soup_free(sam_mesh_soup *soup)
{
    if (!soup)
        return;
    std::free(soup->positions);
    std::free(soup->normals);
    std::free(soup->uvs);
    std::free(soup->face_offsets);
    std::free(soup->corners);
    std::free(soup->corner_uvs);
    std::free(soup->corner_normals);
    std::free(soup->colors);
    std::free(soup->face_materials);
    std::memset(soup, 0, sizeof *soup);
}
