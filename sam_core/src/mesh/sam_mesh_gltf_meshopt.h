/*
 * Geometry that gltfpack compressed with meshopt (EXT_meshopt_compression,
 * its -c and -cc), decoded with meshoptimizer: TinyGLTF does not decode it,
 * and refused such a file over its buffer sizes.
 */
#ifndef SAM_MESH_GLTF_MESHOPT_H
#define SAM_MESH_GLTF_MESHOPT_H

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

// Writes into `glb` the glTF at `path` (its bytes at `data`, `size` bytes:
// a GLB, or a .gltf whose buffers are files beside it or data URIs) as a
// GLB with every buffer view decoded (filters undone) into one binary
// chunk and the extension gone from the file's lists, for TinyGLTF to read
// from memory (its images still found beside `path`). False with
// `message` (one phrase, naming the buffer or buffer view) when a buffer
// cannot be read, a view lies outside its buffer, its mode, stride or
// filter is none the extension allows, the views would hold more than 64
// times the file and its buffers (1 MiB more for small files; copies of
// the same bytes count each time) or it does not decode. Throws
// std::bad_alloc when out of memory (the callers guard).
bool sam_mesh_gltf_meshopt_decode(const char *path, const uint8_t *data, size_t size, std::vector<uint8_t> &glb,
                                  std::string &message);

#endif
