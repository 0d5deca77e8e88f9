// glTF geometry gltfpack compressed with meshopt (EXT_meshopt_compression),
// decoded into a plain GLB for TinyGLTF (sam_mesh_gltf_meshopt.h).
#include "sam_mesh_gltf_meshopt.h"

#include "sam/sam_common.h"
#include "sam_mesh_gltf_glb.h"

#include <cjson/cJSON.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace {

const char *const kExtension = "EXT_meshopt_compression";

// A whole non-negative number under `key` of `object`, `fallback` when
// the key is absent; -1 when it is there but no such number.
double whole(const cJSON *object, const char *key, double fallback)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(object, key);
    if (!item)
        return fallback;
    const double v = cJSON_IsNumber(item) ? item->valuedouble : -1.0;
    return v >= 0 && v <= 9007199254740992.0 && v == double(uint64_t(v)) ? v : -1.0;
}

const char *text(const cJSON *object, const char *key, const char *fallback)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(object, key);
    return cJSON_IsString(item) ? item->valuestring : item ? "" : fallback;
}

// Drops `name` from the string array `key` of `root`, walking it once
// (indexing a cJSON array walks it from the start).
void drop_name(cJSON *root, const char *key, const char *name)
{
    cJSON *list = cJSON_GetObjectItemCaseSensitive(root, key);
    for (cJSON *item = cJSON_IsArray(list) ? list->child : nullptr, *next; item; item = next) {
        next = item->next;
        if (cJSON_IsString(item) && !std::strcmp(item->valuestring, name))
            cJSON_Delete(cJSON_DetachItemViaPointer(list, item));
    }
}

// Sets `key` (every copy of it gone first); false when out of memory.
bool set_number(cJSON *object, const char *key, double v)
{
    while (cJSON_GetObjectItemCaseSensitive(object, key))
        cJSON_DeleteItemFromObjectCaseSensitive(object, key);
    return cJSON_AddNumberToObject(object, key, v) != nullptr;
}

// A data URI's base64 payload decoded into `out`; false on a character
// base64 does not have.
bool base64_decode(const char *in, std::vector<uint8_t> &out)
{
    uint32_t bits = 0;
    int have = 0;
    for (; *in && *in != '='; ++in) {
        const char *abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const char *at = std::strchr(abc, *in);
        if (!at)
            return false;
        bits = bits << 6 | uint32_t(at - abc);
        if ((have += 6) >= 8) {
            have -= 8;
            out.push_back(uint8_t(bits >> have));
        }
    }
    return true;
}

// A relative URI's path: %XX escapes decoded, as glTF's URIs have them.
std::string uri_path(const char *uri)
{
    std::string path;
    for (const char *p = uri; *p; ++p) {
        unsigned code;
        if (*p == '%' && std::isxdigit((unsigned char)p[1]) && std::isxdigit((unsigned char)p[2]) &&
            std::sscanf(p + 1, "%2x", &code) == 1) {
            path += char(code);
            p += 2;
        } else {
            path += *p;
        }
    }
    return path;
}

struct Source {
    const uint8_t *p = nullptr; // null: a buffer this decoder does not read (meshopt's fallback)
    size_t n = 0;
};

struct Decoder {
    cJSON *root = nullptr;
    std::vector<Source> sources;              // by buffer index
    std::vector<std::vector<uint8_t>> loaded; // a .gltf's buffers, read from files or data URIs
    size_t input = 0;                         // bytes of the file and the buffers it reads
    // Bytes the new chunk may hold: views that copy or decode the same
    // bytes again, or claim more than meshopt data holds, would otherwise
    // make a small file ask for gigabytes.
    size_t budget = 0;
    std::vector<uint8_t> out;
    std::string message;

    ~Decoder() { cJSON_Delete(root); }

    bool fail(const std::string &why)
    {
        message = why;
        return false;
    }

    // The buffers' bytes: a GLB's binary chunk for a first buffer without
    // a URI, a .gltf's files beside it (`path`) and data URIs.
    bool read_sources(const char *path, const uint8_t *bin, size_t bin_size)
    {
        const cJSON *buffers = cJSON_GetObjectItemCaseSensitive(root, "buffers"), *buffer;
        const char *slash = std::strrchr(path, '/');
        const std::string dir = slash ? std::string(path, size_t(slash - path) + 1) : "";
        cJSON_ArrayForEach(buffer, buffers)
        {
            const size_t b = sources.size();
            const char *uri = text(buffer, "uri", nullptr);
            Source s;
            if (!uri && b == 0 && bin) {
                s = {bin, bin_size};
            } else if (uri && !std::strncmp(uri, "data:", 5)) {
                const char *payload = std::strstr(uri, ";base64,");
                std::vector<uint8_t> bytes;
                if (!payload || !base64_decode(payload + 8, bytes))
                    return fail("buffer " + std::to_string(b) + ": its data URI is not base64");
                loaded.push_back(std::move(bytes));
                s = {loaded.back().data(), loaded.back().size()};
            } else if (uri) {
                const std::string file = dir + uri_path(uri);
                uint8_t *data;
                size_t size;
                sam_error err;
                if (sam_read_file(file.c_str(), &data, &size, &err) != SAM_OK)
                    return fail("buffer " + std::to_string(b) + ": " + err.message);
                loaded.emplace_back(data, data + size);
                std::free(data);
                s = {loaded.back().data(), loaded.back().size()};
            }
            input += s.n;
            sources.push_back(s);
        }
        return true;
    }

    // The bytes [offset, offset + length) of buffer `b`, or null.
    const uint8_t *bytes(double b, double offset, double length)
    {
        if (b < 0 || b >= double(sources.size()))
            return nullptr;
        const Source &s = sources[size_t(b)];
        if (!s.p || offset < 0 || length < 0 || offset > double(s.n) || length > double(s.n) - offset)
            return nullptr;
        return s.p + size_t(offset);
    }

    // Room for `n` more bytes at a 4-byte boundary of `out`: their offset,
    // or false past the budget.
    bool append(double n, size_t *at)
    {
        const size_t aligned = (out.size() + 3) & ~size_t(3);
        if (n < 0 || aligned > budget || n > double(budget - aligned))
            return false;
        out.resize(aligned + size_t(n));
        *at = aligned;
        return true;
    }

    bool view(cJSON *view, int index)
    {
        const std::string name = "buffer view " + std::to_string(index);
        cJSON *extensions = cJSON_GetObjectItemCaseSensitive(view, "extensions");
        const cJSON *ext = cJSON_GetObjectItemCaseSensitive(extensions, kExtension);
        size_t at;
        double length;
        if (!ext) {
            const double offset = whole(view, "byteOffset", 0);
            length = whole(view, "byteLength", -1);
            const uint8_t *src = bytes(whole(view, "buffer", -1), offset, length);
            if (!src)
                return fail(name + " lies outside its buffer, or in one it has no bytes of (a fallback)");
            if (!append(length, &at))
                return fail(name + ": the views copy more than " + std::to_string(budget) +
                            " bytes, 64 times the file and its buffers");
            if (length > 0)
                std::memcpy(out.data() + at, src, size_t(length));
        } else {
            const double offset = whole(ext, "byteOffset", 0), size = whole(ext, "byteLength", -1);
            const double stride = whole(ext, "byteStride", -1), count = whole(ext, "count", -1);
            const std::string mode = text(ext, "mode", ""), filter = text(ext, "filter", "NONE");
            const uint8_t *src = bytes(whole(ext, "buffer", -1), offset, size);
            if (!src)
                return fail(name + ": its meshopt data lies outside its buffer");
            const bool attributes = mode == "ATTRIBUTES", triangles = mode == "TRIANGLES", indices = mode == "INDICES";
            const bool stride_ok = attributes ? stride >= 4 && stride <= 256 && std::fmod(stride, 4) == 0
                                              : (triangles || indices) && (stride == 2 || stride == 4);
            if (!stride_ok || count < 0 || (triangles && std::fmod(count, 3) != 0))
                return fail(name + ": meshopt mode \"" + mode + "\" with byteStride " + std::to_string(stride) +
                            " and count " + std::to_string(count) + " is not one the extension allows");
            length = count * stride;
            if (!append(length, &at))
                return fail(name + ": " + std::to_string(size_t(count)) + " elements of " +
                            std::to_string(size_t(stride)) + " bytes would take the views past " +
                            std::to_string(budget) +
                            " bytes, 64 times the file and its buffers: more than meshopt data holds");
            uint8_t *dst = out.data() + at;
            const size_t n = size_t(count), s = size_t(stride);
            const int rc = attributes  ? meshopt_decodeVertexBuffer(dst, n, s, src, size_t(size))
                           : triangles ? meshopt_decodeIndexBuffer(dst, n, s, src, size_t(size))
                                       : meshopt_decodeIndexSequence(dst, n, s, src, size_t(size));
            if (rc != 0)
                return fail(name + ": its meshopt data does not decode (meshopt error " + std::to_string(rc) + ")");
            if (filter == "OCTAHEDRAL" && attributes && (s == 4 || s == 8))
                meshopt_decodeFilterOct(dst, n, s);
            else if (filter == "QUATERNION" && attributes && s == 8)
                meshopt_decodeFilterQuat(dst, n, s);
            else if (filter == "EXPONENTIAL" && attributes)
                meshopt_decodeFilterExp(dst, n, s);
            else if (filter != "NONE")
                return fail(name + ": meshopt filter \"" + filter + "\" does not go with mode \"" + mode +
                            "\" and byteStride " + std::to_string(s));
            cJSON_DeleteItemFromObjectCaseSensitive(extensions, kExtension);
        }
        if (!set_number(view, "buffer", 0) || !set_number(view, "byteOffset", double(at)) ||
            !set_number(view, "byteLength", length))
            return fail("out of memory writing the JSON again");
        return true;
    }
};

} // namespace

bool sam_mesh_gltf_meshopt_decode(const char *path, const uint8_t *data, size_t size, std::vector<uint8_t> &glb,
                                  std::string &message)
{
    auto refuse = [&](const std::string &why) {
        message = why;
        return false;
    };
    Decoder d;
    const char *json = reinterpret_cast<const char *>(data);
    size_t json_size = size;
    const uint8_t *bin = nullptr;
    size_t bin_size = 0;
    if (sam_glb_is(data, size)) {
        if (const char *why = sam_glb_json(data, size, &json_size))
            return refuse(why);
        json += 20;
        const size_t bin_at = 20 + json_size;
        if (bin_at + 8 <= size && sam_glb_u32(data + bin_at + 4) == SAM_GLB_BIN &&
            sam_glb_u32(data + bin_at) <= size - bin_at - 8) {
            bin = data + bin_at + 8;
            bin_size = sam_glb_u32(data + bin_at);
        }
    }
    d.root = cJSON_ParseWithLength(json, json_size);
    if (!cJSON_IsObject(d.root))
        return refuse("its JSON is not a glTF object");
    if (!d.read_sources(path, bin, bin_size))
        return refuse(d.message);
    // Under 2 GiB in all, the GLB's 32-bit lengths with room to spare.
    d.budget = size_t(std::max(0.0, std::min(64.0 * double(size + d.input) + 1048576.0,
                                             2147483648.0 - 65536.0 - double(json_size))));
    cJSON *views = cJSON_GetObjectItemCaseSensitive(d.root, "bufferViews");
    if (views && !cJSON_IsArray(views))
        return refuse("its buffer views are not an array");
    int i = 0;
    cJSON *view;
    cJSON_ArrayForEach(view, views)
    {
        if (!cJSON_IsObject(view))
            return refuse("buffer view " + std::to_string(i) + " is not an object");
        if (!d.view(view, i++))
            return refuse(d.message);
    }
    d.out.resize((d.out.size() + 3) & ~size_t(3));
    cJSON *buffers = cJSON_CreateArray(), *buffer = cJSON_CreateObject();
    if (!buffers || !buffer || !cJSON_AddNumberToObject(buffer, "byteLength", double(d.out.size()))) {
        cJSON_Delete(buffers);
        cJSON_Delete(buffer);
        return refuse("out of memory writing its JSON again");
    }
    cJSON_AddItemToArray(buffers, buffer);
    while (cJSON_GetObjectItemCaseSensitive(d.root, "buffers"))
        cJSON_DeleteItemFromObjectCaseSensitive(d.root, "buffers");
    if (!cJSON_AddItemToObject(d.root, "buffers", buffers)) {
        cJSON_Delete(buffers);
        return refuse("out of memory writing its JSON again");
    }
    drop_name(d.root, "extensionsUsed", kExtension);
    drop_name(d.root, "extensionsRequired", kExtension);
    std::unique_ptr<char, decltype(&cJSON_free)> printed(cJSON_PrintUnformatted(d.root), cJSON_free);
    if (!printed)
        return refuse("out of memory writing its JSON again");
    const std::string text(printed.get());
    glb.reserve(28 + text.size() + 3 + d.out.size());
    sam_glb_start(glb, 2, text);
    sam_glb_put_u32(glb, uint32_t(d.out.size()));
    sam_glb_put_u32(glb, SAM_GLB_BIN);
    glb.insert(glb.end(), d.out.begin(), d.out.end());
    if (!sam_glb_finish(glb))
        return refuse("its decoded GLB would pass 4 GiB");
    return true;
}
