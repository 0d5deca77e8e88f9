/*
 * sam_deform's CPU reference against hand-worked poses of each deformer,
 * its strength over time, and the rest pose kept bit for bit.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_deform.h"

#define PI 3.14159265358979323846

/* One deformer applied to one point at time t. */
static void pose(const sam_deformer *d, double t, const float in[3], float out[3])
{
    sam_deform_step step;
    sam_deform_prepare(d, 1, t, &step);
    sam_deform_positions(&step, 1, in, out, 1);
}

static void assert_point(const float got[3], double x, double y, double z)
{
    double e = fmax(fabs(got[0] - x), fmax(fabs(got[1] - y), fabs(got[2] - z)));
    printf("  got (%.7f, %.7f, %.7f), want (%.7f, %.7f, %.7f), error %.2e\n", got[0], got[1], got[2], x, y, z, e);
    assert_true(e < 1e-6);
}

static void test_each_type_by_hand(void **state)
{
    (void)state;
    float out[3];
    /* A quarter bend over one unit: the axis point at u = 1 lands on the
     * arc of radius 2 / pi, a quarter turn round (2 / pi, 0, 0). */
    sam_deformer bend = {.type = SAM_DEFORM_BEND, .axis = {0, 1, 0}, .direction = {1, 0, 0}, .angle_deg = 90,
                         .length = 1};
    pose(&bend, 0, (float[3]){0, 1, 0}, out);
    assert_point(out, 2 / PI, 2 / PI, 0);
    /* Off the axis along z: carried unchanged across the arc's plane. */
    pose(&bend, 0, (float[3]){0, 1, 0.5f}, out);
    assert_point(out, 2 / PI, 2 / PI, 0.5);
    /* 90 degrees of twist per unit about z: (1, 0, 1) turns to (0, 1, 1). */
    sam_deformer twist = {.type = SAM_DEFORM_TWIST, .axis = {0, 0, 1}, .angle_deg = 90, .length = 1};
    pose(&twist, 0, (float[3]){1, 0, 1}, out);
    assert_point(out, 0, 1, 1);
    /* Squash 1.44 along x about (1, 0, 0): across by 1 / 1.2. */
    sam_deformer squash = {.type = SAM_DEFORM_SQUASH, .axis = {1, 0, 0}, .center = {1, 0, 0}, .amount = 0.44f};
    pose(&squash, 0, (float[3]){2, 1, 1}, out);
    assert_point(out, 1 + 1.44, 1 / 1.2, 1 / 1.2);
    /* A wave along x, wavelength 4, 1 unit/s: at t = 1 the crest is at x = 2. */
    sam_deformer wave = {.type = SAM_DEFORM_WAVE, .axis = {1, 0, 0}, .direction = {0, 1, 0}, .amplitude = 0.5f,
                         .wavelength = 4, .speed = 1};
    pose(&wave, 1, (float[3]){2, 0, 0}, out);
    assert_point(out, 2, 0.5, 0);
    pose(&wave, 1, (float[3]){1, 0, 0}, out);
    assert_point(out, 1, 0, 0);
}

static void test_strength_over_time(void **state)
{
    (void)state;
    sam_deformer d = {.type = SAM_DEFORM_TWIST, .axis = {0, 0, 1}, .angle_deg = 90, .length = 1, .period_s = 4};
    assert_float_equal(sam_deform_strength(&d, 0), 0.0, 0.0);
    assert_float_equal(sam_deform_strength(&d, 1), 1.0, 1e-15);
    assert_float_equal(sam_deform_strength(&d, 3), -1.0, 1e-15);
    assert_float_equal(sam_deform_strength(&d, 5), 1.0, 1e-12);
    float out[3];
    pose(&d, 3, (float[3]){1, 0, 1}, out); /* a quarter turn the other way */
    assert_point(out, 0, -1, 1);
    d.period_s = 0;
    assert_float_equal(sam_deform_strength(&d, 123.4), 1.0, 0.0);
}

static void test_rest_pose_is_kept_exactly(void **state)
{
    (void)state;
    sam_deformer d[4] = {
        {.type = SAM_DEFORM_BEND, .axis = {0, 1, 0}, .direction = {1, 0, 0}, .angle_deg = 90, .length = 1,
         .period_s = 2},
        {.type = SAM_DEFORM_TWIST, .axis = {0, 0, 1}, .angle_deg = 0, .length = 1},
        {.type = SAM_DEFORM_SQUASH, .axis = {1, 0, 0}, .amount = 0.5f, .period_s = 1},
        {.type = SAM_DEFORM_WAVE, .axis = {1, 0, 0}, .direction = {0, 1, 0}, .amplitude = 0, .wavelength = 1,
         .speed = 3},
    };
    sam_deform_step steps[4];
    assert_int_equal(sam_deform_prepare(d, 4, 0.0, steps), 0);
    float in[6] = {0.1f, 0.2f, 0.3f, -7.0f, 1e-3f, 5.5f}, out[6];
    sam_deform_positions(steps, 4, in, out, 2);
    assert_memory_equal(in, out, sizeof in);
    assert_int_equal(sam_deform_prepare(d, 4, 0.5, steps), 1);
    assert_int_equal(steps[0].identity, 0);
    assert_int_equal(steps[1].identity, 1);
    assert_int_equal(steps[3].identity, 1);
    assert_string_equal(sam_deformer_type_name(SAM_DEFORM_SQUASH), "squash");
    assert_string_equal(sam_deformer_type_name((sam_deformer_type)9), "unknown");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_each_type_by_hand),
        cmocka_unit_test(test_strength_over_time),
        cmocka_unit_test(test_rest_pose_is_kept_exactly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
