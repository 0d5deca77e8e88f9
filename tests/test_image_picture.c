/*
 * sam_image_read_picture: JPEG and TGA through stb_image beside PNG. The
 * files are written here with stb_image_write (the test's own encoder):
 * TGA reads back exactly, JPEG at quality 100 within a few levels; grey
 * becomes RGB; every truncated prefix and a damaged header give one clear
 * error; another extension is refused by name.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBIW_WINDOWS_UTF8
#include <stb/stb_image_write.h>

#include "sam/sam_image.h"
#include "sam_test.h"

#define W 13
#define H 7

/* A picture whose every byte differs from its neighbours'. */
static void pattern(uint8_t *p, int channels)
{
    for (int i = 0; i < W * H * channels; ++i)
        p[i] = (uint8_t)(i * 37 + (i / channels) * 11);
}

/* Reads `path` (linear encoding: the bytes as they are) and compares with
 * `want` (W x H x channels bytes) within `tolerance` levels. */
static void expect_picture(const char *path, const uint8_t *want, int channels, uint32_t expect_channels,
                           int tolerance)
{
    sam_image img;
    sam_error err;
    if (sam_image_read_picture(path, &img, SAM_PNG_LINEAR, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(img.width, W);
    assert_int_equal(img.height, H);
    assert_int_equal(img.channels, expect_channels);
    int worst = 0;
    for (int p = 0; p < W * H; ++p)
        for (uint32_t c = 0; c < expect_channels; ++c) {
            const int have = (int)lroundf(img.pixels[(size_t)p * expect_channels + c] * 255.0f);
            const int source = want[p * channels + (channels == 1 ? 0 : (int)c)];
            const int d = abs(have - source);
            worst = d > worst ? d : worst;
        }
    sam_image_destroy(&img);
    if (worst > tolerance)
        fail_msg("%s: worst difference %d levels (allowed %d)", path, worst, tolerance);
}

static void test_tga_reads_exactly(void **state)
{
    (void)state;
    uint8_t rgb[W * H * 4];
    char path[512];
    const int channels[3] = {3, 4, 1};
    for (int k = 0; k < 3; ++k) {
        pattern(rgb, channels[k]);
        for (int rle = 0; rle < 2; ++rle) {
            stbi_write_tga_with_rle = rle;
            snprintf(path, sizeof path, "%s/picture_%d_%d.tga", SAM_TEST_TMP_DIR, channels[k], rle);
            assert_true(stbi_write_tga(path, W, H, channels[k], rgb));
            expect_picture(path, rgb, channels[k], channels[k] == 4 ? 4 : 3, 0);
        }
    }
}

static void test_jpeg_reads_closely(void **state)
{
    (void)state;
    /* A smooth picture: JPEG's blocks keep it within a few levels. */
    uint8_t rgb[W * H * 3];
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            uint8_t *p = rgb + 3 * (y * W + x);
            p[0] = (uint8_t)(60 + 8 * x), p[1] = (uint8_t)(90 + 10 * y), p[2] = 128;
        }
    char path[512];
    snprintf(path, sizeof path, "%s/picture.jpg", SAM_TEST_TMP_DIR);
    assert_true(stbi_write_jpg(path, W, H, 3, rgb, 100));
    expect_picture(path, rgb, 3, 3, 6);
    /* .jpeg is the same format; sRGB decoding applies as to PNG. */
    char jpeg[512];
    snprintf(jpeg, sizeof jpeg, "%s/picture.JPEG", SAM_TEST_TMP_DIR);
    assert_true(stbi_write_jpg(jpeg, W, H, 3, rgb, 100));
    sam_image lin, srgb;
    sam_error err;
    assert_int_equal(sam_image_read_picture(jpeg, &lin, SAM_PNG_LINEAR, &err), SAM_OK);
    assert_int_equal(sam_image_read_picture(jpeg, &srgb, SAM_PNG_SRGB, &err), SAM_OK);
    assert_float_equal(srgb.pixels[0], sam_srgb_to_linear(lin.pixels[0]), 1e-5f);
    sam_image_destroy(&lin);
    sam_image_destroy(&srgb);
}

/* Every prefix of a file, and the file with its header damaged, gives an
 * error naming the file, never a crash or a picture. */
static void expect_broken_files_fail(const char *name, const uint8_t *bytes, size_t size, const char *needle)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", SAM_TEST_TMP_DIR, name);
    for (size_t n = 0; n < size; n += n < 64 ? 1 : 37) {
        sam_test_write_file(path, bytes, n);
        sam_image img;
        sam_error err;
        sam_status st = sam_image_read_picture(path, &img, SAM_PNG_SRGB, &err);
        if (st == SAM_OK)
            fail_msg("%zu of %zu bytes read as a picture", n, size);
        assert_non_null(strstr(err.message, path));
        assert_true(st == SAM_ERR_FORMAT || st == SAM_ERR_IO);
        assert_null(img.pixels);
    }
    uint8_t *damaged = malloc(size);
    assert_non_null(damaged);
    memcpy(damaged, bytes, size);
    memset(damaged, 0x5a, 16);
    sam_test_write_file(path, damaged, size);
    free(damaged);
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_read_picture(path, &img, SAM_PNG_SRGB, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, needle));
}

static void test_broken_files(void **state)
{
    (void)state;
    uint8_t rgb[W * H * 3];
    pattern(rgb, 3);
    char path[512];
    const char *names[2] = {"whole.jpg", "whole.tga"};
    for (int k = 0; k < 2; ++k) {
        snprintf(path, sizeof path, "%s/%s", SAM_TEST_TMP_DIR, names[k]);
        assert_true(k ? stbi_write_tga(path, W, H, 3, rgb) : stbi_write_jpg(path, W, H, 3, rgb, 90));
        uint8_t *bytes;
        size_t size;
        sam_error err;
        assert_int_equal(sam_read_file(path, &bytes, &size, &err), SAM_OK);
        expect_broken_files_fail(k ? "broken.tga" : "broken.jpg", bytes, size,
                                 k ? "not a readable TGA picture" : "not a readable JPEG picture");
        free(bytes);
    }
}

static void test_other_extensions_are_refused(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    assert_int_equal(sam_image_read_picture("albedo.bmp", &img, SAM_PNG_SRGB, &err), SAM_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "albedo.bmp: unsupported picture format (expected .png, .jpg, .jpeg or .tga)"));
    assert_int_equal(sam_image_read_picture("/no/such/albedo.jpg", &img, SAM_PNG_SRGB, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "/no/such/albedo.jpg"));
    assert_int_equal(sam_image_read_picture(NULL, &img, SAM_PNG_SRGB, &err), SAM_ERR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tga_reads_exactly),
        cmocka_unit_test(test_jpeg_reads_closely),
        cmocka_unit_test(test_broken_files),
        cmocka_unit_test(test_other_extensions_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
