#define _POSIX_C_SOURCE 200809L
#include "sam/sam_image.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openexr.h>

#include "sam_image_internal.h"

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
    if ((st = sam_image_check_size((uint64_t)width, (uint64_t)height, out_channels, 1, path, err)) != SAM_OK)
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
    sam_status st = sam_image_check_output(path, image, err);
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
