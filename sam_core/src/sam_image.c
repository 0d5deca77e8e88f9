#define _POSIX_C_SOURCE 200809L
#include "sam/sam_image.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openexr.h>
#include <png.h>

/* ------------------------------------------------------------------------ */
/* Image memory and size checks                                              */

/* Checks an image size; `what` prefixes the message (a file name or
 * "image"). A size read from a file is a format problem when empty and
 * unsupported when too big; a size from a caller is an invalid argument. */
static sam_status check_size(uint64_t width, uint64_t height, uint64_t channels, int from_file,
                             const char *what, sam_error *err)
{
    if (width == 0 || height == 0)
        return sam_fail(err, from_file ? SAM_ERR_FORMAT : SAM_ERR_INVALID_ARGUMENT,
                        "%s: empty image (%llu x %llu pixels)", what, (unsigned long long)width,
                        (unsigned long long)height);
    if (channels != 3 && channels != 4)
        return sam_fail(err, from_file ? SAM_ERR_FORMAT : SAM_ERR_INVALID_ARGUMENT,
                        "%s: %llu channels (expected 3 or 4)", what, (unsigned long long)channels);
    /* Testing the factors first keeps the product from wrapping. */
    if (width > SAM_IMAGE_MAX_PIXELS || height > SAM_IMAGE_MAX_PIXELS ||
        width * height > SAM_IMAGE_MAX_PIXELS)
        return sam_fail(err, from_file ? SAM_ERR_UNSUPPORTED : SAM_ERR_INVALID_ARGUMENT,
                        "%s: %llu x %llu pixels is more than the limit of %u pixels", what,
                        (unsigned long long)width, (unsigned long long)height,
                        SAM_IMAGE_MAX_PIXELS);
    return SAM_OK;
}

sam_status sam_image_create(sam_image *image, uint32_t width, uint32_t height, uint32_t channels,
                            sam_error *err)
{
    if (!image)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image create: NULL image");
    memset(image, 0, sizeof *image);
    sam_status st = check_size(width, height, channels, 0, "image", err);
    if (st != SAM_OK)
        return st;
    size_t count = (size_t)width * height * channels;
    float *pixels = calloc(count, sizeof *pixels);
    if (!pixels)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "image: out of memory for %u x %u x %u floats",
                        width, height, channels);
    image->width = width;
    image->height = height;
    image->channels = channels;
    image->pixels = pixels;
    return SAM_OK;
}

void sam_image_destroy(sam_image *image)
{
    if (!image)
        return;
    free(image->pixels);
    memset(image, 0, sizeof *image);
}

/* Checks an image passed in by a caller; `what` prefixes the message. */
static sam_status check_image(const char *what, const sam_image *image, sam_error *err)
{
    if (!image || !image->pixels)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: no image given", what);
    return check_size(image->width, image->height, image->channels, 0, what, err);
}

static sam_status check_image_arg(const char *path, const sam_image *image, sam_error *err)
{
    if (!path || !path[0])
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image write: no output path given");
    return check_image(path, image, err);
}

/* ------------------------------------------------------------------------ */
/* sRGB                                                                      */

float sam_srgb_to_linear(float encoded)
{
    if (encoded <= 0.04045f)
        return encoded / 12.92f;
    return powf((encoded + 0.055f) / 1.055f, 2.4f);
}

float sam_linear_to_srgb(float linear)
{
    if (linear <= 0.0031308f)
        return linear * 12.92f;
    return 1.055f * powf(linear, 1.0f / 2.4f) - 0.055f;
}

/* One value as an 8-bit PNG sample: sRGB-encoded when `srgb`, clamped to
 * [0, 1], rounded to nearest. The PNG writer and the 8-bit comparison share
 * it so that a comparison measures exactly the bytes a PNG would hold. */
static uint8_t to_byte(float v, int srgb)
{
    if (srgb)
        v = sam_linear_to_srgb(v);
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* NaN fails v > 0 and becomes 0 */
    return (uint8_t)(v * 255.0f + 0.5f);
}

/* ------------------------------------------------------------------------ */
/* OpenEXR reading                                                           */

/* Per-read state reached from the Core callbacks through the context's user
 * data: our own read/size callbacks keep user data ours (the library's
 * default file stream would replace it with its file handle). */
typedef struct exr_reader {
    int fd;
    int64_t size;
    char message[512]; /* first error message the library reported */
} exr_reader;

static void exr_read_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *user = NULL;
    (void)code;
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user)
        return;
    exr_reader *reader = user;
    /* The first message is the cause; later ones are consequences. */
    if (!reader->message[0] && msg)
        snprintf(reader->message, sizeof reader->message, "%s", msg);
}

static int64_t exr_read_fn(exr_const_context_t ctxt, void *user, void *buffer, uint64_t size,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_reader *reader = user;
    uint8_t *out = buffer;
    uint64_t done = 0;
    while (done < size) {
        ssize_t got = pread(reader->fd, out + done, (size_t)(size - done), (off_t)(offset + done));
        if (got < 0) {
            if (errno == EINTR)
                continue;
            error_cb(ctxt, EXR_ERR_READ_IO, "read of %llu bytes at offset %llu failed: %s",
                     (unsigned long long)size, (unsigned long long)offset, strerror(errno));
            return -1;
        }
        if (got == 0)
            break;
        done += (uint64_t)got;
    }
    /* A short read is how a truncated file shows; the library reports it. */
    return (int64_t)done;
}

static int64_t exr_size_fn(exr_const_context_t ctxt, void *user)
{
    (void)ctxt;
    return ((const exr_reader *)user)->size;
}

/* Describes a failed Core call: the library's own message when it gave one. */
static const char *exr_reason(const exr_reader *reader, exr_result_t rv)
{
    return reader->message[0] ? reader->message : exr_get_default_error_message(rv);
}

static sam_status exr_status(exr_result_t rv)
{
    switch (rv) {
    case EXR_ERR_OUT_OF_MEMORY: return SAM_ERR_OUT_OF_MEMORY;
    case EXR_ERR_FILE_ACCESS: return SAM_ERR_IO;
    case EXR_ERR_FEATURE_NOT_IMPLEMENTED: return SAM_ERR_UNSUPPORTED;
    default: return SAM_ERR_FORMAT;
    }
}

/* Where each source channel goes in the output pixel; -1 = not read. */
typedef struct exr_channel_map {
    int r, g, b, a, y; /* indices into the file's channel list, -1 if absent */
} exr_channel_map;

static int exr_find_channel(const exr_attr_chlist_t *list, const char *name)
{
    for (int i = 0; i < list->num_channels; ++i) {
        if (list->entries[i].name.str && strcmp(list->entries[i].name.str, name) == 0)
            return i;
    }
    return -1;
}

static void exr_list_channels(const exr_attr_chlist_t *list, char *buf, size_t n)
{
    size_t len = 0;
    buf[0] = 0;
    for (int i = 0; i < list->num_channels && len + 1 < n; ++i) {
        int w = snprintf(buf + len, n - len, "%s%s", i ? ", " : "",
                         list->entries[i].name.str ? list->entries[i].name.str : "?");
        if (w < 0)
            break;
        len += (size_t)w;
    }
    if (list->num_channels == 0)
        snprintf(buf, n, "none");
}

/* Output channel index (0..3) a decoder channel feeds, or -1 to skip it. */
static int exr_output_channel(const char *name, int use_y)
{
    if (!name)
        return -1;
    if (use_y)
        return strcmp(name, "Y") == 0 ? 0 : strcmp(name, "A") == 0 ? 3 : -1;
    if (strcmp(name, "R") == 0)
        return 0;
    if (strcmp(name, "G") == 0)
        return 1;
    if (strcmp(name, "B") == 0)
        return 2;
    if (strcmp(name, "A") == 0)
        return 3;
    return -1;
}

/* Growable per-read buffer that chunks are decoded into. */
typedef struct exr_scratch {
    float *data;
    size_t count;
} exr_scratch;

/* Decodes one chunk whose top-left pixel is (x0, y0) relative to the data
 * window into `image`.
 *
 * Every channel of the chunk, wanted or not, is decoded into its own plane
 * of `scratch` and the wanted ones are then interleaved here. OpenEXR 3.1's
 * fast paths for half -> float both swap the channel order of 4-channel
 * interleaved output and write through the pointer of a skipped channel of
 * a 3- or 4-channel part; planar output with no skipped channel avoids both,
 * on every Core version. */
static exr_result_t exr_decode_chunk(exr_context_t ctxt, const exr_chunk_info_t *cinfo,
                                     exr_decode_pipeline_t *decoder, int *initialized,
                                     exr_scratch *scratch, sam_image *image, int use_y,
                                     uint32_t x0, uint32_t y0)
{
    exr_result_t rv = *initialized ? exr_decoding_update(ctxt, 0, cinfo, decoder)
                                   : exr_decoding_initialize(ctxt, 0, cinfo, decoder);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    *initialized = 1;
    const size_t plane = (size_t)cinfo->width * (size_t)cinfo->height;
    const size_t need = plane * (size_t)decoder->channel_count;
    if (need > scratch->count) {
        float *grown = realloc(scratch->data, need * sizeof(float));
        if (!grown)
            return EXR_ERR_OUT_OF_MEMORY;
        scratch->data = grown;
        scratch->count = need;
    }
    for (int i = 0; i < decoder->channel_count; ++i) {
        exr_coding_channel_info_t *ch = &decoder->channels[i];
        ch->decode_to_ptr = (uint8_t *)(scratch->data + plane * (size_t)i);
        ch->user_pixel_stride = sizeof(float);
        ch->user_line_stride = (int32_t)((size_t)ch->width * sizeof(float));
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_bytes_per_element = sizeof(float);
    }
    rv = exr_decoding_choose_default_routines(ctxt, 0, decoder);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_decoding_run(ctxt, 0, decoder);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    const uint32_t c = image->channels;
    for (int i = 0; i < decoder->channel_count; ++i) {
        int out = exr_output_channel(decoder->channels[i].channel_name, use_y);
        if (out < 0 || (uint32_t)out >= c)
            continue;
        const float *src = scratch->data + plane * (size_t)i;
        for (int32_t y = 0; y < cinfo->height; ++y) {
            float *dst = image->pixels + (((size_t)y0 + (size_t)y) * image->width + x0) * c +
                         (size_t)out;
            for (int32_t x = 0; x < cinfo->width; ++x)
                dst[(size_t)x * c] = src[(size_t)y * (size_t)cinfo->width + (size_t)x];
        }
    }
    return EXR_ERR_SUCCESS;
}

/* Reads the pixels of part 0 once the header has been validated. */
static sam_status exr_read_pixels(const char *path, exr_context_t ctxt, exr_reader *reader,
                                  exr_storage_t storage, const exr_attr_box2i_t *dw,
                                  sam_image *image, int use_y, sam_error *err)
{
    exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
    exr_scratch scratch = {NULL, 0};
    int initialized = 0;
    sam_status st = SAM_OK;
    exr_result_t rv;
    exr_chunk_info_t cinfo;

    if (storage == EXR_STORAGE_SCANLINE) {
        int32_t lines = 0;
        if ((rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines)) != EXR_ERR_SUCCESS || lines <= 0) {
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: scanlines per chunk: %s", path,
                          rv ? exr_reason(reader, rv) : "not positive");
            goto done;
        }
        for (int64_t row = 0; row < image->height; row += lines) {
            int y = (int)(dw->min.y + row);
            rv = exr_read_scanline_chunk_info(ctxt, 0, y, &cinfo);
            if (rv == EXR_ERR_SUCCESS) {
                if (cinfo.start_y != y || cinfo.height <= 0 || cinfo.width != (int)image->width ||
                    row + cinfo.height > image->height) {
                    st = sam_fail(err, SAM_ERR_FORMAT,
                                  "%s: chunk at scanline %d: %d x %d pixels from line %d do not "
                                  "fit the %u x %u data window",
                                  path, y, cinfo.width, cinfo.height, cinfo.start_y, image->width,
                                  image->height);
                    goto done;
                }
                rv = exr_decode_chunk(ctxt, &cinfo, &decoder, &initialized, &scratch, image, use_y, 0,
                                      (uint32_t)row);
            }
            if (rv != EXR_ERR_SUCCESS) {
                st = sam_fail(err, exr_status(rv), "%s: chunk at scanline %d: %s", path, y,
                              exr_reason(reader, rv));
                goto done;
            }
        }
    } else {
        uint32_t tile_w = 0, tile_h = 0;
        exr_tile_level_mode_t level_mode;
        exr_tile_round_mode_t round_mode;
        int32_t level_w = 0, level_h = 0;
        rv = exr_get_tile_descriptor(ctxt, 0, &tile_w, &tile_h, &level_mode, &round_mode);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_get_level_sizes(ctxt, 0, 0, 0, &level_w, &level_h);
        if (rv != EXR_ERR_SUCCESS) {
            st = sam_fail(err, exr_status(rv), "%s: tile description: %s", path,
                          exr_reason(reader, rv));
            goto done;
        }
        if (tile_w == 0 || tile_h == 0 || level_w != (int32_t)image->width ||
            level_h != (int32_t)image->height) {
            st = sam_fail(err, SAM_ERR_FORMAT,
                          "%s: tiles of %u x %u pixels and level 0 of %d x %d pixels do not match "
                          "the %u x %u data window",
                          path, tile_w, tile_h, level_w, level_h, image->width, image->height);
            goto done;
        }
        uint32_t tiles_x = (image->width + tile_w - 1) / tile_w;
        uint32_t tiles_y = (image->height + tile_h - 1) / tile_h;
        for (uint32_t ty = 0; ty < tiles_y; ++ty) {
            for (uint32_t tx = 0; tx < tiles_x; ++tx) {
                rv = exr_read_tile_chunk_info(ctxt, 0, (int)tx, (int)ty, 0, 0, &cinfo);
                uint64_t x0 = (uint64_t)tx * tile_w, y0 = (uint64_t)ty * tile_h;
                if (rv == EXR_ERR_SUCCESS) {
                    if (cinfo.width <= 0 || cinfo.height <= 0 ||
                        x0 + (uint64_t)cinfo.width > image->width ||
                        y0 + (uint64_t)cinfo.height > image->height) {
                        st = sam_fail(err, SAM_ERR_FORMAT,
                                      "%s: tile (%u, %u) of %d x %d pixels does not fit the %u x "
                                      "%u data window",
                                      path, tx, ty, cinfo.width, cinfo.height, image->width,
                                      image->height);
                        goto done;
                    }
                    rv = exr_decode_chunk(ctxt, &cinfo, &decoder, &initialized, &scratch, image, use_y,
                                          (uint32_t)x0, (uint32_t)y0);
                }
                if (rv != EXR_ERR_SUCCESS) {
                    st = sam_fail(err, exr_status(rv), "%s: tile (%u, %u): %s", path, tx, ty,
                                  exr_reason(reader, rv));
                    goto done;
                }
            }
        }
    }
    if (use_y) {
        size_t count = (size_t)image->width * image->height;
        for (size_t i = 0; i < count; ++i) {
            float *p = image->pixels + i * image->channels;
            p[1] = p[2] = p[0];
        }
    }
done:
    if (initialized)
        exr_decoding_destroy(ctxt, &decoder);
    free(scratch.data);
    return st;
}

sam_status sam_image_read_exr(const char *path, sam_image *image, sam_error *err)
{
    if (!path || !image)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "read EXR: NULL %s",
                        path ? "image" : "path");
    memset(image, 0, sizeof *image);

    exr_reader reader = {.fd = -1, .size = -1};
    reader.fd = open(path, O_RDONLY | O_CLOEXEC);
    if (reader.fd < 0)
        return sam_fail(err, SAM_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(reader.fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        close(reader.fd);
        return sam_fail(err, SAM_ERR_IO, "%s: not a regular file", path);
    }
    reader.size = (int64_t)sb.st_size;

    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_read_error_handler;
    init.user_data = &reader;
    init.read_fn = exr_read_fn;
    init.size_fn = exr_size_fn;
    /* A damaged file is an error, not a partly reconstructed image. */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;

    exr_context_t ctxt = NULL;
    sam_status st = SAM_OK;
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        st = sam_fail(err, exr_status(rv) == SAM_ERR_IO ? SAM_ERR_IO : SAM_ERR_FORMAT,
                      "%s: not a readable OpenEXR file: %s", path, exr_reason(&reader, rv));
        goto done;
    }

    exr_storage_t storage;
    if ((rv = exr_get_storage(ctxt, 0, &storage)) != EXR_ERR_SUCCESS) {
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: part 0: %s", path, exr_reason(&reader, rv));
        goto done;
    }
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) {
        st = sam_fail(err, SAM_ERR_UNSUPPORTED, "%s: part 0 holds deep %s data (expected a flat "
                      "scanline or tiled image)", path,
                      storage == EXR_STORAGE_DEEP_TILED ? "tiled" : "scanline");
        goto done;
    }

    exr_attr_box2i_t dw;
    if ((rv = exr_get_data_window(ctxt, 0, &dw)) != EXR_ERR_SUCCESS) {
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: data window: %s", path, exr_reason(&reader, rv));
        goto done;
    }
    int64_t width = (int64_t)dw.max.x - dw.min.x + 1, height = (int64_t)dw.max.y - dw.min.y + 1;
    if (width <= 0 || height <= 0) {
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: empty data window (%d, %d) - (%d, %d)", path,
                      dw.min.x, dw.min.y, dw.max.x, dw.max.y);
        goto done;
    }

    const exr_attr_chlist_t *channels = NULL;
    if ((rv = exr_get_channels(ctxt, 0, &channels)) != EXR_ERR_SUCCESS || !channels) {
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: channel list: %s", path,
                      rv ? exr_reason(&reader, rv) : "missing");
        goto done;
    }
    exr_channel_map map = {
        exr_find_channel(channels, "R"), exr_find_channel(channels, "G"),
        exr_find_channel(channels, "B"), exr_find_channel(channels, "A"),
        exr_find_channel(channels, "Y"),
    };
    int use_y = 0;
    if (map.r < 0 || map.g < 0 || map.b < 0) {
        if (map.y < 0) {
            char found[256];
            exr_list_channels(channels, found, sizeof found);
            st = sam_fail(err, SAM_ERR_FORMAT, "%s: no R,G,B or Y channels (found: %s)", path,
                          found);
            goto done;
        }
        use_y = 1;
    }
    /* Every channel is decoded (see exr_decode_chunk), so a subsampled one
     * anywhere in the part is refused, not just among R, G, B, A, Y. */
    for (int k = 0; k < channels->num_channels; ++k) {
        const exr_attr_chlist_entry_t *e = &channels->entries[k];
        if (e->x_sampling != 1 || e->y_sampling != 1) {
            st = sam_fail(err, SAM_ERR_UNSUPPORTED,
                          "%s: channel %s is subsampled %d x %d (only full-resolution channels "
                          "are supported)", path, e->name.str ? e->name.str : "?", e->x_sampling,
                          e->y_sampling);
            goto done;
        }
    }

    uint32_t out_channels = map.a >= 0 ? 4 : 3;
    if ((st = check_size((uint64_t)width, (uint64_t)height, out_channels, 1, path, err)) != SAM_OK)
        goto done;
    if ((st = sam_image_create(image, (uint32_t)width, (uint32_t)height, out_channels, err)) !=
        SAM_OK) {
        sam_fail(err, st, "%s: out of memory for %lld x %lld pixels", path, (long long)width,
                 (long long)height);
        goto done;
    }
    st = exr_read_pixels(path, ctxt, &reader, storage, &dw, image, use_y, err);

done:
    if (ctxt)
        exr_finish(&ctxt);
    close(reader.fd);
    if (st != SAM_OK)
        sam_image_destroy(image);
    return st;
}

/* ------------------------------------------------------------------------ */
/* OpenEXR writing                                                           */

typedef struct exr_writer {
    int fd;
    int saved_errno; /* errno of the first failed write, 0 if none */
} exr_writer;

/* Write contexts lock a mutex around calls that may report errors, so the
 * handler must not call back into the library (exr_get_user_data would lock
 * again). It stays silent: failures are reported from the return codes and
 * the write callback's errno. */
static void exr_write_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    (void)code;
    (void)msg;
}

static int64_t exr_write_fn(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t size,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_writer *writer = user;
    const uint8_t *in = buffer;
    uint64_t done = 0;
    while (done < size) {
        ssize_t put = pwrite(writer->fd, in + done, (size_t)(size - done), (off_t)(offset + done));
        if (put < 0 && errno == EINTR)
            continue;
        if (put <= 0) {
            if (!writer->saved_errno)
                writer->saved_errno = put < 0 ? errno : EIO;
            error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed");
            return -1;
        }
        done += (uint64_t)put;
    }
    return (int64_t)done;
}

static sam_status exr_write_failure(const char *path, const char *what, exr_result_t rv,
                                    const exr_writer *writer, sam_error *err)
{
    if (writer->saved_errno)
        return sam_fail(err, SAM_ERR_IO, "%s: %s: write failed: %s", path, what,
                        strerror(writer->saved_errno));
    return sam_fail(err, rv == EXR_ERR_OUT_OF_MEMORY ? SAM_ERR_OUT_OF_MEMORY : SAM_ERR_IO,
                    "%s: %s: %s", path, what, exr_get_default_error_message(rv));
}

sam_status sam_image_write_exr(const char *path, const sam_image *image, sam_exr_type type,
                               sam_error *err)
{
    sam_status st = check_image_arg(path, image, err);
    if (st != SAM_OK)
        return st;
    if (type != SAM_EXR_HALF && type != SAM_EXR_FLOAT)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: unknown EXR pixel type %d", path,
                        (int)type);
    if (image->width > INT32_MAX || image->height > INT32_MAX)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: %u x %u pixels is too large for EXR",
                        path, image->width, image->height);

    sam_atomic_file file;
    if ((st = sam_atomic_open(&file, path, err)) != SAM_OK)
        return st;
    exr_writer writer = {.fd = fileno(file.fp)};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_write_error_handler;
    init.user_data = &writer;
    init.write_fn = exr_write_fn;

    static const char *const names[4] = {"R", "G", "B", "A"};
    const exr_pixel_type_t pixel_type = type == SAM_EXR_HALF ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
    const uint32_t c = image->channels;
    exr_context_t ctxt = NULL;
    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    int encoder_ready = 0;
    int part = 0;
    int32_t lines = 0;
    const char *what = "header";
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctxt, part, (int32_t)image->width,
                                                 (int32_t)image->height, EXR_COMPRESSION_ZIP);
    for (uint32_t k = 0; k < c && rv == EXR_ERR_SUCCESS; ++k)
        rv = exr_add_channel(ctxt, part, names[k], pixel_type, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctxt);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
    if (rv == EXR_ERR_SUCCESS && lines <= 0)
        rv = EXR_ERR_INVALID_ARGUMENT;

    what = "pixels";
    for (uint32_t y = 0; y < image->height && rv == EXR_ERR_SUCCESS; y += (uint32_t)lines) {
        exr_chunk_info_t cinfo;
        rv = exr_write_scanline_chunk_info(ctxt, part, (int)y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = encoder_ready ? exr_encoding_update(ctxt, part, &cinfo, &encoder)
                           : exr_encoding_initialize(ctxt, part, &cinfo, &encoder);
        if (rv != EXR_ERR_SUCCESS)
            break;
        encoder_ready = 1;
        for (int i = 0; i < encoder.channel_count; ++i) {
            exr_coding_channel_info_t *ch = &encoder.channels[i];
            uint32_t k = 0;
            while (k < c && strcmp(ch->channel_name, names[k]) != 0)
                ++k;
            if (k == c) {
                rv = EXR_ERR_INVALID_ARGUMENT;
                break;
            }
            ch->encode_from_ptr =
                (const uint8_t *)(image->pixels + ((size_t)y * image->width) * c + k);
            ch->user_pixel_stride = (int32_t)(c * sizeof(float));
            ch->user_line_stride = (int32_t)((size_t)image->width * c * sizeof(float));
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = sizeof(float);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_choose_default_routines(ctxt, part, &encoder);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(ctxt, part, &encoder);
    }
    if (encoder_ready)
        exr_encoding_destroy(ctxt, &encoder);
    if (ctxt) {
        /* exr_finish writes the chunk offset table, so it can fail too. */
        exr_result_t frv = exr_finish(&ctxt);
        if (rv == EXR_ERR_SUCCESS && frv != EXR_ERR_SUCCESS) {
            rv = frv;
            what = "offset table";
        }
    }
    if (rv != EXR_ERR_SUCCESS) {
        st = exr_write_failure(path, what, rv, &writer, err);
        sam_atomic_abort(&file);
        return st;
    }
    return sam_atomic_commit(&file, err);
}

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
    sam_status st = check_image_arg(path, image, err);
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
        bytes[i] = to_byte(image->pixels[i], encoding == SAM_PNG_SRGB && i % c != 3);
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
    if ((st = check_size(w, h, channels, 1, path, err)) != SAM_OK)
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
    if ((st = sam_image_create(image, w, h, c, err)) != SAM_OK) {
        free(raw);
        return sam_fail(err, st, "%s: out of memory for %u x %u pixels", path, w, h);
    }
    size_t count = (size_t)w * h * c;
    if (bits == 8) {
        float table[256];
        for (int v = 0; v < 256; ++v)
            table[v] = encoding == SAM_PNG_SRGB ? sam_srgb_to_linear(v / 255.0f) : v / 255.0f;
        for (size_t i = 0; i < count; ++i)
            image->pixels[i] = i % c == 3 ? raw[i] / 255.0f : table[raw[i]];
    } else {
        for (size_t i = 0; i < count; ++i) {
            float v = (float)((raw[2 * i] << 8) | raw[2 * i + 1]) / 65535.0f;
            image->pixels[i] = encoding == SAM_PNG_SRGB && i % c != 3 ? sam_srgb_to_linear(v) : v;
        }
    }
    free(raw);
    return SAM_OK;
}

/* ------------------------------------------------------------------------ */
/* Display: tonemapping and 8-bit comparison                                 */

/* `curve` at x. No light (negative, NaN) is black. Both curves are 1 long
 * before their polynomials overflow (ACES clamps from x ~= 7.25, Reinhard
 * rounds to 1 in float from 2^24), so large values and +inf give 1
 * directly instead of inf / inf. */
static float tone_curve(sam_tonemap curve, float x)
{
    if (!(x > 0.0f))
        return 0.0f;
    if (x >= 0x1p24f)
        return 1.0f;
    if (curve == SAM_TONEMAP_REINHARD)
        return x / (1.0f + x);
    float y = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
    return y < 1.0f ? y : 1.0f;
}

sam_status sam_image_tonemap(const sam_image *hdr, sam_tonemap curve, float exposure_ev,
                             const float backdrop[3], sam_image *out, sam_error *err)
{
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image tonemap: NULL output image");
    memset(out, 0, sizeof *out);
    sam_status st = check_image("image tonemap", hdr, err);
    if (st != SAM_OK)
        return st;
    if (curve != SAM_TONEMAP_ACES && curve != SAM_TONEMAP_REINHARD)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image tonemap: unknown curve %d",
                        (int)curve);
    if (!isfinite(exposure_ev))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image tonemap: exposure %g EV is not finite", exposure_ev);
    float back[3] = {0.0f, 0.0f, 0.0f};
    for (int k = 0; backdrop && k < 3; ++k) {
        if (!(backdrop[k] >= 0.0f && backdrop[k] <= 1.0f))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "image tonemap: backdrop[%d] = %g is outside [0, 1]", k, backdrop[k]);
        back[k] = backdrop[k];
    }
    if ((st = sam_image_create(out, hdr->width, hdr->height, 3, err)) != SAM_OK)
        return st;
    const float scale = exp2f(exposure_ev);
    const uint32_t c = hdr->channels;
    const size_t n = (size_t)hdr->width * hdr->height;
    for (size_t i = 0; i < n; ++i) {
        const float *in = hdr->pixels + i * c;
        float *o = out->pixels + i * 3;
        float a = 1.0f;
        if (c == 4)
            a = in[3] > 0.0f ? (in[3] < 1.0f ? in[3] : 1.0f) : 0.0f; /* NaN becomes 0 */
        for (int k = 0; k < 3; ++k)
            o[k] = a * tone_curve(curve, in[k] * scale) + (1.0f - a) * back[k];
    }
    return SAM_OK;
}

sam_status sam_image_write_picture(const sam_image *hdr, const char *exr, const char *png, sam_tonemap curve,
                                   float exposure_ev, sam_error *err)
{
    sam_status st = sam_image_write_exr(exr, hdr, SAM_EXR_FLOAT, err);
    if (st != SAM_OK || !png)
        return st;
    static const float backdrop[3] = {SAM_IMAGE_PICTURE_BACKDROP, SAM_IMAGE_PICTURE_BACKDROP,
                                      SAM_IMAGE_PICTURE_BACKDROP};
    sam_image preview;
    st = sam_image_tonemap(hdr, curve, exposure_ev, backdrop, &preview, err);
    if (st == SAM_OK)
        st = sam_image_write_png(png, &preview, SAM_PNG_SRGB, err);
    sam_image_destroy(&preview);
    return st;
}

/* RMSE of `values` values whose squared errors sum to `sum`, and its PSNR
 * in dB for 8-bit samples; 0 and INFINITY for a zero sum. */
static void rmse_psnr(uint64_t sum, uint64_t values, double *rmse, double *psnr_db)
{
    *rmse = sum ? sqrt((double)sum / (double)values) : 0.0;
    *psnr_db = sum ? 20.0 * log10(255.0 / *rmse) : INFINITY;
}

sam_status sam_image_compare_srgb8(const sam_image *a, const sam_image *b, const sam_image *mask,
                                   sam_image_comparison *out, sam_error *err)
{
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "image compare: NULL result");
    memset(out, 0, sizeof *out);
    sam_status st = check_image("image compare: first image", a, err);
    if (st == SAM_OK)
        st = check_image("image compare: second image", b, err);
    if (st == SAM_OK && mask)
        st = check_image("image compare: mask", mask, err);
    if (st != SAM_OK)
        return st;
    if (a->width != b->width || a->height != b->height)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image compare: the images differ in size: %u x %u and %u x %u pixels",
                        a->width, a->height, b->width, b->height);
    if (mask && (mask->width != a->width || mask->height != a->height))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image compare: the mask is %u x %u pixels, the images %u x %u",
                        mask->width, mask->height, a->width, a->height);

    /* Squared byte differences are integers: summed exactly in 64 bits
     * (at most 2^28 pixels x 3 x 255^2 < 2^46), so the result does not
     * depend on the order of the sum. */
    uint64_t pixels = 0, differing = 0, sum = 0;
    const size_t n = (size_t)a->width * a->height;
    for (size_t i = 0; i < n; ++i) {
        if (mask && !(mask->pixels[i * mask->channels + mask->channels - 1] > 0.0f))
            continue;
        const float *pa = a->pixels + i * a->channels, *pb = b->pixels + i * b->channels;
        uint64_t d2 = 0;
        for (int k = 0; k < 3; ++k) {
            int d = (int)to_byte(pa[k], 1) - (int)to_byte(pb[k], 1);
            d2 += (uint64_t)(d * d);
        }
        ++pixels;
        differing += d2 != 0;
        sum += d2;
    }
    if (pixels == 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "image compare: the mask selects none of the %u x %u pixels (no last "
                        "channel > 0)", mask->width, mask->height);
    out->pixels = pixels;
    out->differing_pixels = differing;
    rmse_psnr(sum, 3 * pixels, &out->rmse, &out->psnr_db);
    rmse_psnr(sum, 3 * differing, &out->rmse_differing, &out->psnr_differing_db);
    return SAM_OK;
}
