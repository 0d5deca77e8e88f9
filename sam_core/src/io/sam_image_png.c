#include "sam/sam_image.h"

#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>

#include "sam_image_internal.h"

/* ------------------------------------------------------------------------ */
/* PNG                                                                       */

/* State reached from libpng's callbacks. */
typedef struct png_io {
    const uint8_t *data; /* whole file, when reading */
    size_t size, pos;
    char message[256]; /* first error; later ones are consequences */
} png_io;

static void png_error_fn(png_structp png, png_const_charp msg)
{
    png_io *io = png_get_error_ptr(png);
    if (!io->message[0])
        snprintf(io->message, sizeof io->message, "%s", msg ? msg : "unknown libpng error");
    png_longjmp(png, 1);
}

/* Warnings (e.g. a bad CRC in an ancillary chunk, which is then skipped)
 * leave the image usable; they are not worth a line on stderr. */
static void png_warning_fn(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static void png_read_fn(png_structp png, png_bytep out, size_t length)
{
    png_io *io = png_get_io_ptr(png);
    if (length > io->size - io->pos) {
        snprintf(io->message, sizeof io->message,
                 "truncated: %zu bytes needed at offset %zu but the file ends at %zu", length,
                 io->pos, io->size);
        png_error(png, "truncated");
    }
    memcpy(out, io->data + io->pos, length);
    io->pos += length;
}

sam_status sam_image_write_png(const char *path, const sam_image *image,
                               sam_png_encoding encoding, sam_error *err)
{
    sam_status st = sam_image_check_output(path, image, err);
    if (st != SAM_OK)
        return st;
    if (encoding != SAM_PNG_SRGB && encoding != SAM_PNG_LINEAR)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: unknown PNG encoding %d", path,
                        (int)encoding);
    const uint32_t w = image->width, h = image->height, c = image->channels;
    if (w > PNG_UINT_31_MAX || h > PNG_UINT_31_MAX)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: %u x %u pixels is too large for PNG",
                        path, w, h);

    /* Everything libpng may longjmp past is allocated before setjmp and not
     * modified after it, so it can be freed on the error path. */
    size_t row_bytes = (size_t)w * c;
    uint8_t *bytes = malloc(row_bytes * h);
    png_bytep *rows = malloc(sizeof *rows * h);
    if (!bytes || !rows) {
        free(bytes);
        free(rows);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %u x %u pixels", path,
                        w, h);
    }
    for (size_t i = 0; i < row_bytes * h; ++i)
        bytes[i] = sam_image_to_byte(image->pixels[i], encoding == SAM_PNG_SRGB && i % c != 3);
    for (uint32_t y = 0; y < h; ++y)
        rows[y] = bytes + row_bytes * y;

    sam_atomic_file file;
    if ((st = sam_atomic_open(&file, path, err)) != SAM_OK) {
        free(bytes);
        free(rows);
        return st;
    }
    png_io io = {0};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &io, png_error_fn,
                                              png_warning_fn);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        sam_atomic_abort(&file);
        free(bytes);
        free(rows);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: cannot create the PNG writer", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        sam_atomic_abort(&file);
        free(bytes);
        free(rows);
        return sam_fail(err, SAM_ERR_IO, "%s: PNG write failed: %s", path, io.message);
    }
    png_init_io(png, file.fp);
    png_set_IHDR(png, info, w, h, 8, c == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (encoding == SAM_PNG_SRGB)
        png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(bytes);
    free(rows);
    return sam_atomic_commit(&file, err);
}

/* Decodes the PNG in `io` into a newly malloc'd buffer of 8- or 16-bit
 * (big-endian) RGB(A) samples. Kept apart from the caller so that setjmp's
 * volatile rules cover only this function's locals. */
static sam_status png_decode(const char *path, png_io *io, uint8_t **out, uint32_t *out_w,
                             uint32_t *out_h, uint32_t *out_channels, uint32_t *out_depth,
                             sam_error *err)
{
    uint8_t *volatile raw = NULL;
    png_bytep *volatile rows = NULL;
    volatile sam_status st = SAM_OK;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, io, png_error_fn,
                                             png_warning_fn);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_read_struct(&png, &info, NULL);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: cannot create the PNG reader", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        free(raw);
        free(rows);
        return sam_fail(err, SAM_ERR_FORMAT, "%s: %s", path, io->message);
    }
    png_set_read_fn(png, io, png_read_fn);
    png_read_info(png, info);
    uint32_t w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    int color_type = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
    if (color_type == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if (color_type == PNG_COLOR_TYPE_GRAY && depth < 8)
        png_set_expand_gray_1_2_4_to_8(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS))
        png_set_tRNS_to_alpha(png);
    if (color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);

    uint32_t channels = png_get_channels(png, info);
    uint32_t out_bits = png_get_bit_depth(png, info);
    size_t row_bytes = png_get_rowbytes(png, info);
    if ((st = sam_image_check_size(w, h, channels, 1, path, err)) != SAM_OK)
        goto fail;
    if ((out_bits != 8 && out_bits != 16) || row_bytes != (size_t)w * channels * (out_bits / 8)) {
        st = sam_fail(err, SAM_ERR_FORMAT,
                      "%s: color type %d, bit depth %d did not expand to 8/16-bit RGB(A) (%u "
                      "channels, %u bits)", path, color_type, depth, channels, out_bits);
        goto fail;
    }
    raw = malloc(row_bytes * h);
    rows = malloc(sizeof(png_bytep) * h);
    if (!raw || !rows) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for %u x %u pixels", path, w,
                      h);
        goto fail;
    }
    for (uint32_t y = 0; y < h; ++y)
        rows[y] = raw + row_bytes * y;
    png_read_image(png, rows);
    /* Reading to IEND makes a file cut after the pixel data an error too. */
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    free(rows);
    *out = raw;
    *out_w = w;
    *out_h = h;
    *out_channels = channels;
    *out_depth = out_bits;
    return SAM_OK;
fail:
    png_destroy_read_struct(&png, &info, NULL);
    free(raw);
    free(rows);
    return st;
}

sam_status sam_image_read_png(const char *path, sam_image *image, sam_png_encoding encoding,
                              sam_error *err)
{
    if (!path || !image)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "read PNG: NULL %s",
                        path ? "image" : "path");
    memset(image, 0, sizeof *image);
    if (encoding != SAM_PNG_SRGB && encoding != SAM_PNG_LINEAR)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: unknown PNG encoding %d", path,
                        (int)encoding);
    uint8_t *data = NULL;
    size_t size = 0;
    sam_status st = sam_read_file(path, &data, &size, err);
    if (st != SAM_OK)
        return st;
    if (size < 8 || png_sig_cmp(data, 0, 8) != 0) {
        free(data);
        return sam_fail(err, SAM_ERR_FORMAT, "%s: not a PNG file (%zu bytes, no PNG signature)",
                        path, size);
    }
    png_io io = {.data = data, .size = size};
    uint8_t *raw = NULL;
    uint32_t w = 0, h = 0, c = 0, bits = 0;
    st = png_decode(path, &io, &raw, &w, &h, &c, &bits, err);
    free(data);
    if (st != SAM_OK)
        return st;
    if (bits == 8) {
        st = sam_image_from_bytes(image, raw, w, h, c, encoding, err);
        free(raw);
        return st != SAM_OK ? sam_fail(err, st, "%s: out of memory for %u x %u pixels", path, w, h) : SAM_OK;
    }
    if ((st = sam_image_create(image, w, h, c, err)) != SAM_OK) {
        free(raw);
        return sam_fail(err, st, "%s: out of memory for %u x %u pixels", path, w, h);
    }
    const size_t count = (size_t)w * h * c;
    for (size_t i = 0; i < count; ++i) {
        float v = (float)((raw[2 * i] << 8) | raw[2 * i + 1]) / 65535.0f;
        image->pixels[i] = encoding == SAM_PNG_SRGB && i % c != 3 ? sam_srgb_to_linear(v) : v;
    }
    free(raw);
    return SAM_OK;
}
