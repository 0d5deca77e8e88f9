/*
 * Geometry compressed with Draco (KHR_draco_mesh_compression: Blender's
 * glTF exporter with compression on, draco_transcoder, gltf-transform),
 * decoded with the Draco library: TinyGLTF leaves the extension to its
 * caller.
 */
#ifndef SAM_MESH_GLTF_DRACO_H
#define SAM_MESH_GLTF_DRACO_H

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

// An attribute asked of a decoded primitive: its name (for messages), the
// extension's number for it, and the glTF component type and component
// count its accessor gives.
struct SamDracoWant {
    const char *name;
    int id;
    int component_type;
    int components;
};

// A decoded primitive: `points` vertices, the corners of its triangles
// (3 per triangle, each below `points`), and each asked attribute's
// values packed as its accessor says they are stored (points x components
// values of the component type, bytes in `attributes`, in the order asked).
struct SamDracoMesh {
    size_t points = 0;
    std::vector<uint32_t> corners;
    std::vector<std::vector<uint8_t>> attributes;
};

// Decodes the `size` bytes at `data` (a KHR_draco_mesh_compression
// buffer view) into `out`, with the attributes `want` names. False with
// `message` (one phrase) when the bytes do not decode, they hold a point
// cloud, a corner names no point, or an attribute is missing, its
// component count or stored type is not its accessor's, or a point's value
// is missing or lies outside the attribute's data. Throws
// std::bad_alloc when out of memory (the callers guard).
bool sam_mesh_gltf_draco_decode(const uint8_t *data, size_t size, const std::vector<SamDracoWant> &want,
                                SamDracoMesh &out, std::string &message);

// Rewrites `file` (a GLB, or a .gltf's JSON) for TinyGLTF 2.7, which
// refuses an index accessor without a buffer view, as Draco-compressed
// primitives have: such `indices` go (the corners come from the Draco
// data). The GLB's chunks after the JSON are kept as they are. False with
// `message` when its GLB layout or JSON cannot be read or the GLB would
// pass 4 GiB. Throws std::bad_alloc when out of memory.
bool sam_mesh_gltf_draco_unindex(std::vector<uint8_t> &file, std::string &message);

#endif
