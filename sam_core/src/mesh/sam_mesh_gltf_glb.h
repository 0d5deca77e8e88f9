/*
 * A GLB's layout, for the readers that write a glTF file again before
 * TinyGLTF reads it (sam_mesh_gltf_meshopt.cpp, sam_mesh_gltf_draco.cpp):
 * a 12-byte header (magic, version, length), then chunks of an 8-byte head
 * (length, type) and their bytes, the JSON chunk first and the binary
 * chunk after it. Chunks are found where TinyGLTF finds them: the next
 * right after the stated length of the one before.
 */
#ifndef SAM_MESH_GLTF_GLB_H
#define SAM_MESH_GLTF_GLB_H

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#define SAM_GLB_JSON 0x4E4F534Au
#define SAM_GLB_BIN 0x004E4942u

inline uint32_t sam_glb_u32(const uint8_t *p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

inline void sam_glb_put_u32(std::vector<uint8_t> &out, uint32_t v)
{
    for (int i = 0; i < 4; ++i)
        out.push_back(uint8_t(v >> (8 * i)));
}

// Starts a GLB in `out` (emptied, its capacity kept): the header of
// version `version`, its length left for sam_glb_finish, and `json` as its
// JSON chunk, padded with spaces to 4 bytes. The chunks after it are the
// caller's to append.
inline void sam_glb_start(std::vector<uint8_t> &out, uint32_t version, std::string json)
{
    json.resize((json.size() + 3) & ~size_t(3), ' ');
    static const uint8_t magic[4] = {'g', 'l', 'T', 'F'};
    out.assign(magic, magic + 4);
    sam_glb_put_u32(out, version);
    sam_glb_put_u32(out, 0);
    sam_glb_put_u32(out, uint32_t(json.size()));
    sam_glb_put_u32(out, SAM_GLB_JSON);
    out.insert(out.end(), json.begin(), json.end());
}

// Writes the length of the GLB in `out` into its header; false when it
// passes the 4 GiB the field holds.
inline bool sam_glb_finish(std::vector<uint8_t> &out)
{
    if (out.size() > UINT32_MAX)
        return false;
    for (int i = 0; i < 4; ++i)
        out[8 + size_t(i)] = uint8_t(out.size() >> (8 * i));
    return true;
}

// Whether the `size` bytes at `data` begin as a GLB does.
inline bool sam_glb_is(const uint8_t *data, size_t size)
{
    return size >= 4 && !std::memcmp(data, "glTF", 4);
}

// A GLB's JSON chunk: its bytes start at 20, `*json_size` of them, and the
// chunks after it at 20 + *json_size. Returns a phrase saying what is
// wrong, or NULL when the chunk is there whole.
inline const char *sam_glb_json(const uint8_t *data, size_t size, size_t *json_size)
{
    if (size < 20 || sam_glb_u32(data + 16) != SAM_GLB_JSON)
        return "a GLB without a JSON chunk first";
    *json_size = sam_glb_u32(data + 12);
    if (*json_size > size - 20)
        return "its JSON chunk runs past the end of the file";
    return nullptr;
}

// What is wrong with the chunk layout of the GLB at `data` (`size`
// bytes), as a phrase with the numbers found; "" when its header's length
// fits the file, its JSON chunk fits that length, and so does the chunk
// after it, head and bytes. TinyGLTF 2.7 checks a binary chunk's bytes but
// not its 8-byte head against the length, and read up to 8 bytes past
// the end of a file whose chunk said it filled the rest.
inline std::string sam_glb_check(const uint8_t *data, size_t size)
{
    if (size < 12)
        return "a GLB of " + std::to_string(size) + " bytes, shorter than its 12-byte header";
    const size_t length = sam_glb_u32(data + 8);
    if (length > size)
        return "its header gives " + std::to_string(length) + " bytes, the file has " + std::to_string(size);
    size_t json_size;
    if (const char *why = sam_glb_json(data, length, &json_size))
        return why;
    const size_t at = 20 + json_size;
    if (at == length)
        return "";
    if (length - at < 8)
        return "the chunk after the JSON, at byte " + std::to_string(at) + ", is cut short by the GLB's length of " +
               std::to_string(length);
    const size_t chunk = sam_glb_u32(data + at);
    if (chunk > length - at - 8)
        return "the chunk after the JSON, " + std::to_string(chunk) + " bytes at byte " + std::to_string(at + 8) +
               ", runs past the GLB's length of " + std::to_string(length);
    return "";
}

#endif
