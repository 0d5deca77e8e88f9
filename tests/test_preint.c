#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_preint.h"
#include "sam_test.h"

static sam_profile skin(void)
{
    sam_profile p;
    assert_int_equal(sam_profile_preset("skin", &p, NULL), SAM_OK);
    return p;
}

/* A ring far larger than the profile: D is the clamped cosine. */
static void test_flat_limit(void **state)
{
    (void)state;
    sam_profile p = skin();
    for (float c = -1.0f; c <= 1.0f; c += 0.125f) {
        float d[3];
        sam_preint_diffuse(&p, c, 1e-3f, d); /* r = 1 m */
        for (int k = 0; k < 3; ++k)
            assert_float_equal(d[k], c > 0 ? c : 0, 2e-3);
    }
}

/* D is a normalised blur of the clamped cosine along the ring: it
 * integrates over theta to 2, the clamped cosine's integral, and light
 * wraps past N.L = 0 more for tighter curvature and redder channels. */
static void test_energy_and_wrap(void **state)
{
    (void)state;
    sam_profile p = skin();
    float curvatures[3] = {0.05f, 0.3f, 1.0f};
    float wrap[3];
    for (int ci = 0; ci < 3; ++ci) {
        double sum[3] = {0, 0, 0};
        const int n = 720;
        for (int i = 0; i < n; ++i) {
            double theta = -3.14159265358979 + (i + 0.5) * 2 * 3.14159265358979 / n;
            float d[3];
            sam_preint_diffuse(&p, (float)cos(theta), curvatures[ci], d);
            for (int k = 0; k < 3; ++k) {
                assert_true(d[k] >= 0 && d[k] <= 1.0f + 1e-6f);
                sum[k] += d[k] * 2 * 3.14159265358979 / n;
            }
        }
        for (int k = 0; k < 3; ++k)
            assert_float_equal(sum[k], 2.0, 5e-3);
        float at_terminator[3];
        sam_preint_diffuse(&p, 0.0f, curvatures[ci], at_terminator);
        wrap[ci] = at_terminator[0];
        assert_true(at_terminator[0] > at_terminator[2]); /* red scatters farthest */
    }
    assert_true(wrap[0] < wrap[1] && wrap[1] < wrap[2]);
    printf("diffuse falloff at N.L = 0, red: %.4f (1/20 mm), %.4f (1/3.3 mm), %.4f (1/1 mm)\n", wrap[0], wrap[1],
           wrap[2]);
}

static void test_penumbra(void **state)
{
    (void)state;
    sam_profile p = skin();
    float lo[3], hi[3], mid[3];
    sam_preint_penumbra(&p, 0.0f, 20.0f, lo);
    sam_preint_penumbra(&p, 1.0f, 20.0f, hi);
    sam_preint_penumbra(&p, 0.5f, 20.0f, mid);
    for (int k = 0; k < 3; ++k) {
        assert_float_equal(lo[k], 0.0f, 1e-3); /* a wide penumbra: scattering barely reaches the ends */
        assert_float_equal(hi[k], 1.0f, 1e-3);
        assert_float_equal(mid[k], 0.5f, 1e-3); /* symmetric profile, symmetric ramp */
    }
    /* Monotone in s; a narrow penumbra lets red scatter into the shadow. */
    float prev[3] = {-1, -1, -1};
    for (float s = 0.0f; s <= 1.0f; s += 0.0625f) {
        float v[3];
        sam_preint_penumbra(&p, s, 2.0f, v);
        for (int k = 0; k < 3; ++k) {
            assert_true(v[k] >= prev[k] - 1e-6f);
            prev[k] = v[k];
        }
    }
    float narrow[3];
    sam_preint_penumbra(&p, 0.3f, 1.0f, narrow);
    assert_true(narrow[0] > narrow[2]);
}

static void test_tables_match_functions(void **state)
{
    (void)state;
    sam_profile p = skin();
    float diffuse[8 * 4 * 3], penumbra[6 * 5 * 3];
    sam_error err;
    assert_int_equal(sam_preint_diffuse_table(&p, 8, 4, 2.0f, diffuse, &err), SAM_OK);
    assert_int_equal(sam_preint_penumbra_table(&p, 6, 5, 10.0f, penumbra, &err), SAM_OK);
    float d[3], q[3];
    sam_preint_diffuse(&p, -1.0f + 2.0f * 5.5f / 8, 2.5f / 4 * 2.0f, d);
    sam_preint_penumbra(&p, 3.5f / 6, 1.5f / 5 * 10.0f, q);
    for (int k = 0; k < 3; ++k) {
        assert_float_equal(diffuse[3 * (2 * 8 + 5) + k], d[k], 1e-6);
        assert_float_equal(penumbra[3 * (1 * 6 + 3) + k], q[k], 1e-6);
    }
    assert_int_equal(sam_preint_diffuse_table(&p, 1, 4, 2.0f, diffuse, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "size 1x4"));
    assert_int_equal(sam_preint_penumbra_table(&p, 6, 5, -1.0f, penumbra, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_preint_diffuse_table(&p, 8, 4, NAN, diffuse, &err), SAM_ERR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flat_limit),
        cmocka_unit_test(test_energy_and_wrap),
        cmocka_unit_test(test_penumbra),
        cmocka_unit_test(test_tables_match_functions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
