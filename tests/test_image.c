#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include <cmocka.h>

#include <OpenEXR/openexr.h>
#include <png.h>
#include <zlib.h>

#include "sam/sam_common.h"
#include "sam/sam_image.h"
#include "sam_test.h"

/* ------------------------------------------------------------------------ */
/* helpers                                                                   */

/* Deterministic pseudo-random floats in [lo, hi). */
static float next_random(uint32_t *state, float lo, float hi)
{
    *state = *state * 1664525u + 1013904223u;
    return lo + (hi - lo) * (float)(*state >> 8) / 16777216.0f;
}

static void fill_random(sam_image *img, uint32_t seed, float lo, float hi)
{
    size_t n = (size_t)img->width * img->height * img->channels;
    for (size_t i = 0; i < n; ++i)
        img->pixels[i] = next_random(&seed, lo, hi);
}

static void make_image(sam_image *img, uint32_t w, uint32_t h, uint32_t c)
{
    sam_error err;
    if (sam_image_create(img, w, h, c, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

static uint8_t *read_all(const char *path, size_t *size)
{
    uint8_t *data;
    sam_error err;
    if (sam_read_file(path, &data, size, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return data;
}

/* One channel of a test EXR written through the Core API. */
typedef struct test_channel {
    const char *name;
    exr_pixel_type_t type;
} test_channel;

/* Value of channel k at (x, y) of the test pattern (integers for uint). */
static float pattern(int k, int x, int y, exr_pixel_type_t type)
{
    if (type == EXR_PIXEL_UINT)
        return (float)(k * 1000 + y * 37 + x);
    return 0.25f * (float)(k + 1) + 0.125f * (float)x - 0.0625f * (float)y;
}

/* Writes a single-part EXR with the given channels, storage and data window
 * origin, filled with pattern(). Channel data is planar per channel. */
static void write_test_exr(const char *path, int tiled, exr_compression_t compression, int w,
                           int h, int ox, int oy, const test_channel *chans, int n)
{
    exr_context_t ctxt;
    int part;
    assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, NULL), EXR_ERR_SUCCESS);
    assert_int_equal(exr_add_part(ctxt, "test", tiled ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE,
                                  &part),
                     EXR_ERR_SUCCESS);
    assert_int_equal(exr_initialize_required_attr_simple(ctxt, part, w, h, compression),
                     EXR_ERR_SUCCESS);
    exr_attr_box2i_t dw = {{{{ox, oy}}}, {{{ox + w - 1, oy + h - 1}}}};
    assert_int_equal(exr_set_data_window(ctxt, part, &dw), EXR_ERR_SUCCESS);
    if (tiled)
        assert_int_equal(exr_set_tile_descriptor(ctxt, part, 4, 4, EXR_TILE_ONE_LEVEL,
                                                 EXR_TILE_ROUND_DOWN),
                         EXR_ERR_SUCCESS);
    for (int k = 0; k < n; ++k)
        assert_int_equal(exr_add_channel(ctxt, part, chans[k].name, chans[k].type,
                                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                         EXR_ERR_SUCCESS);
    assert_int_equal(exr_write_header(ctxt), EXR_ERR_SUCCESS);

    /* Planar source data in each channel's user type: float or uint32. */
    uint8_t *planes[8];
    for (int k = 0; k < n; ++k) {
        planes[k] = malloc((size_t)w * h * 4);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) {
                float v = pattern(k, x, y, chans[k].type);
                size_t at = ((size_t)y * w + x) * 4;
                if (chans[k].type == EXR_PIXEL_UINT) {
                    uint32_t u = (uint32_t)v;
                    memcpy(planes[k] + at, &u, 4);
                } else {
                    memcpy(planes[k] + at, &v, 4);
                }
            }
        }
    }
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int ready = 0;
    int32_t lines = 1;
    uint32_t tw = 4, th = 4;
    if (!tiled)
        assert_int_equal(exr_get_scanlines_per_chunk(ctxt, part, &lines), EXR_ERR_SUCCESS);
    int steps_x = tiled ? (w + 3) / 4 : 1, steps_y = tiled ? (h + 3) / 4 : (h + lines - 1) / lines;
    for (int ty = 0; ty < steps_y; ++ty) {
        for (int tx = 0; tx < steps_x; ++tx) {
            exr_chunk_info_t cinfo;
            int x0 = tiled ? tx * (int)tw : 0, y0 = tiled ? ty * (int)th : ty * lines;
            if (tiled)
                assert_int_equal(exr_write_tile_chunk_info(ctxt, part, tx, ty, 0, 0, &cinfo),
                                 EXR_ERR_SUCCESS);
            else
                assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, oy + y0, &cinfo),
                                 EXR_ERR_SUCCESS);
            if (ready)
                assert_int_equal(exr_encoding_update(ctxt, part, &cinfo, &enc), EXR_ERR_SUCCESS);
            else
                assert_int_equal(exr_encoding_initialize(ctxt, part, &cinfo, &enc),
                                 EXR_ERR_SUCCESS);
            ready = 1;
            for (int i = 0; i < enc.channel_count; ++i) {
                int k = 0;
                while (strcmp(enc.channels[i].channel_name, chans[k].name) != 0)
                    ++k;
                enc.channels[i].encode_from_ptr = planes[k] + ((size_t)y0 * w + x0) * 4;
                enc.channels[i].user_pixel_stride = 4;
                enc.channels[i].user_line_stride = w * 4;
                enc.channels[i].user_bytes_per_element = 4;
                enc.channels[i].user_data_type =
                    chans[k].type == EXR_PIXEL_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
            }
            assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &enc),
                             EXR_ERR_SUCCESS);
            assert_int_equal(exr_encoding_run(ctxt, part, &enc), EXR_ERR_SUCCESS);
        }
    }
    exr_encoding_destroy(ctxt, &enc);
    assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);
    for (int k = 0; k < n; ++k)
        free(planes[k]);
}

/* Asserts that every proper prefix of `path`'s bytes fails to load. */
static void check_truncations(const char *path, const char *prefix_name, int png)
{
    size_t size;
    uint8_t *data = read_all(path, &size);
    char cut[512];
    sam_test_tmp_path(cut, sizeof cut, prefix_name);
    for (size_t len = 0; len < size; ++len) {
        sam_test_write_file(cut, data, len);
        sam_image img;
        sam_error err;
        sam_status st = png ? sam_image_read_png(cut, &img, SAM_PNG_SRGB, &err)
                            : sam_image_read_exr(cut, &img, &err);
        if (st == SAM_OK)
            fail_msg("prefix of %zu of %zu bytes of %s loaded", len, size, path);
        assert_null(img.pixels);
        assert_non_null(strstr(err.message, prefix_name));
    }
    free(data);
}

/* ------------------------------------------------------------------------ */
/* image basics and sRGB                                                     */

static void test_create_validates(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_create(&img, 0, 4, 3, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "0 x 4"));
    assert_int_equal(sam_image_create(&img, 4, 4, 5, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "5 channels"));
    assert_int_equal(sam_image_create(&img, 1u << 15, (1u << 13) + 1, 3, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "32768 x 8193"));
    assert_null(img.pixels);
    assert_int_equal(sam_image_create(&img, UINT32_MAX, UINT32_MAX, 4, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_image_create(&img, 2, 3, 4, &err), SAM_OK);
    assert_int_equal(img.width * img.height * img.channels, 24);
    for (int i = 0; i < 24; ++i)
        assert_true(img.pixels[i] == 0.0f);
    sam_image_destroy(&img);
    assert_null(img.pixels);
    sam_image_destroy(&img);
    sam_image_destroy(NULL);
}

static void test_srgb_transfer(void **state)
{
    (void)state;
    assert_int_equal((int)(sam_linear_to_srgb(0.5f) * 255.0f + 0.5f), 188);
    assert_float_equal(sam_linear_to_srgb(0.2140411f), 0.5f, 1e-5f);
    assert_float_equal(sam_linear_to_srgb(0.0f), 0.0f, 0.0f);
    assert_float_equal(sam_linear_to_srgb(1.0f), 1.0f, 1e-6f);
    assert_float_equal(sam_srgb_to_linear(1.0f), 1.0f, 1e-6f);
    assert_float_equal(sam_srgb_to_linear(188.0f / 255.0f), 0.5029f, 1e-4f);
    /* The two pieces meet at the threshold, and the functions are inverses. */
    assert_float_equal(sam_linear_to_srgb(0.0031308f), 0.04045f, 1e-6f);
    for (int i = 0; i <= 1000; ++i) {
        float x = (float)i / 1000.0f;
        assert_float_equal(sam_srgb_to_linear(sam_linear_to_srgb(x)), x, 2e-6f);
    }
}

/* ------------------------------------------------------------------------ */
/* EXR                                                                       */

static void exr_round_trip(sam_exr_type type, uint32_t channels, const char *name)
{
    char path[512];
    sam_test_tmp_path(path, sizeof path, name);
    sam_image src, back;
    sam_error err;
    make_image(&src, 37, 21, channels); /* not a multiple of ZIP's 16-line chunks */
    fill_random(&src, 7u + channels, -4.0f, 60.0f);
    src.pixels[0] = 1e-5f;  /* a half subnormal */
    src.pixels[1] = -0.0f;
    assert_int_equal(sam_image_write_exr(path, &src, type, &err), SAM_OK);
    assert_int_equal(sam_image_read_exr(path, &back, &err), SAM_OK);
    assert_int_equal(back.width, 37);
    assert_int_equal(back.height, 21);
    assert_int_equal(back.channels, channels);
    size_t n = (size_t)37 * 21 * channels;
    float worst = 0.0f;
    for (size_t i = 0; i < n; ++i) {
        float a = src.pixels[i], b = back.pixels[i];
        if (type == SAM_EXR_FLOAT) {
            assert_memory_equal(&a, &b, sizeof a);
        } else {
            /* half: 11 significant bits; subnormals are spaced 2^-24 */
            float tol = fabsf(a) * 0x1p-11f + 0x1p-24f;
            if (fabsf(a - b) > tol)
                fail_msg("pixel value %zu: wrote %g read %g", i, a, b);
            if (fabsf(a) > 1e-3f && fabsf(a - b) / fabsf(a) > worst)
                worst = fabsf(a - b) / fabsf(a);
        }
    }
    if (type == SAM_EXR_HALF)
        assert_true(worst > 0.0f && worst <= 0x1p-11f);

    /* The file is what the contract says: one scanline part, ZIP, the type. */
    exr_context_t ctxt;
    assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);
    exr_storage_t storage;
    exr_compression_t compression;
    const exr_attr_chlist_t *list;
    int count;
    assert_int_equal(exr_get_count(ctxt, &count), EXR_ERR_SUCCESS);
    assert_int_equal(count, 1);
    assert_int_equal(exr_get_storage(ctxt, 0, &storage), EXR_ERR_SUCCESS);
    assert_int_equal(storage, EXR_STORAGE_SCANLINE);
    assert_int_equal(exr_get_compression(ctxt, 0, &compression), EXR_ERR_SUCCESS);
    assert_int_equal(compression, EXR_COMPRESSION_ZIP);
    assert_int_equal(exr_get_channels(ctxt, 0, &list), EXR_ERR_SUCCESS);
    assert_int_equal(list->num_channels, (int)channels);
    for (int k = 0; k < list->num_channels; ++k)
        assert_int_equal(list->entries[k].pixel_type,
                         type == SAM_EXR_HALF ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT);
    exr_finish(&ctxt);
    assert_int_equal(sam_test_count_temp_files(name), 0);
    sam_image_destroy(&src);
    sam_image_destroy(&back);
}

static void test_exr_round_trip_half_rgb(void **state)
{
    (void)state;
    exr_round_trip(SAM_EXR_HALF, 3, "rt_half_rgb.exr");
}

static void test_exr_round_trip_half_rgba(void **state)
{
    (void)state;
    exr_round_trip(SAM_EXR_HALF, 4, "rt_half_rgba.exr");
}

static void test_exr_round_trip_float_rgb(void **state)
{
    (void)state;
    exr_round_trip(SAM_EXR_FLOAT, 3, "rt_float_rgb.exr");
}

static void test_exr_round_trip_float_rgba(void **state)
{
    (void)state;
    exr_round_trip(SAM_EXR_FLOAT, 4, "rt_float_rgba.exr");
}

/* Checks pixels of an image read from write_test_exr's pattern; `src` maps
 * output channel -> test channel index. */
static void check_pattern(const sam_image *img, const int *src, const exr_pixel_type_t *types)
{
    for (uint32_t y = 0; y < img->height; ++y) {
        for (uint32_t x = 0; x < img->width; ++x) {
            for (uint32_t c = 0; c < img->channels; ++c) {
                float want = pattern(src[c], (int)x, (int)y, types[c]);
                float got = img->pixels[((size_t)y * img->width + x) * img->channels + c];
                if (got != want)
                    fail_msg("(%u, %u) channel %u: expected %g, found %g", x, y, c, want, got);
            }
        }
    }
}

static void test_exr_y_only_is_replicated(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "y_only.exr");
    const test_channel chans[] = {{"Y", EXR_PIXEL_HALF}};
    write_test_exr(path, 0, EXR_COMPRESSION_ZIP, 9, 35, 3, -5, chans, 1);
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_read_exr(path, &img, &err), SAM_OK);
    assert_int_equal(img.width, 9);
    assert_int_equal(img.height, 35);
    assert_int_equal(img.channels, 3);
    const int src[3] = {0, 0, 0};
    const exr_pixel_type_t types[3] = {EXR_PIXEL_HALF, EXR_PIXEL_HALF, EXR_PIXEL_HALF};
    check_pattern(&img, src, types); /* pattern values are exact in half */
    sam_image_destroy(&img);

    /* Y with A gives RGBA. */
    const test_channel ya[] = {{"Y", EXR_PIXEL_FLOAT}, {"A", EXR_PIXEL_HALF}};
    write_test_exr(path, 0, EXR_COMPRESSION_NONE, 5, 4, 0, 0, ya, 2);
    assert_int_equal(sam_image_read_exr(path, &img, &err), SAM_OK);
    assert_int_equal(img.channels, 4);
    const int src4[4] = {0, 0, 0, 1};
    const exr_pixel_type_t types4[4] = {EXR_PIXEL_FLOAT, EXR_PIXEL_FLOAT, EXR_PIXEL_FLOAT,
                                        EXR_PIXEL_HALF};
    check_pattern(&img, src4, types4);
    sam_image_destroy(&img);
}

static void test_exr_tiled_any_channel_order(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "tiled.exr");
    /* 10 x 7 leaves partial tiles on the right and bottom edges. */
    const test_channel chans[] = {{"B", EXR_PIXEL_FLOAT},
                                  {"A", EXR_PIXEL_HALF},
                                  {"R", EXR_PIXEL_HALF},
                                  {"G", EXR_PIXEL_FLOAT},
                                  {"Z", EXR_PIXEL_FLOAT}};
    const exr_compression_t methods[] = {EXR_COMPRESSION_NONE, EXR_COMPRESSION_PIZ,
                                         EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_RLE};
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
        write_test_exr(path, 1, methods[m], 10, 7, -2, 11, chans, 5);
        sam_image img;
        sam_error err;
        if (sam_image_read_exr(path, &img, &err) != SAM_OK)
            fail_msg("compression %d: %s", (int)methods[m], err.message);
        assert_int_equal(img.width, 10);
        assert_int_equal(img.height, 7);
        assert_int_equal(img.channels, 4);
        const int src[4] = {2, 3, 0, 1};
        const exr_pixel_type_t types[4] = {EXR_PIXEL_HALF, EXR_PIXEL_FLOAT, EXR_PIXEL_FLOAT,
                                           EXR_PIXEL_HALF};
        check_pattern(&img, src, types);
        sam_image_destroy(&img);
    }
}

/* Channel sets that take different decoding paths in the Core library:
 * uncompressed direct reads, half -> float conversion of 3 and 4 channels
 * (with and without an unused channel), uint conversion. */
static void test_exr_channel_layouts(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "layouts.exr");
    typedef struct layout {
        test_channel chans[4];
        int n;
        exr_compression_t compression;
        uint32_t out_channels;
        int src[4]; /* test channel feeding each output channel */
    } layout;
    const layout layouts[] = {
        {{{"R", EXR_PIXEL_HALF}, {"G", EXR_PIXEL_HALF}, {"B", EXR_PIXEL_HALF}, {"Z", EXR_PIXEL_HALF}},
         4, EXR_COMPRESSION_ZIP, 3, {0, 1, 2, 0}},
        {{{"R", EXR_PIXEL_HALF}, {"G", EXR_PIXEL_HALF}, {"B", EXR_PIXEL_HALF}, {"A", EXR_PIXEL_HALF}},
         4, EXR_COMPRESSION_NONE, 4, {0, 1, 2, 3}},
        {{{"B", EXR_PIXEL_FLOAT}, {"G", EXR_PIXEL_FLOAT}, {"R", EXR_PIXEL_FLOAT}}, 3,
         EXR_COMPRESSION_NONE, 3, {2, 1, 0, 0}},
        {{{"R", EXR_PIXEL_UINT}, {"G", EXR_PIXEL_UINT}, {"B", EXR_PIXEL_UINT}}, 3,
         EXR_COMPRESSION_RLE, 3, {0, 1, 2, 0}},
        {{{"Y", EXR_PIXEL_HALF}, {"Z", EXR_PIXEL_FLOAT}, {"A", EXR_PIXEL_HALF}}, 3,
         EXR_COMPRESSION_ZIPS, 4, {0, 0, 0, 2}},
    };
    for (size_t i = 0; i < sizeof layouts / sizeof layouts[0]; ++i) {
        const layout *l = &layouts[i];
        write_test_exr(path, 0, l->compression, 7, 19, 0, 0, l->chans, l->n);
        sam_image img;
        sam_error err;
        if (sam_image_read_exr(path, &img, &err) != SAM_OK)
            fail_msg("layout %zu: %s", i, err.message);
        assert_int_equal(img.channels, l->out_channels);
        exr_pixel_type_t types[4];
        for (int c = 0; c < 4; ++c)
            types[c] = l->chans[l->src[c]].type;
        check_pattern(&img, l->src, types);
        sam_image_destroy(&img);
    }
}

static void test_exr_without_color_channels_names_them(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "env.exr");
    const test_channel chans[] = {{"Z", EXR_PIXEL_FLOAT}, {"N.x", EXR_PIXEL_HALF}};
    write_test_exr(path, 0, EXR_COMPRESSION_NONE, 4, 4, 0, 0, chans, 2);
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_read_exr(path, &img, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "env.exr: no R,G,B or Y channels (found: N.x, Z)"));
    assert_null(img.pixels);

    /* R and G without B is not a colour image either. */
    const test_channel rg[] = {{"R", EXR_PIXEL_FLOAT}, {"G", EXR_PIXEL_FLOAT}};
    write_test_exr(path, 0, EXR_COMPRESSION_NONE, 4, 4, 0, 0, rg, 2);
    assert_int_equal(sam_image_read_exr(path, &img, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "(found: G, R)"));
}

static void test_exr_read_errors(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_read_exr("/nonexistent/env.exr", &img, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/env.exr"));
    assert_null(img.pixels);
    assert_int_equal(sam_image_read_exr(NULL, &img, &err), SAM_ERR_INVALID_ARGUMENT);

    char path[512];
    sam_test_tmp_path(path, sizeof path, "not_an.exr");
    sam_test_write_text(path, "this is a text file, not an image\n");
    assert_int_equal(sam_image_read_exr(path, &img, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "not_an.exr"));
    assert_null(img.pixels);

    /* A PNG is not an EXR. */
    sam_image small;
    make_image(&small, 2, 2, 3);
    sam_test_tmp_path(path, sizeof path, "png_as.exr");
    assert_int_equal(sam_image_write_png(path, &small, SAM_PNG_SRGB, &err), SAM_OK);
    assert_int_equal(sam_image_read_exr(path, &img, &err), SAM_ERR_FORMAT);
    sam_image_destroy(&small);
}

static void test_exr_huge_data_window_is_refused(void **state)
{
    (void)state;
    /* A valid small file whose header is then edited to claim 20000 x 20000
     * pixels: the size check must come before any allocation. */
    char path[512];
    sam_test_tmp_path(path, sizeof path, "huge.exr");
    sam_image img;
    sam_error err;
    make_image(&img, 4, 4, 3);
    assert_int_equal(sam_image_write_exr(path, &img, SAM_EXR_HALF, &err), SAM_OK);
    sam_image_destroy(&img);
    size_t size;
    uint8_t *data = read_all(path, &size);
    static const char key[] = "dataWindow\0box2i\0";
    uint8_t *at = NULL;
    for (size_t i = 0; i + sizeof key - 1 <= size && !at; ++i)
        if (memcmp(data + i, key, sizeof key - 1) == 0)
            at = data + i + sizeof key - 1;
    assert_non_null(at);
    const int32_t box[4] = {0, 0, 19999, 19999}; /* after the 4-byte attribute size */
    memcpy(at + 4, box, sizeof box);                /* little-endian host, as the file */
    sam_test_write_file(path, data, size);
    free(data);
    assert_int_equal(sam_image_read_exr(path, &img, &err), SAM_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "huge.exr: 20000 x 20000 pixels is more than the limit"));
    assert_null(img.pixels);
}

static void test_exr_truncated_files_fail_cleanly(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "small.exr");
    sam_image img;
    sam_error err;
    make_image(&img, 5, 20, 4);
    fill_random(&img, 3, 0.0f, 2.0f);
    assert_int_equal(sam_image_write_exr(path, &img, SAM_EXR_HALF, &err), SAM_OK);
    sam_image_destroy(&img);
    check_truncations(path, "small_cut.exr", 0);

    const test_channel chans[] = {{"R", EXR_PIXEL_HALF}, {"G", EXR_PIXEL_HALF},
                                  {"B", EXR_PIXEL_HALF}};
    sam_test_tmp_path(path, sizeof path, "small_tiled.exr");
    write_test_exr(path, 1, EXR_COMPRESSION_PIZ, 6, 5, 0, 0, chans, 3);
    check_truncations(path, "small_tiled_cut.exr", 0);
}

/* ------------------------------------------------------------------------ */
/* PNG                                                                       */

static void test_png_round_trip_linear(void **state)
{
    (void)state;
    for (uint32_t c = 3; c <= 4; ++c) {
        char path[512];
        sam_test_tmp_path(path, sizeof path, c == 3 ? "rt_rgb.png" : "rt_rgba.png");
        sam_image src, back;
        sam_error err;
        make_image(&src, 23, 17, c);
        uint32_t seed = 11;
        size_t n = (size_t)23 * 17 * c;
        for (size_t i = 0; i < n; ++i)
            src.pixels[i] = (float)((int)next_random(&seed, 0.0f, 256.0f)) / 255.0f;
        assert_int_equal(sam_image_write_png(path, &src, SAM_PNG_LINEAR, &err), SAM_OK);
        assert_int_equal(sam_image_read_png(path, &back, SAM_PNG_LINEAR, &err), SAM_OK);
        assert_int_equal(back.width, 23);
        assert_int_equal(back.height, 17);
        assert_int_equal(back.channels, c);
        for (size_t i = 0; i < n; ++i)
            assert_float_equal(back.pixels[i], src.pixels[i], 1e-6f);
        sam_image_destroy(&src);
        sam_image_destroy(&back);
    }
}

static void test_png_round_trip_srgb(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "rt_srgb.png");
    sam_image src, back;
    sam_error err;
    make_image(&src, 31, 9, 4);
    fill_random(&src, 5, 0.0f, 1.0f);
    assert_int_equal(sam_image_write_png(path, &src, SAM_PNG_SRGB, &err), SAM_OK);
    assert_int_equal(sam_image_read_png(path, &back, SAM_PNG_SRGB, &err), SAM_OK);
    size_t n = (size_t)31 * 9 * 4;
    for (size_t i = 0; i < n; ++i) {
        if (i % 4 == 3) {
            assert_float_equal(back.pixels[i], src.pixels[i], 0.5f / 255.0f + 1e-6f);
        } else {
            /* Quantisation happens in the encoded domain: half a step there. */
            assert_float_equal(sam_linear_to_srgb(back.pixels[i]), sam_linear_to_srgb(src.pixels[i]),
                               0.5f / 255.0f + 1e-5f);
        }
    }
    sam_image_destroy(&src);
    sam_image_destroy(&back);
}

static void test_png_srgb_known_values_clamp_and_nan(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "known.png");
    sam_image src, back;
    sam_error err;
    make_image(&src, 3, 2, 4);
    const float values[24] = {0.5f, 0.0f,  1.0f,  0.5f,  0.2141f, -1.0f, 7.0f,  NAN,
                              NAN,  1e-4f, 0.04f, 1.0f,  0.0031308f, 0.5f, 0.5f, 0.0f,
                              INFINITY, -INFINITY, 0.25f, 2.0f, 0.18f, 0.18f, 0.18f, 1.0f};
    memcpy(src.pixels, values, sizeof values);
    assert_int_equal(sam_image_write_png(path, &src, SAM_PNG_SRGB, &err), SAM_OK);
    /* Read the stored bytes back unchanged. */
    assert_int_equal(sam_image_read_png(path, &back, SAM_PNG_LINEAR, &err), SAM_OK);
    const int bytes[24] = {188, 0, 255, 128, 128, 0, 255, 0, 0, 0, 56, 255,
                           10, 188, 188, 0, 255, 0, 137, 255, 118, 118, 118, 255};
    for (int i = 0; i < 24; ++i) {
        int got = (int)(back.pixels[i] * 255.0f + 0.5f);
        if (got != bytes[i])
            fail_msg("value %d (%g): expected byte %d, found %d", i, values[i], bytes[i], got);
    }
    sam_image_destroy(&back);

    /* The file says it is sRGB. */
    size_t size;
    uint8_t *data = read_all(path, &size);
    int has_srgb = 0;
    for (size_t i = 0; i + 4 <= size; ++i)
        has_srgb |= memcmp(data + i, "sRGB", 4) == 0;
    assert_true(has_srgb);
    free(data);

    /* Decoding gives linear values back. */
    assert_int_equal(sam_image_read_png(path, &back, SAM_PNG_SRGB, &err), SAM_OK);
    assert_float_equal(back.pixels[0], 0.5029f, 1e-4f);
    assert_float_equal(back.pixels[3], 128.0f / 255.0f, 1e-6f); /* alpha stays linear */
    sam_image_destroy(&back);
    sam_image_destroy(&src);
}

/* Writes a PNG of any colour type with libpng directly; `rows` holds
 * packed sample data as libpng expects for that type and depth. */
static void write_raw_png(const char *path, uint32_t w, uint32_t h, int color_type, int depth,
                          int interlace, const uint8_t *data, size_t row_bytes,
                          const png_color *palette, int palette_size, const uint8_t *trns,
                          int trns_count)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    assert_non_null(info);
    if (setjmp(png_jmpbuf(png)))
        fail_msg("libpng failed writing %s", path);
    png_init_io(png, fp);
    png_set_IHDR(png, info, w, h, depth, color_type, interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (palette)
        png_set_PLTE(png, info, palette, palette_size);
    if (trns)
        png_set_tRNS(png, info, trns, trns_count, NULL);
    png_write_info(png, info);
    png_bytep rows[64];
    for (uint32_t y = 0; y < h; ++y)
        rows[y] = (png_bytep)(data + row_bytes * y);
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

static void test_png_reads_every_color_type(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "types.png");
    sam_image img;
    sam_error err;

    /* 8-bit grey -> equal RGB */
    const uint8_t grey[6] = {0, 51, 102, 153, 204, 255};
    write_raw_png(path, 3, 2, PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, grey, 3, NULL, 0, NULL,
                  0);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    assert_int_equal(img.channels, 3);
    for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 3; ++c)
            assert_float_equal(img.pixels[i * 3 + c], grey[i] / 255.0f, 1e-6f);
    sam_image_destroy(&img);

    /* 1-bit grey, 5 pixels wide: 10110 */
    const uint8_t bits[1] = {0xB0};
    write_raw_png(path, 5, 1, PNG_COLOR_TYPE_GRAY, 1, PNG_INTERLACE_NONE, bits, 1, NULL, 0, NULL,
                  0);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_SRGB, &err), SAM_OK);
    const float want_bits[5] = {1, 0, 1, 1, 0};
    for (int i = 0; i < 5; ++i)
        assert_float_equal(img.pixels[i * 3 + 1], want_bits[i], 1e-6f);
    sam_image_destroy(&img);

    /* grey + alpha -> RGBA */
    const uint8_t ga[4] = {10, 20, 30, 40};
    write_raw_png(path, 2, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, PNG_INTERLACE_NONE, ga, 4, NULL, 0,
                  NULL, 0);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    assert_int_equal(img.channels, 4);
    assert_float_equal(img.pixels[4 + 2], 30 / 255.0f, 1e-6f);
    assert_float_equal(img.pixels[4 + 3], 40 / 255.0f, 1e-6f);
    sam_image_destroy(&img);

    /* 16-bit RGB, big-endian samples */
    const uint8_t rgb16[12] = {0x00, 0x00, 0x80, 0x00, 0xff, 0xff, 0x12, 0x34, 0xab, 0xcd, 0x00, 0x01};
    write_raw_png(path, 2, 1, PNG_COLOR_TYPE_RGB, 16, PNG_INTERLACE_NONE, rgb16, 12, NULL, 0, NULL,
                  0);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    assert_int_equal(img.channels, 3);
    const float want16[6] = {0.0f, 0x8000 / 65535.0f, 1.0f, 0x1234 / 65535.0f, 0xabcd / 65535.0f,
                             1 / 65535.0f};
    for (int i = 0; i < 6; ++i)
        assert_float_equal(img.pixels[i], want16[i], 1e-7f);
    sam_image_destroy(&img);

    /* 4-bit palette with a transparent entry -> RGBA */
    const png_color palette[3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
    const uint8_t trns[3] = {255, 0, 128};
    const uint8_t indices[2] = {0x01, 0x20}; /* 0 1 2 0 */
    write_raw_png(path, 4, 1, PNG_COLOR_TYPE_PALETTE, 4, PNG_INTERLACE_NONE, indices, 2, palette,
                  3, trns, 3);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    assert_int_equal(img.channels, 4);
    const float want_pal[16] = {1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 128 / 255.0f, 1, 0, 0, 1};
    for (int i = 0; i < 16; ++i)
        assert_float_equal(img.pixels[i], want_pal[i], 1e-6f);
    sam_image_destroy(&img);

    /* Adam7-interlaced 8-bit RGB */
    uint8_t rgb[9 * 10 * 3];
    for (size_t i = 0; i < sizeof rgb; ++i)
        rgb[i] = (uint8_t)(i * 7);
    write_raw_png(path, 9, 10, PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_ADAM7, rgb, 27, NULL, 0, NULL,
                  0);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    for (size_t i = 0; i < sizeof rgb; ++i)
        assert_float_equal(img.pixels[i], rgb[i] / 255.0f, 1e-6f);
    sam_image_destroy(&img);
}

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24), p[1] = (uint8_t)(v >> 16), p[2] = (uint8_t)(v >> 8), p[3] = (uint8_t)v;
}

/* Appends a chunk with a correct CRC at `p`; returns the bytes written. */
static size_t put_chunk(uint8_t *p, const char *tag, const uint8_t *data, uint32_t len)
{
    put_be32(p, len);
    memcpy(p + 4, tag, 4);
    if (len)
        memcpy(p + 8, data, len);
    put_be32(p + 8 + len, (uint32_t)crc32(0, p + 4, 4 + len));
    return 12 + len;
}

static void test_png_huge_header_is_refused(void **state)
{
    (void)state;
    uint8_t file[128];
    memcpy(file, "\x89PNG\r\n\x1a\n", 8);
    uint8_t ihdr[13] = {0};
    put_be32(ihdr, 20000);
    put_be32(ihdr + 4, 20000);
    ihdr[8] = 8; /* depth */
    ihdr[9] = 2; /* RGB */
    size_t n = 8 + put_chunk(file + 8, "IHDR", ihdr, 13);
    n += put_chunk(file + n, "IDAT", NULL, 0);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "huge.png");
    sam_test_write_file(path, file, n);
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_SRGB, &err), SAM_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "huge.png: 20000 x 20000 pixels is more than the limit"));
    assert_null(img.pixels);
}

static void test_png_read_errors(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_read_png("/nonexistent/a.png", &img, SAM_PNG_SRGB, &err),
                     SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent/a.png"));
    char path[512];
    sam_test_tmp_path(path, sizeof path, "text.png");
    sam_test_write_text(path, "not a png at all");
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_SRGB, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "text.png: not a PNG file"));
    assert_null(img.pixels);

    /* An EXR is not a PNG. */
    sam_image small;
    make_image(&small, 2, 2, 3);
    sam_test_tmp_path(path, sizeof path, "exr_as.png");
    assert_int_equal(sam_image_write_exr(path, &small, SAM_EXR_FLOAT, &err), SAM_OK);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_SRGB, &err), SAM_ERR_FORMAT);

    /* A corrupt critical chunk is reported with libpng's reason. */
    sam_test_tmp_path(path, sizeof path, "crc.png");
    assert_int_equal(sam_image_write_png(path, &small, SAM_PNG_LINEAR, &err), SAM_OK);
    size_t size;
    uint8_t *data = read_all(path, &size);
    data[16] ^= 0x01; /* inside IHDR's width field: its CRC no longer matches */
    sam_test_write_file(path, data, size);
    free(data);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_SRGB, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "crc.png: "));
    assert_non_null(strstr(err.message, "CRC"));
    sam_image_destroy(&small);
}

static void test_png_truncated_files_fail_cleanly(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "small.png");
    sam_image img;
    sam_error err;
    make_image(&img, 6, 5, 4);
    fill_random(&img, 9, 0.0f, 1.0f);
    assert_int_equal(sam_image_write_png(path, &img, SAM_PNG_SRGB, &err), SAM_OK);
    sam_image_destroy(&img);
    check_truncations(path, "small_cut.png", 1);
}

/* ------------------------------------------------------------------------ */
/* atomic output                                                             */

/* Writes with the process's file size capped at `limit` bytes, so the write
 * fails part way through; restores the limit afterwards. */
static sam_status write_capped(const char *path, const sam_image *img, int png, rlim_t limit,
                               sam_error *err)
{
    struct rlimit old, capped;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    capped = old;
    capped.rlim_cur = limit;
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &capped), 0);
    sam_status st = png ? sam_image_write_png(path, img, SAM_PNG_SRGB, err)
                        : sam_image_write_exr(path, img, SAM_EXR_FLOAT, err);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, old_handler);
    return st;
}

static void test_failed_writes_leave_no_file(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    make_image(&img, 128, 128, 4);
    fill_random(&img, 21, 0.0f, 1.0f); /* noise: does not compress below the cap */
    const char *names[2] = {"capped.exr", "capped.png"};
    for (int png = 0; png <= 1; ++png) {
        char path[512];
        sam_test_tmp_path(path, sizeof path, names[png]);
        remove(path);
        assert_int_equal(write_capped(path, &img, png, 4096, &err), SAM_ERR_IO);
        assert_non_null(strstr(err.message, names[png]));
        assert_false(sam_test_file_exists(path));
        assert_int_equal(sam_test_count_temp_files(names[png]), 0);

        /* An existing file survives a failed write untouched. */
        sam_test_write_text(path, "previous contents");
        assert_int_equal(write_capped(path, &img, png, 4096, &err), SAM_ERR_IO);
        size_t size;
        uint8_t *data = read_all(path, &size);
        assert_string_equal((char *)data, "previous contents");
        free(data);
        assert_int_equal(sam_test_count_temp_files(names[png]), 0);
    }

    /* A missing directory fails before anything is written. */
    assert_int_equal(sam_image_write_exr("/nonexistent-dir/a.exr", &img, SAM_EXR_HALF, &err),
                     SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent-dir/a.exr"));
    assert_int_equal(sam_image_write_png("/nonexistent-dir/a.png", &img, SAM_PNG_SRGB, &err),
                     SAM_ERR_IO);

    /* Invalid images are refused before a file is created. */
    char path[512];
    sam_test_tmp_path(path, sizeof path, "invalid.exr");
    sam_image bad = img;
    bad.channels = 2;
    assert_int_equal(sam_image_write_exr(path, &bad, SAM_EXR_HALF, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    bad = img;
    bad.pixels = NULL;
    assert_int_equal(sam_image_write_png(path, &bad, SAM_PNG_SRGB, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_image_write_exr(path, &img, (sam_exr_type)7, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_false(sam_test_file_exists(path));
    sam_image_destroy(&img);
}

/* ------------------------------------------------------------------------ */
/* Tonemapping                                                               */

/* Tonemaps a single RGB or RGBA pixel and returns its 3 display values. */
static void tonemap_pixel(const float *in, uint32_t channels, sam_tonemap curve, float ev,
                          const float *backdrop, float out[3])
{
    sam_image hdr, ldr;
    sam_error err;
    make_image(&hdr, 1, 1, channels);
    memcpy(hdr.pixels, in, channels * sizeof *in);
    if (sam_image_tonemap(&hdr, curve, ev, backdrop, &ldr, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(ldr.width, 1);
    assert_int_equal(ldr.height, 1);
    assert_int_equal(ldr.channels, 3);
    memcpy(out, ldr.pixels, 3 * sizeof *out);
    sam_image_destroy(&ldr);
    sam_image_destroy(&hdr);
}

static void test_tonemap_curves(void **state)
{
    (void)state;
    float out[3];
    /* ACES (Narkowicz): 1 -> 2.54 / 3.16; 0.18 -> 0.086724 / 0.324932;
     * past x ~= 7.25 the fit exceeds 1 and is clamped. */
    tonemap_pixel((const float[3]){1.0f, 0.18f, 10.0f}, 3, SAM_TONEMAP_ACES, 0.0f, NULL, out);
    assert_float_equal(out[0], 2.54f / 3.16f, 1e-6f);
    assert_float_equal(out[1], 0.086724f / 0.324932f, 1e-6f);
    assert_float_equal(out[2], 1.0f, 0.0f);
    /* Reinhard x / (1 + x). */
    tonemap_pixel((const float[3]){1.0f, 3.0f, 0.25f}, 3, SAM_TONEMAP_REINHARD, 0.0f, NULL, out);
    assert_float_equal(out[0], 0.5f, 1e-7f);
    assert_float_equal(out[1], 0.75f, 1e-7f);
    assert_float_equal(out[2], 0.2f, 1e-7f);

    /* No light, negative light and NaN are black; huge values and +inf are
     * white on both curves (not inf / inf). */
    for (int c = 0; c < 2; ++c) {
        sam_tonemap curve = c ? SAM_TONEMAP_REINHARD : SAM_TONEMAP_ACES;
        tonemap_pixel((const float[3]){0.0f, -0.1f, NAN}, 3, curve, 0.0f, NULL, out);
        for (int k = 0; k < 3; ++k)
            assert_true(out[k] == 0.0f);
        tonemap_pixel((const float[3]){1e30f, 3.4e38f, INFINITY}, 3, curve, 0.0f, NULL, out);
        for (int k = 0; k < 3; ++k)
            assert_true(out[k] == 1.0f);
    }

    /* Exposure multiplies by 2^EV before the curve. */
    tonemap_pixel((const float[3]){0.5f, 4.0f, 0.125f}, 3, SAM_TONEMAP_REINHARD, 1.0f, NULL, out);
    assert_float_equal(out[0], 0.5f, 1e-7f);          /* 1 / 2 */
    assert_float_equal(out[1], 8.0f / 9.0f, 1e-7f);   /* 8 / 9 */
    assert_float_equal(out[2], 0.2f, 1e-7f);          /* 0.25 / 1.25 */
    tonemap_pixel((const float[3]){4.0f, 4.0f, 4.0f}, 3, SAM_TONEMAP_ACES, -2.0f, NULL, out);
    assert_float_equal(out[0], 2.54f / 3.16f, 1e-6f);
}

static void test_tonemap_alpha_over_backdrop(void **state)
{
    (void)state;
    float out[3];
    const float backdrop[3] = {0.2f, 0.4f, 0.0f};
    /* Half covered: 0.5 * curve + 0.5 * backdrop, with curve(1) = 0.5. */
    tonemap_pixel((const float[4]){1.0f, 1.0f, 1.0f, 0.5f}, 4, SAM_TONEMAP_REINHARD, 0.0f,
                  backdrop, out);
    assert_float_equal(out[0], 0.35f, 1e-7f);
    assert_float_equal(out[1], 0.45f, 1e-7f);
    assert_float_equal(out[2], 0.25f, 1e-7f);
    /* Uncovered: the backdrop exactly, whatever the colour. */
    tonemap_pixel((const float[4]){5.0f, NAN, 1.0f, 0.0f}, 4, SAM_TONEMAP_ACES, 0.0f, backdrop,
                  out);
    assert_memory_equal(out, backdrop, sizeof backdrop);
    /* Covered: the curve alone. Alpha is clamped to [0, 1], NaN as 0. */
    tonemap_pixel((const float[4]){3.0f, 1.0f, 0.0f, 1.0f}, 4, SAM_TONEMAP_REINHARD, 0.0f,
                  backdrop, out);
    assert_float_equal(out[0], 0.75f, 1e-7f);
    assert_float_equal(out[1], 0.5f, 1e-7f);
    assert_float_equal(out[2], 0.0f, 0.0f);
    tonemap_pixel((const float[4]){3.0f, 1.0f, 0.0f, 7.0f}, 4, SAM_TONEMAP_REINHARD, 0.0f,
                  backdrop, out);
    assert_float_equal(out[0], 0.75f, 1e-7f);
    tonemap_pixel((const float[4]){3.0f, 1.0f, 0.0f, NAN}, 4, SAM_TONEMAP_REINHARD, 0.0f,
                  backdrop, out);
    assert_memory_equal(out, backdrop, sizeof backdrop);
    /* No backdrop is black. */
    tonemap_pixel((const float[4]){1.0f, 3.0f, 0.0f, 0.5f}, 4, SAM_TONEMAP_REINHARD, 0.0f, NULL,
                  out);
    assert_float_equal(out[0], 0.25f, 1e-7f);
    assert_float_equal(out[1], 0.375f, 1e-7f);
    assert_float_equal(out[2], 0.0f, 0.0f);

    /* Every pixel of a larger image, in place. */
    sam_image hdr, ldr;
    sam_error err;
    make_image(&hdr, 3, 2, 4);
    for (uint32_t i = 0; i < 6; ++i) {
        hdr.pixels[4 * i + 0] = (float)i;
        hdr.pixels[4 * i + 3] = i % 2 ? 1.0f : 0.0f;
    }
    assert_int_equal(sam_image_tonemap(&hdr, SAM_TONEMAP_REINHARD, 0.0f, backdrop, &ldr, &err),
                     SAM_OK);
    for (uint32_t i = 0; i < 6; ++i) {
        float want = i % 2 ? (float)i / (1.0f + (float)i) : backdrop[0];
        assert_float_equal(ldr.pixels[3 * i], want, 1e-7f);
    }
    sam_image_destroy(&ldr);
    sam_image_destroy(&hdr);
}

static void test_tonemap_errors(void **state)
{
    (void)state;
    sam_image hdr, ldr;
    sam_error err;
    make_image(&hdr, 2, 2, 3);
    memset(&ldr, 0x5a, sizeof ldr); /* must be zeroed on failure */
    assert_int_equal(sam_image_tonemap(&hdr, (sam_tonemap)2, 0.0f, NULL, &ldr, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "unknown curve 2"));
    assert_null(ldr.pixels);
    assert_int_equal(ldr.width, 0);
    assert_int_equal(sam_image_tonemap(&hdr, SAM_TONEMAP_ACES, NAN, NULL, &ldr, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "exposure nan EV is not finite"));
    assert_int_equal(sam_image_tonemap(&hdr, SAM_TONEMAP_ACES, INFINITY, NULL, &ldr, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "exposure inf EV"));
    assert_int_equal(sam_image_tonemap(&hdr, SAM_TONEMAP_ACES, 0.0f, (const float[3]){0, 1.5f, 0},
                                       &ldr, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "backdrop[1] = 1.5 is outside [0, 1]"));
    assert_int_equal(sam_image_tonemap(&hdr, SAM_TONEMAP_ACES, 0.0f, (const float[3]){0, 0, NAN},
                                       &ldr, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    sam_image bad = hdr;
    bad.channels = 2;
    assert_int_equal(sam_image_tonemap(&bad, SAM_TONEMAP_ACES, 0.0f, NULL, &ldr, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "2 channels (expected 3 or 4)"));
    assert_int_equal(sam_image_tonemap(NULL, SAM_TONEMAP_ACES, 0.0f, NULL, &ldr, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_image_tonemap(&hdr, SAM_TONEMAP_ACES, 0.0f, NULL, NULL, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_null(ldr.pixels);
    sam_image_destroy(&hdr);
}

/* ------------------------------------------------------------------------ */
/* 8-bit comparison                                                          */

/* Linear values that sam_image_write_png (SAM_PNG_SRGB) stores as these
 * bytes: 0.5 -> 188 and 0.2141 -> 128 are checked against the writer in
 * test_png_srgb_known_values_clamp_and_nan. */
#define BYTE_188 0.5f
#define BYTE_128 0.2141f

static sam_image_comparison compare(const sam_image *a, const sam_image *b, const sam_image *mask)
{
    sam_image_comparison c;
    sam_error err;
    if (sam_image_compare_srgb8(a, b, mask, &c, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return c;
}

static void fill(sam_image *img, float v)
{
    for (size_t i = 0; i < (size_t)img->width * img->height * img->channels; ++i)
        img->pixels[i] = v;
}

/* The comparison tests' starting image: 2 x 2, every value byte 188. */
static void make_grey_2x2(sam_image *img, uint32_t channels)
{
    make_image(img, 2, 2, channels);
    fill(img, BYTE_188);
}

static void test_compare_known_differences(void **state)
{
    (void)state;
    sam_image a, b;
    make_grey_2x2(&a, 3);
    make_grey_2x2(&b, 3);

    /* One channel of one pixel 60 levels off: over 4 pixels x 3 channels
     * rmse = sqrt(60^2 / 12); over the differing pixel, sqrt(60^2 / 3). */
    b.pixels[3 * 2 + 1] = BYTE_128;
    sam_image_comparison c = compare(&a, &b, NULL);
    assert_int_equal(c.pixels, 4);
    assert_int_equal(c.differing_pixels, 1);
    double rmse = sqrt(60.0 * 60.0 / 12.0), rmse_d = sqrt(60.0 * 60.0 / 3.0);
    assert_float_equal(c.rmse, rmse, 1e-9);
    assert_float_equal(c.psnr_db, 20.0 * log10(255.0 / rmse), 1e-9);
    assert_float_equal(c.psnr_db, 23.3596, 1e-4); /* 20 log10(255 / sqrt(300)) */
    assert_float_equal(c.rmse_differing, rmse_d, 1e-9);
    assert_float_equal(c.psnr_differing_db, 20.0 * log10(255.0 / rmse_d), 1e-9);
    /* Symmetric. */
    sam_image_comparison r = compare(&b, &a, NULL);
    assert_memory_equal(&r, &c, sizeof r);

    /* A second pixel off by 255 in two channels: 60^2 + 2 * 255^2. */
    a.pixels[3 * 3 + 1] = 1.0f;
    a.pixels[3 * 3 + 2] = 1.0f;
    b.pixels[3 * 3 + 1] = 0.0f;
    b.pixels[3 * 3 + 2] = 0.0f;
    c = compare(&a, &b, NULL);
    double sum = 60.0 * 60.0 + 2.0 * 255.0 * 255.0;
    assert_int_equal(c.pixels, 4);
    assert_int_equal(c.differing_pixels, 2);
    assert_float_equal(c.rmse, sqrt(sum / 12.0), 1e-9);
    assert_float_equal(c.psnr_db, 20.0 * log10(255.0 / sqrt(sum / 12.0)), 1e-9);
    assert_float_equal(c.rmse_differing, sqrt(sum / 6.0), 1e-9);
    assert_float_equal(c.psnr_differing_db, 20.0 * log10(255.0 / sqrt(sum / 6.0)), 1e-9);

    /* One level: 0 against a value that encodes to byte 1 (0.6 / 255 in sRGB). */
    fill(&a, 0.0f);
    fill(&b, 0.0f);
    b.pixels[0] = 0.6f / 255.0f / 12.92f;
    c = compare(&a, &b, NULL);
    assert_int_equal(c.differing_pixels, 1);
    assert_float_equal(c.rmse, sqrt(1.0 / 12.0), 1e-9);
    assert_float_equal(c.psnr_db, 20.0 * log10(255.0 / sqrt(1.0 / 12.0)), 1e-9);
    sam_image_destroy(&a);
    sam_image_destroy(&b);
}

static void test_compare_identical_in_8_bits(void **state)
{
    (void)state;
    sam_image a, b;
    make_grey_2x2(&a, 4);
    make_grey_2x2(&b, 3);
    /* Float differences that the same byte hides, values the encoder
     * clamps (2 and 1, -1 and 0, NaN and 0), and alpha, which is not
     * compared, all count as equal. */
    b.pixels[0] = 0.5001f;
    a.pixels[4 * 1 + 0] = 2.0f;
    b.pixels[3 * 1 + 0] = 1.0f;
    a.pixels[4 * 2 + 1] = -1.0f;
    b.pixels[3 * 2 + 1] = 0.0f;
    a.pixels[4 * 3 + 2] = NAN;
    b.pixels[3 * 3 + 2] = 0.0f;
    a.pixels[4 * 3 + 3] = 0.25f;
    sam_image_comparison c = compare(&a, &b, NULL);
    assert_int_equal(c.pixels, 4);
    assert_int_equal(c.differing_pixels, 0);
    assert_true(c.rmse == 0.0);
    assert_true(isinf(c.psnr_db) && c.psnr_db > 0);
    assert_true(c.rmse_differing == 0.0);
    assert_true(isinf(c.psnr_differing_db) && c.psnr_differing_db > 0);
    c = compare(&a, &a, NULL);
    assert_int_equal(c.differing_pixels, 0);
    assert_true(isinf(c.psnr_db));
    sam_image_destroy(&a);
    sam_image_destroy(&b);
}

static void test_compare_mask(void **state)
{
    (void)state;
    sam_image a, b, mask;
    make_grey_2x2(&a, 3);
    make_grey_2x2(&b, 3);
    make_image(&mask, 2, 2, 4);
    b.pixels[3 * 1 + 0] = BYTE_128; /* pixel 1 differs by 60 in red */

    /* Alpha 0 at the differing pixel (and -1, NaN count as outside). */
    fill(&mask, 1.0f);
    mask.pixels[4 * 1 + 3] = 0.0f;
    mask.pixels[4 * 2 + 3] = -1.0f;
    sam_image_comparison c = compare(&a, &b, &mask);
    assert_int_equal(c.pixels, 2);
    assert_int_equal(c.differing_pixels, 0);
    assert_true(isinf(c.psnr_db));
    assert_true(isinf(c.psnr_differing_db));

    /* Only the differing pixel and one other: 60^2 over 2 x 3 values. The
     * mask's colour does not matter, only its last channel. */
    fill(&mask, 0.0f);
    mask.pixels[4 * 1 + 3] = 1.0f;
    mask.pixels[4 * 3 + 3] = 0.001f;
    mask.pixels[4 * 0 + 0] = 1.0f;
    mask.pixels[4 * 2 + 3] = NAN;
    c = compare(&a, &b, &mask);
    assert_int_equal(c.pixels, 2);
    assert_int_equal(c.differing_pixels, 1);
    assert_float_equal(c.rmse, sqrt(3600.0 / 6.0), 1e-9);
    assert_float_equal(c.psnr_db, 20.0 * log10(255.0 / sqrt(600.0)), 1e-9);
    assert_float_equal(c.rmse_differing, sqrt(3600.0 / 3.0), 1e-9);

    /* An RGB mask selects by its last channel, blue. */
    sam_image rgb;
    make_image(&rgb, 2, 2, 3);
    rgb.pixels[3 * 1 + 2] = 1.0f;
    rgb.pixels[3 * 0 + 0] = 1.0f; /* red only: not selected */
    c = compare(&a, &b, &rgb);
    assert_int_equal(c.pixels, 1);
    assert_int_equal(c.differing_pixels, 1);
    assert_float_equal(c.rmse, c.rmse_differing, 0.0);

    /* A mask that selects nothing is an error, not a perfect score. */
    fill(&rgb, 0.0f);
    sam_error err;
    assert_int_equal(sam_image_compare_srgb8(&a, &b, &rgb, &c, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "the mask selects none of the 2 x 2 pixels"));
    sam_image_destroy(&rgb);
    sam_image_destroy(&mask);
    sam_image_destroy(&a);
    sam_image_destroy(&b);
}

/* The comparison sees the bytes sam_image_write_png stores: random values
 * (with some out of range) compared directly and through two PNG files. */
static void test_compare_matches_png_bytes(void **state)
{
    (void)state;
    sam_image a, b, pa, pb;
    sam_error err;
    make_image(&a, 17, 9, 4);
    make_image(&b, 17, 9, 3);
    fill_random(&a, 3, -0.1f, 1.1f);
    fill_random(&b, 4, -0.1f, 1.1f);
    for (size_t i = 0; i < 17 * 9; i += 4) {
        for (int k = 0; k < 3; ++k)
            b.pixels[3 * i + k] = a.pixels[4 * i + k]; /* some equal pixels */
    }
    a.pixels[5] = NAN;
    char path_a[512], path_b[512];
    sam_test_tmp_path(path_a, sizeof path_a, "compare_a.png");
    sam_test_tmp_path(path_b, sizeof path_b, "compare_b.png");
    assert_int_equal(sam_image_write_png(path_a, &a, SAM_PNG_SRGB, &err), SAM_OK);
    assert_int_equal(sam_image_write_png(path_b, &b, SAM_PNG_SRGB, &err), SAM_OK);
    assert_int_equal(sam_image_read_png(path_a, &pa, SAM_PNG_LINEAR, &err), SAM_OK);
    assert_int_equal(sam_image_read_png(path_b, &pb, SAM_PNG_LINEAR, &err), SAM_OK);
    uint64_t sum = 0, differing = 0;
    for (size_t i = 0; i < 17 * 9; ++i) {
        uint64_t d2 = 0;
        for (int k = 0; k < 3; ++k) {
            long d = lroundf(pa.pixels[4 * i + k] * 255.0f) -
                     lroundf(pb.pixels[3 * i + k] * 255.0f);
            d2 += (uint64_t)(d * d);
        }
        sum += d2;
        differing += d2 != 0;
    }
    sam_image_comparison c = compare(&a, &b, NULL);
    assert_int_equal(c.pixels, 17 * 9);
    assert_int_equal(c.differing_pixels, differing);
    assert_true(differing > 0 && differing < 17 * 9);
    assert_float_equal(c.rmse, sqrt((double)sum / (3.0 * 17 * 9)), 1e-12);
    assert_float_equal(c.rmse_differing, sqrt((double)sum / (3.0 * (double)differing)), 1e-12);
    sam_image_destroy(&pa);
    sam_image_destroy(&pb);
    sam_image_destroy(&a);
    sam_image_destroy(&b);
}

static void test_compare_errors(void **state)
{
    (void)state;
    sam_image a, b, mask;
    sam_image_comparison c;
    sam_error err;
    make_image(&a, 2, 2, 3);
    make_image(&b, 3, 2, 3);
    make_image(&mask, 2, 5, 4);
    memset(&c, 0x5a, sizeof c); /* must be zeroed on failure */
    assert_int_equal(sam_image_compare_srgb8(&a, &b, NULL, &c, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "the images differ in size: 2 x 2 and 3 x 2 pixels"));
    assert_int_equal(c.pixels, 0);
    assert_true(c.rmse == 0.0);
    assert_int_equal(sam_image_compare_srgb8(&a, &a, &mask, &c, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "the mask is 2 x 5 pixels, the images 2 x 2"));
    sam_image bad = a;
    bad.channels = 2;
    assert_int_equal(sam_image_compare_srgb8(&a, &bad, NULL, &c, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "second image: 2 channels (expected 3 or 4)"));
    assert_int_equal(sam_image_compare_srgb8(&a, &a, &bad, &c, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "mask: 2 channels"));
    assert_int_equal(sam_image_compare_srgb8(NULL, &a, NULL, &c, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "first image: no image given"));
    assert_int_equal(sam_image_compare_srgb8(&a, &a, NULL, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    sam_image_destroy(&mask);
    sam_image_destroy(&a);
    sam_image_destroy(&b);
}

/* Text: drawn pixels lie inside the reported width and the font's height,
 * scale 2 covers four times the pixels of scale 1, text past an edge is
 * clipped, and bad arguments draw nothing. */
static void test_draw_text(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    const float ink[3] = {1, 0.5f, 0.25f};
    size_t covered[2] = {0, 0};
    for (int scale = 1; scale <= 2; scale++) {
        assert_int_equal(sam_image_create(&img, 200, 60, 4, &err), SAM_OK);
        const int w = sam_image_draw_text(&img, 10, 5, scale, ink, "SAM 1.0");
        assert_int_equal(w, sam_image_text_width("SAM 1.0", scale));
        assert_true(w > 20 * scale && w < 60 * scale);
        for (uint32_t y = 0; y < img.height; y++)
            for (uint32_t x = 0; x < img.width; x++) {
                const float *p = img.pixels + 4 * ((size_t)y * img.width + x);
                if (p[0] == 0)
                    continue;
                covered[scale - 1]++;
                assert_true(p[0] == 1.0f && p[1] == 0.5f && p[2] == 0.25f && p[3] == 0.0f);
                assert_true((int)x >= 10 && (int)x < 10 + w && (int)y >= 5 && (int)y < 5 + 14 * scale);
            }
        sam_image_destroy(&img);
    }
    assert_true(covered[0] > 50);
    assert_int_equal(covered[1], 4 * covered[0]);
    assert_int_equal(sam_image_create(&img, 20, 8, 3, &err), SAM_OK);
    assert_true(sam_image_draw_text(&img, -30, -4, 3, ink, "clipped on every side\nand below") > 0);
    assert_int_equal(sam_image_draw_text(&img, 0, 0, 1, NULL, "x"), 0);
    assert_int_equal(sam_image_draw_text(NULL, 0, 0, 1, ink, "x"), 0);
    sam_image_destroy(&img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_create_validates),
        cmocka_unit_test(test_srgb_transfer),
        cmocka_unit_test(test_exr_round_trip_half_rgb),
        cmocka_unit_test(test_exr_round_trip_half_rgba),
        cmocka_unit_test(test_exr_round_trip_float_rgb),
        cmocka_unit_test(test_exr_round_trip_float_rgba),
        cmocka_unit_test(test_exr_y_only_is_replicated),
        cmocka_unit_test(test_exr_tiled_any_channel_order),
        cmocka_unit_test(test_exr_channel_layouts),
        cmocka_unit_test(test_exr_without_color_channels_names_them),
        cmocka_unit_test(test_exr_read_errors),
        cmocka_unit_test(test_exr_huge_data_window_is_refused),
        cmocka_unit_test(test_exr_truncated_files_fail_cleanly),
        cmocka_unit_test(test_png_round_trip_linear),
        cmocka_unit_test(test_png_round_trip_srgb),
        cmocka_unit_test(test_png_srgb_known_values_clamp_and_nan),
        cmocka_unit_test(test_png_reads_every_color_type),
        cmocka_unit_test(test_png_huge_header_is_refused),
        cmocka_unit_test(test_png_read_errors),
        cmocka_unit_test(test_png_truncated_files_fail_cleanly),
        cmocka_unit_test(test_failed_writes_leave_no_file),
        cmocka_unit_test(test_tonemap_curves),
        cmocka_unit_test(test_tonemap_alpha_over_backdrop),
        cmocka_unit_test(test_tonemap_errors),
        cmocka_unit_test(test_compare_known_differences),
        cmocka_unit_test(test_compare_identical_in_8_bits),
        cmocka_unit_test(test_compare_mask),
        cmocka_unit_test(test_compare_matches_png_bytes),
        cmocka_unit_test(test_compare_errors),
        cmocka_unit_test(test_draw_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
