/* sam_app_stage_exposure: the exposure a bare mesh's picture is shown with. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sam/sam_app_stage.h"

enum { W = 10, H = 10 };

/* Fills a W x H RGBA picture: every pixel covered with (r, g, b). */
static sam_image filled(float *pixels, float r, float g, float b)
{
    for (int i = 0; i < W * H; ++i) {
        pixels[4 * i + 0] = r;
        pixels[4 * i + 1] = g;
        pixels[4 * i + 2] = b;
        pixels[4 * i + 3] = 1.0f;
    }
    return (sam_image){W, H, 4, pixels};
}

static void test_grey_maps_to_one_point_two(void **state)
{
    (void)state;
    float px[W * H * 4];
    sam_image img = filled(px, 0.3f, 0.3f, 0.3f);
    assert_float_equal(sam_app_stage_exposure(&img), log2f(1.2f / 0.3f), 1e-4);
}

/* A strongly coloured object is exposed by its brightest channel, so that
 * channel lands at 1.2 instead of clipping (its luminance, 0.49 here, would
 * have given 1.3 EV more). */
static void test_coloured_object_keeps_its_colour(void **state)
{
    (void)state;
    float px[W * H * 4];
    sam_image img = filled(px, 2.0f, 0.05f, 0.05f);
    assert_float_equal(sam_app_stage_exposure(&img), log2f(1.2f / 2.0f), 1e-4);
}

/* The 97th percentile of the covered pixels: the background and a few
 * fireflies do not move it. */
static void test_percentile_of_covered_pixels(void **state)
{
    (void)state;
    float px[W * H * 4];
    sam_image img = filled(px, 0.5f, 0.4f, 0.2f);
    for (int i = 0; i < 2; ++i)
        px[4 * i] = 1000.0f;
    for (int i = 50; i < 100; ++i) {
        px[4 * i] = px[4 * i + 1] = px[4 * i + 2] = 80.0f;
        px[4 * i + 3] = 0.0f;
    }
    assert_float_equal(sam_app_stage_exposure(&img), log2f(1.2f / 0.5f), 1e-4);
}

static void test_dark_or_empty_pictures(void **state)
{
    (void)state;
    float px[W * H * 4];
    sam_image img = filled(px, 0.0f, 0.0f, 0.0f);
    assert_float_equal(sam_app_stage_exposure(&img), 0.0f, 0.0f);
    img = filled(px, 1e-20f, 0.0f, 0.0f);
    assert_float_equal(sam_app_stage_exposure(&img), 32.0f, 0.0f);
    img = filled(px, 1e20f, 0.0f, 0.0f);
    assert_float_equal(sam_app_stage_exposure(&img), -32.0f, 0.0f);
    for (int i = 0; i < W * H; ++i)
        px[4 * i + 3] = 0.0f;
    assert_float_equal(sam_app_stage_exposure(&img), 0.0f, 0.0f);
    assert_float_equal(sam_app_stage_exposure(NULL), 0.0f, 0.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grey_maps_to_one_point_two),
        cmocka_unit_test(test_coloured_object_keeps_its_colour),
        cmocka_unit_test(test_percentile_of_covered_pixels),
        cmocka_unit_test(test_dark_or_empty_pictures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
