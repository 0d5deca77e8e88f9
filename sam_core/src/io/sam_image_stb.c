/* JPEG and TGA pictures through stb_image (Debian's libstb), and the
 * reader that picks a picture's decoder by its extension
 * (sam_image_read_picture in sam_image.h). PNG stays with libpng
 * (sam_image_png.c). stb_image keeps its failure reason in a thread-local
 * variable and nothing else between calls; this file sets none of its
 * process-wide options. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "sam_image_internal.h"

/* Bytes a TGA's pixels need, from its header and (run-length encoded) its
 * packets (SIZE_MAX without a whole header). stb_image reads zeros past the
 * end of a file, so a truncated TGA would load with black rows. */
static size_t tga_size(const uint8_t *d, size_t size)
{
    if (size < 18)
        return SIZE_MAX;
    const size_t id = d[0], map_entries = (size_t)d[5] | (size_t)d[6] << 8, map_bits = d[7];
    const size_t w = (size_t)d[12] | (size_t)d[13] << 8, h = (size_t)d[14] | (size_t)d[15] << 8;
    const size_t bytes = ((size_t)d[16] + 7) / 8, type = d[2];
    size_t at = 18 + id + (d[1] ? map_entries * ((map_bits + 7) / 8) : 0);
    if (type < 9)
        return at + w * h * bytes;
    for (size_t pixels = 0; pixels < w * h;) {
        if (at >= size)
            return at + 1;
        const size_t packet = d[at++], count = (packet & 0x7f) + 1;
        at += packet & 0x80 ? bytes : count * bytes;
        pixels += count;
    }
    return at;
}

/* A JPEG ends with its end-of-image marker; stb_image fills the blocks of
 * a truncated one with grey. */
static int jpeg_complete(const uint8_t *d, size_t size)
{
    for (size_t i = size; i-- > 2;)
        if (d[i - 1] == 0xFF && d[i] == 0xD9)
            return 1;
    return 0;
}

static sam_status read_stb(const char *path, sam_image *image, sam_png_encoding encoding, sam_error *err)
{
    uint8_t *data;
    size_t size;
    sam_status st = sam_read_file(path, &data, &size, err);
    if (st != SAM_OK)
        return st;
    int w = 0, h = 0, c = 0;
    if (size > (size_t)INT32_MAX) {
        free(data);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "%s: %zu bytes is too large a picture", path, size);
    }
    if (!stbi_info_from_memory(data, (int)size, &w, &h, &c)) {
        free(data);
        return sam_fail(err, SAM_ERR_FORMAT, "%s: not a readable %s picture (%s)", path,
                        sam_path_has_extension(path, ".tga") ? "TGA" : "JPEG", stbi_failure_reason());
    }
    if ((st = sam_image_check_size((uint64_t)w, (uint64_t)h, 4, 1, path, err)) != SAM_OK) {
        free(data);
        return st;
    }
    const int tga = sam_path_has_extension(path, ".tga");
    const size_t need = tga ? tga_size(data, size) : 0;
    if (tga ? need > size : !jpeg_complete(data, size)) {
        free(data);
        if (!tga)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: truncated JPEG: no end-of-image marker in its %zu bytes", path,
                            size);
        if (need == SIZE_MAX)
            return sam_fail(err, SAM_ERR_FORMAT, "%s: truncated TGA: %zu bytes, less than its 18-byte header", path,
                            size);
        return sam_fail(err, SAM_ERR_FORMAT, "%s: truncated TGA: its %d x %d pixels need %zu bytes, the file has %zu",
                        path, w, h, need, size);
    }
    /* Grey becomes RGB and grey with alpha RGBA, as with PNG. */
    const int want = c == 2 || c == 4 ? 4 : 3;
    stbi_uc *raw = stbi_load_from_memory(data, (int)size, &w, &h, &c, want);
    free(data);
    if (!raw)
        return sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, stbi_failure_reason());
    st = sam_image_from_bytes(image, raw, (uint32_t)w, (uint32_t)h, (uint32_t)want, encoding, err);
    stbi_image_free(raw);
    return st != SAM_OK ? sam_fail(err, st, "%s: out of memory for %d x %d pixels", path, w, h) : SAM_OK;
}

sam_status sam_image_read_picture(const char *path, sam_image *image, sam_png_encoding encoding,
                                  sam_error *err)
{
    if (!path || !image)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "read picture: NULL %s", path ? "image" : "path");
    memset(image, 0, sizeof *image);
    if (encoding != SAM_PNG_SRGB && encoding != SAM_PNG_LINEAR)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: unknown encoding %d", path, (int)encoding);
    if (sam_path_has_extension(path, ".png"))
        return sam_image_read_png(path, image, encoding, err);
    if (sam_path_has_extension(path, ".jpg") || sam_path_has_extension(path, ".jpeg") ||
        sam_path_has_extension(path, ".tga"))
        return read_stb(path, image, encoding, err);
    return sam_fail(err, SAM_ERR_UNSUPPORTED, "%s: unsupported picture format (expected .png, .jpg, .jpeg or .tga)",
                    path);
}
