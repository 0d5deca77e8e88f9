#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_brdf.h"

#define PI 3.14159265358979323846

static const float skin_f0 = SAM_BRDF_SKIN_F0;

/* Deterministic uniform numbers in [0, 1) for random directions. */
static double next_uniform(uint64_t *state)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*state >> 11) / 9007199254740992.0;
}

static void random_upper_direction(uint64_t *state, float d[3])
{
    double z = next_uniform(state);
    double phi = 2.0 * PI * next_uniform(state);
    double r = sqrt(1.0 - z * z);
    d[0] = (float)(r * cos(phi));
    d[1] = (float)(r * sin(phi));
    d[2] = (float)z;
}

static void assert_close(double actual, double expected, double tolerance)
{
    if (!(fabs(actual - expected) <= tolerance))
        fail_msg("got %.9g, expected %.9g (tolerance %.2g)", actual, expected, tolerance);
}

static void test_beckmann_is_normalised(void **state)
{
    (void)state;
    /* int D(n.H) (n.H) dH over the hemisphere is 1: the 1/pi that d'Eon's
     * PHBeckmann leaves out is in. */
    const float roughness[] = {0.05f, 0.3f, 1.0f};
    for (size_t k = 0; k < 3; k++) {
        const int steps = 20000;
        double sum = 0.0, dt = 0.5 * PI / steps;
        for (int i = 0; i < steps; i++) {
            double t = (i + 0.5) * dt;
            sum += sam_brdf_beckmann((float)cos(t), roughness[k]) * cos(t) * sin(t) * dt;
        }
        assert_close(2.0 * PI * sum, 1.0, 1e-4);
    }
    assert_close(sam_brdf_beckmann(1.0f, 0.3f), 1.0 / (PI * 0.09), 1e-5);
    assert_true(sam_brdf_beckmann(0.0f, 0.3f) == 0.0f);
    assert_true(sam_brdf_beckmann(-0.5f, 0.3f) == 0.0f);
    assert_true(isnan(sam_brdf_beckmann(0.5f, 0.0f)));
}

static void test_schlick_fresnel(void **state)
{
    (void)state;
    assert_close(sam_brdf_fresnel_schlick(1.0f, skin_f0), skin_f0, 1e-7);
    assert_close(sam_brdf_fresnel_schlick(0.0f, skin_f0), 1.0, 1e-7);
    assert_close(sam_brdf_fresnel_schlick(0.5f, skin_f0), 0.028 + 0.972 / 32.0, 1e-7);
    assert_true(isnan(sam_brdf_fresnel_schlick(0.5f, 1.5f)));
}

static void test_ks_eval_values(void **state)
{
    (void)state;
    /* Normal incidence and view: D = 1/(pi m^2), F = F0, |l+v|^2 = 4. */
    assert_close(sam_brdf_ks_eval(1, 1, 1, 1, 0.3f, skin_f0), 0.028 / (4.0 * PI * 0.09), 1e-7);

    /* A tilted pair, against the formula written out in double. */
    const float n[3] = {0, 0, 1};
    const double tl = 0.5, tv = 0.9, pv = 2.5;
    const float l[3] = {(float)sin(tl), 0.0f, (float)cos(tl)};
    const float v[3] = {(float)(sin(tv) * cos(pv)), (float)(sin(tv) * sin(pv)), (float)cos(tv)};
    double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
    double hh = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    double len = sqrt(hh);
    double nh = h[2] / len, vh = (v[0] * h[0] + v[1] * h[1] + v[2] * h[2]) / len;
    double m = 0.4, tan2 = (1 - nh * nh) / (nh * nh);
    double d = exp(-tan2 / (m * m)) / (PI * m * m * pow(nh, 4));
    double f = 0.028 + 0.972 * pow(1 - vh, 5);
    double expected = d * f / hh;
    float by_dir = sam_brdf_ks_eval_dir(n, l, v, 0.4f, skin_f0);
    assert_close(by_dir, expected, 1e-5 * expected);
    float by_cos = sam_brdf_ks_eval((float)cos(tl), (float)cos(tv), (float)nh, (float)vh, 0.4f,
                                    skin_f0);
    assert_close(by_cos, expected, 1e-5 * expected);

    /* Below the horizon on either side there is no specular reflection. */
    const float under[3] = {0.6f, 0.0f, -0.8f};
    assert_true(sam_brdf_ks_eval_dir(n, under, v, 0.4f, skin_f0) == 0.0f);
    assert_true(sam_brdf_ks_eval_dir(n, l, under, 0.4f, skin_f0) == 0.0f);
    assert_true(sam_brdf_ks_eval(0.0f, 0.5f, 0.9f, 0.7f, 0.4f, skin_f0) == 0.0f);
    assert_true(sam_brdf_ks_eval(0.5f, -0.1f, 0.9f, 0.7f, 0.4f, skin_f0) == 0.0f);
}

static void test_ks_reciprocity(void **state)
{
    (void)state;
    const float n[3] = {0, 0, 1};
    uint64_t rng = 12345;
    for (int k = 0; k < 2000; k++) {
        float l[3], v[3];
        random_upper_direction(&rng, l);
        random_upper_direction(&rng, v);
        float m = (float)(0.05 + 0.95 * next_uniform(&rng));
        float f_lv = sam_brdf_ks_eval_dir(n, l, v, m, skin_f0);
        float f_vl = sam_brdf_ks_eval_dir(n, v, l, m, skin_f0);
        assert_true(f_lv >= 0.0f);
        assert_close(f_vl, f_lv, 1e-5 * f_lv + 1e-30);
    }
}

/* Directional albedo by brute force over the outgoing hemisphere (midpoint
 * rule in theta, phi) with the vector BRDF: an independent check of the
 * half-vector change of variables, the horizon cut and the constants. */
static double brute_force_albedo(float n_dot_l, float m, float f0)
{
    const float n[3] = {0, 0, 1};
    const float l[3] = {(float)sqrt(1.0 - (double)n_dot_l * n_dot_l), 0.0f, n_dot_l};
    const int nt = 400, np = 400; /* np over [0, pi]; mirror symmetry gives the rest */
    double dt = 0.5 * PI / nt, dp = PI / np, sum = 0.0;
    for (int i = 0; i < nt; i++) {
        double t = (i + 0.5) * dt;
        for (int j = 0; j < np; j++) {
            double p = (j + 0.5) * dp;
            const float v[3] = {(float)(sin(t) * cos(p)), (float)(sin(t) * sin(p)),
                                (float)cos(t)};
            sum += sam_brdf_ks_eval_dir(n, l, v, m, f0) * cos(t) * sin(t);
        }
    }
    return 2.0 * sum * dt * dp;
}

static void test_albedo_matches_brute_force(void **state)
{
    (void)state;
    const float cases[][2] = {{1.0f, 0.3f}, {0.5f, 0.3f}, {0.1f, 0.3f}, {0.7f, 1.0f}};
    for (size_t k = 0; k < 4; k++) {
        double brute = brute_force_albedo(cases[k][0], cases[k][1], skin_f0);
        double albedo = sam_brdf_ks_albedo(cases[k][0], cases[k][1], skin_f0,
                                           SAM_BRDF_QUADRATURE_ORDER);
        assert_close(albedo, brute, 2e-5);
        /* rho_dt is the complement of the lobe's albedo. */
        assert_close(sam_brdf_rho_dt(cases[k][0], cases[k][1], skin_f0), 1.0 - albedo, 1e-7);
    }
}

static void test_smooth_limit_is_fresnel(void **state)
{
    (void)state;
    /* As m -> 0 the lobe is a mirror: the albedo is F(n.l) itself (the
     * Kelemen geometry term is then 1). */
    const float mu[] = {1.0f, 0.5f, 0.2f};
    for (size_t k = 0; k < 3; k++) {
        double albedo = sam_brdf_ks_albedo(mu[k], 0.001f, skin_f0, SAM_BRDF_QUADRATURE_ORDER);
        assert_close(albedo, sam_brdf_fresnel_schlick(mu[k], skin_f0), 5e-5);
    }
}

static void test_range_and_energy(void **state)
{
    (void)state;
    const float mu[] = {0.0f, 0.003f, 0.02f, 0.1f, 0.3f, 0.6f, 0.9f, 1.0f};
    const float m[] = {1.0f / 64, 0.1f, 0.3f, 1.0f, 2.0f};
    const float f0[] = {0.0f, skin_f0, 0.5f, 1.0f};
    for (size_t a = 0; a < 8; a++)
        for (size_t b = 0; b < 5; b++) {
            double albedo_by_f0[4];
            for (size_t c = 0; c < 4; c++) {
                double albedo = sam_brdf_ks_albedo(mu[a], m[b], f0[c], SAM_BRDF_QUADRATURE_ORDER);
                if (!(albedo >= 0.0 && albedo <= 1.0 + 1e-9))
                    fail_msg("albedo %.9g at n.l %g m %g F0 %g", albedo, mu[a], m[b], f0[c]);
                float rho = sam_brdf_rho_dt(mu[a], m[b], f0[c]);
                assert_true(rho >= 0.0f && rho <= 1.0f);
                albedo_by_f0[c] = albedo;
            }
            /* Schlick's F is linear in F0, so is the albedo; more F0 reflects more. */
            assert_close(albedo_by_f0[2], 0.5 * (albedo_by_f0[0] + albedo_by_f0[3]), 1e-12);
            assert_true(albedo_by_f0[0] < albedo_by_f0[1] && albedo_by_f0[1] < albedo_by_f0[3]);
        }
}

static void test_zero_f0(void **state)
{
    (void)state;
    /* F0 = 0 leaves only Schlick's (1 - v.H)^5 term: nothing is reflected
     * near normal incidence, but grazing light still is. */
    const float m[] = {0.1f, 0.3f, 1.0f};
    for (size_t b = 0; b < 3; b++) {
        assert_true(sam_brdf_rho_dt(1.0f, m[b], 0.0f) > 0.9999f);
        assert_true(sam_brdf_rho_dt(0.9f, m[b], 0.0f) > 0.9995f);
        assert_true(sam_brdf_rho_dt(0.05f, m[b], 0.0f) < 0.9f);
    }
}

static void test_grazing_light_transmits_less(void **state)
{
    (void)state;
    /* Fresnel grows towards grazing, so rho_dt falls. (Within a few m of
     * grazing the lobe is clipped by the horizon and rho_dt may rise again
     * for very smooth surfaces; the roughnesses here are past that.) */
    const float m[] = {0.1f, 0.3f, 0.5f, 1.0f};
    const float mu[] = {0.7f, 0.5f, 0.3f, 0.2f, 0.1f, 0.05f, 0.02f, 0.0f};
    for (size_t b = 0; b < 4; b++) {
        float previous = sam_brdf_rho_dt(mu[0], m[b], skin_f0);
        for (size_t a = 1; a < 8; a++) {
            float rho = sam_brdf_rho_dt(mu[a], m[b], skin_f0);
            if (!(rho < previous))
                fail_msg("m %g: rho_dt(%g) = %g not below rho_dt(%g) = %g", m[b], mu[a], rho,
                         mu[a - 1], previous);
            previous = rho;
        }
        assert_true(sam_brdf_rho_dt(0.0f, m[b], skin_f0) < 0.8f);
        assert_true(sam_brdf_rho_dt(1.0f, m[b], skin_f0) > 0.97f);
    }
}

static void test_quadrature_converges(void **state)
{
    (void)state;
    const float cases[][2] = {{1.0f, 0.3f},  {0.5f, 0.3f},  {0.1f, 0.3f},   {0.02f, 0.05f},
                              {0.01f, 1.0f}, {0.0f, 1.0f},  {0.3f, 1.0f / 64}, {0.001f, 0.3f}};
    for (size_t k = 0; k < 8; k++) {
        double a64 = sam_brdf_ks_albedo(cases[k][0], cases[k][1], skin_f0, 64);
        double a128 = sam_brdf_ks_albedo(cases[k][0], cases[k][1], skin_f0, 128);
        assert_close(a64, a128, cases[k][0] >= 0.01f ? 1e-5 : 1e-4);
    }
    /* A low order is visibly worse at grazing: the test can tell. */
    double a4 = sam_brdf_ks_albedo(0.02f, 0.05f, skin_f0, 4);
    double a128 = sam_brdf_ks_albedo(0.02f, 0.05f, skin_f0, 128);
    assert_true(fabs(a4 - a128) > 1e-3);
}

static void test_table_layout_matches_direct(void **state)
{
    (void)state;
    /* Non-square with roughness_max != 1, so a transposed or mis-scaled
     * table cannot pass. */
    enum { W = 7, H = 5 };
    const float roughness_max = 0.8f, f0 = 0.05f;
    float table[W * H];
    sam_error err;
    assert_int_equal(sam_brdf_rho_dt_table(W, H, f0, roughness_max, table, &err), SAM_OK);
    for (uint32_t j = 0; j < H; j++)
        for (uint32_t i = 0; i < W; i++) {
            float mu = (float)((i + 0.5) / W);
            float m = (float)((j + 0.5) / H * roughness_max);
            float direct = sam_brdf_rho_dt(mu, m, f0);
            assert_close(table[j * W + i], direct, 1e-7);

            /* A GL-style lookup at the texel centre returns the entry. */
            assert_close(sam_brdf_rho_dt_table_lookup(table, W, H, roughness_max, mu, m),
                         table[j * W + i], 1e-6);
        }
    /* Halfway between two texel centres: their mean; outside: the edge. */
    float mu_mid = 2.0f / W, m_row = (float)(1.5 / H * roughness_max);
    assert_close(sam_brdf_rho_dt_table_lookup(table, W, H, roughness_max, mu_mid, m_row),
                 0.5 * (table[W + 1] + table[W + 2]), 1e-6);
    assert_close(sam_brdf_rho_dt_table_lookup(table, W, H, roughness_max, 0.0f, 0.0f), table[0],
                 1e-7);
    assert_close(sam_brdf_rho_dt_table_lookup(table, W, H, roughness_max, 1.5f, 5.0f),
                 table[W * H - 1], 1e-7);
    assert_true(isnan(sam_brdf_rho_dt_table_lookup(table, W, H, roughness_max, NAN, 0.3f)));
}

static void test_default_table(void **state)
{
    (void)state;
    enum { N = SAM_BRDF_RHO_DT_TABLE_SIZE };
    float table[N * N];
    assert_int_equal(sam_brdf_rho_dt_table(N, N, skin_f0, SAM_BRDF_ROUGHNESS_MAX, table, NULL),
                     SAM_OK);
    for (uint32_t k = 0; k < N; k += 5) {
        float mu = (float)((k + 0.5) / N), m = (float)((N - 1 - k + 0.5) / N);
        assert_close(table[(N - 1 - k) * N + k], sam_brdf_rho_dt(mu, m, skin_f0), 1e-7);
    }
    /* Bilinear interpolation error at off-grid points: measured at most
     * 6.0e-4 for n.l >= 0.3, m >= 0.1, and N.L * error (what reaches the
     * irradiance) at most 4.7e-4 for every n.l, m >= 1/64. */
    for (int a = 0; a <= 6; a++)
        for (int b = 0; b <= 4; b++) {
            float mu = 0.3f + 0.7f * a / 6.0f + 0.013f, m = 0.1f + 0.9f * b / 4.0f - 0.011f;
            if (mu > 1.0f)
                mu = 1.0f;
            float delta = sam_brdf_rho_dt_table_lookup(table, N, N, 1.0f, mu, m) -
                          sam_brdf_rho_dt(mu, m, skin_f0);
            assert_true(fabsf(delta) < 1e-3f);
        }
    for (int a = 0; a <= 8; a++) {
        float mu = 0.003f + 0.03f * a, m = 0.05f + 0.1f * a;
        float delta = sam_brdf_rho_dt_table_lookup(table, N, N, 1.0f, mu, m) -
                      sam_brdf_rho_dt(mu, m, skin_f0);
        assert_true(mu * fabsf(delta) < 1e-3f);
    }
}

static void test_invalid_arguments(void **state)
{
    (void)state;
    float table[16];
    for (int k = 0; k < 16; k++)
        table[k] = -7.0f;
    sam_error err;
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, skin_f0, 1.0f, NULL, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_brdf_rho_dt_table(0, 4, skin_f0, 1.0f, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "0 x 4"));
    assert_int_equal(sam_brdf_rho_dt_table(4, 1, skin_f0, 1.0f, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_brdf_rho_dt_table(SAM_BRDF_MAX_TABLE_SIZE + 1, 4, skin_f0, 1.0f, table,
                                           &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, skin_f0, 0.0f, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "roughness_max 0"));
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, skin_f0, -1.0f, table, NULL),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, skin_f0, NAN, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, skin_f0, INFINITY, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, 1.5f, 1.0f, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "F0 1.5"));
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, -0.1f, 1.0f, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_brdf_rho_dt_table(4, 4, NAN, 1.0f, table, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    for (int k = 0; k < 16; k++)
        assert_true(table[k] == -7.0f);

    assert_true(isnan(sam_brdf_rho_dt(0.5f, 0.0f, skin_f0)));
    assert_true(isnan(sam_brdf_rho_dt(0.5f, -0.3f, skin_f0)));
    assert_true(isnan(sam_brdf_rho_dt(0.5f, INFINITY, skin_f0)));
    assert_true(isnan(sam_brdf_rho_dt(NAN, 0.3f, skin_f0)));
    assert_true(isnan(sam_brdf_rho_dt(0.5f, 0.3f, 2.0f)));
    assert_true(isnan(sam_brdf_ks_albedo(0.5f, 0.3f, skin_f0, 0)));
    assert_true(isnan(sam_brdf_ks_albedo(0.5f, 0.3f, skin_f0, SAM_BRDF_MAX_QUADRATURE_ORDER + 1)));
    assert_true(isnan(sam_brdf_ks_eval(0.5f, 0.5f, 0.9f, 0.8f, 0.0f, skin_f0)));
    /* n.l outside [0, 1] clamps rather than failing. */
    assert_close(sam_brdf_rho_dt(1.2f, 0.3f, skin_f0), sam_brdf_rho_dt(1.0f, 0.3f, skin_f0), 0.0);
    assert_close(sam_brdf_rho_dt(-0.2f, 0.3f, skin_f0), sam_brdf_rho_dt(0.0f, 0.3f, skin_f0), 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_beckmann_is_normalised),
        cmocka_unit_test(test_schlick_fresnel),
        cmocka_unit_test(test_ks_eval_values),
        cmocka_unit_test(test_ks_reciprocity),
        cmocka_unit_test(test_albedo_matches_brute_force),
        cmocka_unit_test(test_smooth_limit_is_fresnel),
        cmocka_unit_test(test_range_and_energy),
        cmocka_unit_test(test_zero_f0),
        cmocka_unit_test(test_grazing_light_transmits_less),
        cmocka_unit_test(test_quadrature_converges),
        cmocka_unit_test(test_table_layout_matches_direct),
        cmocka_unit_test(test_default_table),
        cmocka_unit_test(test_invalid_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
