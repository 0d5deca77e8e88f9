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

// Writes into `glb` the GLB at `data` (`size` bytes) with every buffer view
// decoded (filters undone) into one binary chunk and the extension gone
// from the file's lists, for TinyGLTF to read from memory. The views may
// read only the GLB's own binary chunk. False with `message` (one phrase,
// naming the buffer view) when the file is no such GLB, a view lies
// outside the chunk, its mode, stride or filter is none the extension
// allows, the views would hold more than 64 times the file (1 MiB more for
// small files; copies of the same bytes count each time) or it does not
// decode. Throws std::bad_alloc when out of memory (the callers guard).
bool sam_mesh_gltf_meshopt_decode(const uint8_t *data, size_t size, std::vector<uint8_t> &glb, std::string &message);

#endif
