/*
 * Tests of sam_profile: presets, closed forms against independent numerical
 * integration, the radius of influence, the 8-Gaussian fit, the separable
 * kernel, the JSON description and the profile file loaders.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_profile.h"
#include "sam_test.h"

#define PI 3.14159265358979323846

static const char *const jensen_names[] = {"apple",    "chicken1", "chicken2", "cream",
                                           "ketchup",  "marble",   "potato",   "skimmilk",
                                           "skin1",    "skin2",    "wholemilk"};
#define JENSEN_COUNT (sizeof jensen_names / sizeof jensen_names[0])

static sam_profile preset(const char *name)
{
    sam_profile p;
    sam_error err;
    if (sam_profile_preset(name, &p, &err) != SAM_OK)
        fail_msg("preset %s: %s", name, err.message);
    return p;
}

/* 2 pi int_a^inf r R(r) dr with Simpson on r = a + e^u - e^u0 style log
 * spacing: nodes r_k = a + (e^{u_k} - e^{u_0}), u uniform; independent of
 * the library's quadrature. a = 0 gives the total. */
static void numeric_energy(const sam_profile *p, double a, double out[3])
{
    const int n = 20000;
    const double e0 = 1e-7, e1 = 1e4;
    double h = log(e1 / e0) / n;
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k <= n; k++) {
        double e = e0 * exp(k * h); /* offset from a; dr = e du */
        double r = a + e - e0;
        float R[3];
        sam_profile_eval(p, (float)r, R);
        double c = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        for (int ch = 0; ch < 3; ch++)
            out[ch] += c * h / 3 * 2 * PI * r * R[ch] * e;
    }
}

/* Jensen 2001's closed form of the total diffuse reflectance. */
static double jensen_total(double ssp, double sa, double eta)
{
    double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    double A = (1 + fdr) / (1 - fdr);
    double alpha = ssp / (ssp + sa);
    double s = sqrt(3 * (1 - alpha));
    return 0.5 * alpha * (1 + exp(-4.0 / 3.0 * A * s)) * exp(-s);
}

/* The dipole of the task statement, written out independently. */
static double jensen_rd(double ssp, double sa, double eta, double r)
{
    double st = sa + ssp, alpha = ssp / st, str = sqrt(3 * sa * st);
    double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    double A = (1 + fdr) / (1 - fdr);
    double zr = 1 / st, zv = zr * (1 + 4 * A / 3);
    double dr = sqrt(r * r + zr * zr), dv = sqrt(r * r + zv * zv);
    return alpha / (4 * PI) *
           (zr * (str * dr + 1) * exp(-str * dr) / (dr * dr * dr) +
            zv * (str * dv + 1) * exp(-str * dv) / (dv * dv * dv));
}

static void test_presets(void **state)
{
    (void)state;
    assert_int_equal(sam_profile_preset_count(), 12);
    assert_string_equal(sam_profile_preset_name(0), "skin");
    assert_null(sam_profile_preset_name(12));
    for (size_t i = 0; i < JENSEN_COUNT; i++)
        assert_string_equal(sam_profile_preset_name(i + 1), jensen_names[i]);

    sam_profile p = preset("MarBLE");
    assert_int_equal(p.kind, SAM_PROFILE_DIPOLE);
    assert_string_equal(p.name, "marble");
    assert_true(p.sigma_s_prime[1] == 2.62f && p.sigma_a[2] == 0.0071f && p.eta == 1.3f);
    p = preset("SKIN");
    assert_int_equal(p.kind, SAM_PROFILE_GAUSSIAN_SUM);
    assert_int_equal(p.gaussian_count, 6);
    assert_true(p.variance[5] == 7.41f && p.weight[0][2] == 0.649f);

    sam_error err;
    assert_int_equal(sam_profile_preset("jade", &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "'jade'"));
    assert_non_null(strstr(err.message, "skin, apple"));
    assert_non_null(strstr(err.message, "wholemilk"));
}

static void test_dipole_eval_matches_formula(void **state)
{
    (void)state;
    for (size_t i = 0; i < JENSEN_COUNT; i++) {
        sam_profile p = preset(jensen_names[i]);
        for (double r = 0; r < 50; r = r * 2.5 + 0.01) {
            float R[3];
            sam_profile_eval(&p, (float)r, R);
            for (int c = 0; c < 3; c++) {
                double want = jensen_rd(p.sigma_s_prime[c], p.sigma_a[c], p.eta, (float)r);
                assert_true(fabs(R[c] - want) <= 1e-5 * want);
            }
        }
    }
}

static void test_dipole_total_closed_form_vs_numeric(void **state)
{
    (void)state;
    for (size_t i = 0; i < JENSEN_COUNT; i++) {
        sam_profile p = preset(jensen_names[i]);
        float total[3];
        double numeric[3];
        sam_profile_total_reflectance(&p, total);
        numeric_energy(&p, 0, numeric);
        for (int c = 0; c < 3; c++) {
            double jensen = jensen_total(p.sigma_s_prime[c], p.sigma_a[c], p.eta);
            assert_true(fabs(total[c] - jensen) <= 1e-6 * jensen);
            if (!(fabs(numeric[c] - total[c]) <= 1e-5 * total[c]))
                fail_msg("%s channel %d: closed form %.8g, numeric %.8g", p.name, c,
                         (double)total[c], numeric[c]);
        }
    }
}

static void test_gaussian_sum_integrates_to_weights(void **state)
{
    (void)state;
    const float variance[3] = {0.003f, 0.4f, 12.0f};
    const float weight[3][3] = {{0.2f, 0.0f, 0.5f}, {0.1f, 0.3f, 0.0f}, {0.05f, 0.6f, 0.25f}};
    sam_profile custom;
    assert_int_equal(sam_profile_gaussian_sum(3, variance, weight, &custom, NULL), SAM_OK);
    sam_profile profiles[2] = {preset("skin"), custom};
    for (int i = 0; i < 2; i++) {
        double numeric[3], sum[3] = {0, 0, 0};
        float total[3];
        numeric_energy(&profiles[i], 0, numeric);
        sam_profile_total_reflectance(&profiles[i], total);
        for (uint32_t g = 0; g < profiles[i].gaussian_count; g++)
            for (int c = 0; c < 3; c++)
                sum[c] += profiles[i].weight[g][c];
        for (int c = 0; c < 3; c++) {
            assert_true(fabs(numeric[c] - sum[c]) <= 1e-5 * sum[c]);
            assert_true(fabs(total[c] - sum[c]) <= 1e-6 * sum[c]);
        }
    }
}

static void test_radius_bounds_remaining_energy(void **state)
{
    (void)state;
    const float tolerances[3] = {1e-2f, 1e-3f, 1e-4f};
    for (size_t i = 0; i < sam_profile_preset_count(); i++) {
        sam_profile p = preset(sam_profile_preset_name(i));
        float total[3];
        sam_profile_total_reflectance(&p, total);
        float previous = 0;
        for (int t = 0; t < 3; t++) {
            float r = sam_profile_radius(&p, tolerances[t]);
            assert_true(r > previous && isfinite(r));
            previous = r;
            double beyond[3], inside[3], worst_beyond = 0, worst_inside = 0;
            numeric_energy(&p, r, beyond);
            numeric_energy(&p, r * (1 - 1e-3), inside);
            for (int c = 0; c < 3; c++) {
                worst_beyond = fmax(worst_beyond, beyond[c] / total[c]);
                worst_inside = fmax(worst_inside, inside[c] / total[c]);
            }
            if (!(worst_beyond <= tolerances[t] * (1 + 1e-5)) ||
                !(worst_inside > tolerances[t]))
                fail_msg("%s tol %g: r %g leaves %g, 0.999 r leaves %g", p.name,
                         (double)tolerances[t], (double)r, worst_beyond, worst_inside);
        }
        assert_true(sam_profile_radius(&p, 1.0f) == 0.0f);
        assert_true(isinf(sam_profile_radius(&p, 0.0f)));
    }
}

/* G(t) = 2 pi int_t^inf s R_d(s) ds, the slab's transmission, against the
 * profile integrated numerically from t outwards, for every preset from
 * no slab (the total reflectance) to 20 mm; it must also fall with t. */
static void test_slab_transmission_vs_numeric(void **state)
{
    (void)state;
    const double thickness[] = {0.0, 0.05, 0.3, 1.0, 2.0, 5.0, 20.0};
    for (size_t i = 0; i < sam_profile_preset_count(); i++) {
        sam_profile p = preset(sam_profile_preset_name(i));
        float total[3], previous[3] = {INFINITY, INFINITY, INFINITY};
        sam_profile_total_reflectance(&p, total);
        for (size_t k = 0; k < sizeof thickness / sizeof *thickness; k++) {
            float g[3];
            double numeric[3];
            sam_profile_slab_transmission(&p, (float)thickness[k], g);
            numeric_energy(&p, thickness[k], numeric);
            for (int c = 0; c < 3; c++) {
                if (!(fabs(g[c] - numeric[c]) <= 1e-4 * numeric[c] + 1e-9 * total[c]) || !(g[c] <= previous[c]))
                    fail_msg("%s, t = %g mm, channel %d: G %.8g, numeric %.8g, G at the thinner slab %.8g", p.name,
                             thickness[k], c, (double)g[c], numeric[c], (double)previous[c]);
                previous[c] = g[c];
            }
            if (k == 0)
                for (int c = 0; c < 3; c++)
                    assert_true(fabs(g[c] - total[c]) <= 1e-6 * total[c]);
        }
        float far[3], mirrored[3], at[3];
        sam_profile_slab_transmission(&p, 1000.0f, far);
        sam_profile_slab_transmission(&p, -1.0f, mirrored);
        sam_profile_slab_transmission(&p, 1.0f, at);
        for (int c = 0; c < 3; c++) {
            assert_true(far[c] < 1e-12f * total[c]);
            assert_true(mirrored[c] == at[c]);
        }
    }
}

static void check_fit(const sam_profile *p, const sam_gaussian_fit *fit, float errors[3])
{
    float total[3];
    double sum[3] = {0, 0, 0};
    sam_profile_total_reflectance(p, total);
    assert_true(fit->count >= 1 && fit->count <= SAM_PROFILE_FIT_GAUSSIANS);
    for (uint32_t i = 0; i < fit->count; i++) {
        assert_true(fit->variance[i] > 0);
        if (i)
            assert_true(fit->variance[i] > fit->variance[i - 1]);
        for (int c = 0; c < 3; c++) {
            assert_true(fit->weight[i][c] >= 0);
            sum[c] += fit->weight[i][c];
        }
    }
    for (int c = 0; c < 3; c++) {
        /* eq. 9: the fit keeps the total reflectance */
        if (!(fabs(sum[c] - total[c]) <= 1e-5 * total[c]))
            fail_msg("%s channel %d: fit weights sum to %.8g, total %.8g", p->name, c, sum[c],
                     (double)total[c]);
        errors[c] = sam_profile_fit_error(p, fit, c);
        if (!(errors[c] < SAM_PROFILE_FIT_ERROR_BOUND))
            fail_msg("%s channel %d: eq. 10 error %.4f%% over the bound", p->name, c,
                     100 * (double)errors[c]);
    }
}

static void test_fit_every_preset(void **state)
{
    (void)state;
    for (size_t i = 0; i < sam_profile_preset_count(); i++) {
        sam_profile p = preset(sam_profile_preset_name(i));
        sam_gaussian_fit fit;
        sam_error err;
        assert_int_equal(sam_profile_fit_gaussians(&p, &fit, &err), SAM_OK);
        float e[3];
        check_fit(&p, &fit, e);
        print_message("fit %-9s count %u  eq.10 error  r %.4f%%  g %.4f%%  b %.4f%%\n", p.name,
                      fit.count, 100 * (double)e[0], 100 * (double)e[1], 100 * (double)e[2]);
        if (p.kind == SAM_PROFILE_DIPOLE)
            assert_int_equal(fit.count, SAM_PROFILE_FIT_GAUSSIANS);
    }
}

static void test_fit_exact_for_small_sums(void **state)
{
    (void)state;
    sam_profile skin = preset("skin");
    sam_gaussian_fit fit;
    assert_int_equal(sam_profile_fit_gaussians(&skin, &fit, NULL), SAM_OK);
    assert_int_equal(fit.count, 6);
    for (int i = 0; i < 6; i++) {
        assert_true(fit.variance[i] == skin.variance[i]);
        assert_memory_equal(fit.weight[i], skin.weight[i], sizeof fit.weight[i]);
    }
    for (int c = 0; c < 3; c++)
        assert_true(sam_profile_fit_error(&skin, &fit, c) < 1e-7f);

    /* Ten entries, but duplicates and an all-zero one leave 8 distinct
     * variances, unsorted: still exact, merged and ascending. */
    const float variance[10] = {4, 1, 0.5f, 2, 1, 0.25f, 8, 16, 0.125f, 32};
    float weight[10][3];
    for (int i = 0; i < 10; i++)
        for (int c = 0; c < 3; c++)
            weight[i][c] = 0.01f * (float)(i + 1) * (float)(c + 1);
    weight[7][0] = weight[7][1] = weight[7][2] = 0; /* variance 16 carries nothing */
    sam_profile p;
    const float(*w)[3] = weight;
    assert_int_equal(sam_profile_gaussian_sum(10, variance, w, &p, NULL), SAM_OK);
    assert_int_equal(sam_profile_fit_gaussians(&p, &fit, NULL), SAM_OK);
    assert_int_equal(fit.count, 8);
    const float sorted[8] = {0.125f, 0.25f, 0.5f, 1, 2, 4, 8, 32};
    for (int i = 0; i < 8; i++)
        assert_true(fit.variance[i] == sorted[i]);
    assert_true(fabsf(fit.weight[3][1] - (weight[1][1] + weight[4][1])) < 1e-7f);
    for (int c = 0; c < 3; c++)
        assert_true(sam_profile_fit_error(&p, &fit, c) < 1e-6f);
}

static void test_fit_of_a_larger_sum(void **state)
{
    (void)state;
    /* Skin's six Gaussians plus six more in between: 12 variances to share
     * among 8. */
    sam_profile skin = preset("skin");
    float variance[12], weight[12][3];
    for (int i = 0; i < 6; i++) {
        variance[2 * i] = skin.variance[i];
        variance[2 * i + 1] = skin.variance[i] * 1.9f;
        for (int c = 0; c < 3; c++) {
            weight[2 * i][c] = skin.weight[i][c];
            weight[2 * i + 1][c] = 0.5f * skin.weight[5 - i][c];
        }
    }
    sam_profile p;
    const float(*w)[3] = weight;
    assert_int_equal(sam_profile_gaussian_sum(12, variance, w, &p, NULL), SAM_OK);
    sam_gaussian_fit fit;
    assert_int_equal(sam_profile_fit_gaussians(&p, &fit, NULL), SAM_OK);
    assert_int_equal(fit.count, 8);
    float e[3];
    check_fit(&p, &fit, e);
    print_message("fit 12-gaussian sum  eq.10 error  r %.4f%%  g %.4f%%  b %.4f%%\n",
                  100 * (double)e[0], 100 * (double)e[1], 100 * (double)e[2]);
}

static void test_fit_error_detects_bad_fits(void **state)
{
    (void)state;
    sam_profile marble = preset("marble");
    sam_gaussian_fit fit;
    assert_int_equal(sam_profile_fit_gaussians(&marble, &fit, NULL), SAM_OK);
    /* Squeezing every variance by 2 keeps the energy but not the shape. */
    sam_gaussian_fit bad = fit;
    for (uint32_t i = 0; i < bad.count; i++)
        bad.variance[i] *= 0.5f;
    for (int c = 0; c < 3; c++) {
        assert_true(sam_profile_fit_error(&marble, &bad, c) > 10 * SAM_PROFILE_FIT_ERROR_BOUND);
        assert_true(sam_profile_fit_error(&marble, &fit, c) < SAM_PROFILE_FIT_ERROR_BOUND);
    }
    assert_true(isnan(sam_profile_fit_error(&marble, &fit, 3)));
    bad.count = 9;
    assert_true(isnan(sam_profile_fit_error(&marble, &bad, 0)));
}

static void check_kernel(const sam_profile *p, const sam_separable_kernel *k, uint32_t taps)
{
    assert_int_equal(k->taps, taps);
    uint32_t h = taps / 2;
    assert_true(k->offset_mm[h] == 0.0f);
    assert_true(k->width_mm > 0);
    assert_true(k->offset_mm[taps - 1] == k->width_mm && k->offset_mm[0] == -k->width_mm);
    double sum[3] = {0, 0, 0};
    for (uint32_t i = 0; i < taps; i++) {
        if (i)
            assert_true(k->offset_mm[i] > k->offset_mm[i - 1]);
        assert_true(k->offset_mm[i] == -k->offset_mm[taps - 1 - i]);
        for (int c = 0; c < 3; c++) {
            assert_true(k->weight[i][c] >= 0);
            assert_true(k->weight[i][c] == k->weight[taps - 1 - i][c]);
            sum[c] += k->weight[i][c];
        }
    }
    /* Quadratic spacing: the steps grow away from the centre. */
    for (uint32_t i = h + 1; i + 1 < taps; i++)
        assert_true(k->offset_mm[i + 1] - k->offset_mm[i] > k->offset_mm[i] - k->offset_mm[i - 1]);
    for (int c = 0; c < 3; c++) {
        if (!(fabs(sum[c] - 1) < 1e-5))
            fail_msg("%s taps %u channel %d: weights sum to %.8f", p->name, taps, c, sum[c]);
        assert_true(k->strength[c] >= 0 && k->strength[c] <= 1 && k->falloff[c] > 0);
    }
}

static void test_kernel_every_preset(void **state)
{
    (void)state;
    const uint32_t counts[3] = {9, 17, 33};
    for (size_t i = 0; i < sam_profile_preset_count(); i++) {
        sam_profile p = preset(sam_profile_preset_name(i));
        for (int t = 0; t < 3; t++) {
            sam_separable_kernel k;
            sam_error err;
            assert_int_equal(sam_profile_separable_kernel(&p, counts[t], &k, &err), SAM_OK);
            check_kernel(&p, &k, counts[t]);
            /* The base (red) channel's marginal reproduces itself. */
            assert_true(sam_profile_kernel_error(&p, &k, 0) < 1e-3f);
            if (counts[t] == 17)
                print_message("kernel %-9s width %.3f mm  falloff %.3f %.3f %.3f  strength %.2f "
                              "%.2f %.2f  eq.3 error g %.2f%% b %.2f%%\n",
                              p.name, (double)k.width_mm, (double)k.falloff[0],
                              (double)k.falloff[1], (double)k.falloff[2], (double)k.strength[0],
                              (double)k.strength[1], (double)k.strength[2],
                              100 * (double)sam_profile_kernel_error(&p, &k, 1),
                              100 * (double)sam_profile_kernel_error(&p, &k, 2));
            /* The width leaves SAM_PROFILE_KERNEL_TAIL of the widest
             * channel's marginal outside, and no more for any. */
            float inside[3], total[3];
            sam_profile_marginal_mass(&p, k.width_mm, inside);
            sam_profile_total_reflectance(&p, total);
            double worst = 0;
            for (int c = 0; c < 3; c++) {
                assert_true(total[c] - inside[c] <= (SAM_PROFILE_KERNEL_TAIL + 1e-5) * total[c]);
                worst = fmax(worst, (total[c] - inside[c]) / total[c]);
            }
            assert_true(worst > 0.99 * SAM_PROFILE_KERNEL_TAIL);
        }
    }
}

static void test_kernel_recovers_known_parameters(void **state)
{
    (void)state;
    /* red: one Gaussian; green: half of it plus a spike far narrower than
     * the centre tap (Jimenez's delta, strength 0.5); blue: the red
     * Gaussian at half the standard deviation (falloff ~0.5). */
    const float variance[3] = {1.0f, 1e-8f, 0.25f};
    const float weight[3][3] = {{1, 0.5f, 0}, {0, 0.5f, 0}, {0, 0, 1}};
    sam_profile p;
    assert_int_equal(sam_profile_gaussian_sum(3, variance, weight, &p, NULL), SAM_OK);
    sam_separable_kernel k;
    assert_int_equal(sam_profile_separable_kernel(&p, 17, &k, NULL), SAM_OK);
    check_kernel(&p, &k, 17);
    assert_true(fabsf(k.falloff[0] - 0.999f) < 0.01f && k.strength[0] > 0.99f);
    assert_true(fabsf(k.falloff[1] - 0.999f) < 0.01f && fabsf(k.strength[1] - 0.5f) < 0.01f);
    assert_true(fabsf(k.falloff[2] - 0.499f) < 0.01f && k.strength[2] > 0.99f);
    for (int c = 0; c < 3; c++)
        assert_true(sam_profile_kernel_error(&p, &k, c) < 1e-3f);
    /* 1% of a unit Gaussian's 1D mass lies beyond 2.5758 sigma. */
    assert_true(fabsf(k.width_mm - 2.5758f) < 1e-3f);
}

static void test_kernel_rejects_bad_taps(void **state)
{
    (void)state;
    sam_profile p = preset("skin");
    sam_separable_kernel k;
    const uint32_t bad[] = {0, 7, 8, 16, 18, 34, 35};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sam_error err;
        assert_int_equal(sam_profile_separable_kernel(&p, bad[i], &k, &err),
                         SAM_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(err.message, "taps"));
    }
    assert_int_equal(sam_profile_separable_kernel(&p, 17, &k, NULL), SAM_OK);
    assert_true(isnan(sam_profile_kernel_error(&p, &k, -1)));
    k.taps = 16;
    assert_true(isnan(sam_profile_kernel_error(&p, &k, 0)));
}

/* Strip mass of the marginal, by nested Simpson rules over x and y. */
static double numeric_strip(const sam_profile *p, int channel, double X)
{
    const int nx = 200, ny = 1000;
    const double y0 = 1e-6, y1 = 1e4, hy = log(y1 / y0) / ny, hx = X / nx;
    double sum = 0;
    for (int i = 0; i <= nx; i++) {
        double x = i * hx, m = 0;
        for (int k = 0; k <= ny; k++) {
            double y = y0 * exp(k * hy);
            float R[3];
            sam_profile_eval(p, (float)sqrt(x * x + y * y), R);
            m += ((k == 0 || k == ny) ? 1 : (k % 2 ? 4 : 2)) * hy / 3 * y * R[channel];
        }
        float R0[3];
        sam_profile_eval(p, (float)x, R0);
        m = 2 * (m + y0 * R0[channel]);
        sum += ((i == 0 || i == nx) ? 1 : (i % 2 ? 4 : 2)) * hx / 3 * m;
    }
    return 2 * sum;
}

static void test_marginal_mass(void **state)
{
    (void)state;
    sam_profile skin = preset("skin");
    for (double x = 0.001; x < 30; x *= 2.7) {
        float m[3];
        sam_profile_marginal_mass(&skin, (float)x, m);
        for (int c = 0; c < 3; c++) {
            double want = 0;
            for (uint32_t i = 0; i < skin.gaussian_count; i++)
                want += skin.weight[i][c] * erf((float)x / sqrt(2.0 * skin.variance[i]));
            assert_true(fabs(m[c] - want) <= 1e-5 * want);
        }
    }
    sam_profile marble = preset("marble");
    const double xs[3] = {0.05, 1.0, 6.0};
    for (int i = 0; i < 3; i++) {
        float m[3];
        sam_profile_marginal_mass(&marble, (float)xs[i], m);
        double want = numeric_strip(&marble, 1, xs[i]);
        if (!(fabs(m[1] - want) <= 1e-4 * want))
            fail_msg("marble strip %g: %.8g vs numeric %.8g", xs[i], (double)m[1], want);
    }
    float far[3], total[3];
    sam_profile_marginal_mass(&marble, 1e5f, far);
    sam_profile_total_reflectance(&marble, total);
    for (int c = 0; c < 3; c++)
        assert_true(fabsf(far[c] - total[c]) <= 1e-6f * total[c]);
}

static void test_constructors_validate(void **state)
{
    (void)state;
    sam_profile p;
    sam_error err;
    const float ssp[3] = {1, 1, 1}, sa[3] = {0.1f, -0.2f, 0.1f}, ok_sa[3] = {0, 0, 0};
    assert_int_equal(sam_profile_dipole(ssp, sa, 1.3f, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "sigma_a.g = -0.2"));
    assert_int_equal(sam_profile_dipole(ssp, ok_sa, 0.0f, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "eta = 0"));
    assert_int_equal(sam_profile_dipole(ssp, ok_sa, 10.0f, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_profile_dipole(ssp, ok_sa, NAN, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    /* sigma_a = 0 is allowed: no absorption, total reflectance 1 */
    assert_int_equal(sam_profile_dipole(ssp, ok_sa, 1.3f, &p, &err), SAM_OK);
    float total[3];
    sam_profile_total_reflectance(&p, total);
    assert_true(fabsf(total[0] - 1) < 1e-6f);
    assert_true(isfinite(sam_profile_radius(&p, 1e-3f)));

    const float v[2] = {1, -1}, w[2][3] = {{1, 1, 1}, {1, 1, 1}}, zero[2][3] = {{0}};
    assert_int_equal(sam_profile_gaussian_sum(2, v, w, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "gaussian 1: variance -1"));
    assert_int_equal(sam_profile_gaussian_sum(0, v, w, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_profile_gaussian_sum(33, v, w, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_profile_gaussian_sum(1, v, zero, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "zero weight"));
}

static void test_to_json(void **state)
{
    (void)state;
    sam_profile marble = preset("marble");
    char buf[1024];
    size_t n = sam_profile_to_json(&marble, buf, sizeof buf);
    const char *want = "{\"kind\":\"dipole\",\"name\":\"marble\",\"sigma_s_prime\":[2.19,2.62,3],"
                       "\"sigma_a\":[0.0021,0.0041,0.0071],\"eta\":1.3}";
    assert_string_equal(buf, want);
    assert_int_equal(n, strlen(want));
    /* snprintf semantics: the needed length, a terminated prefix */
    char small[10];
    assert_int_equal(sam_profile_to_json(&marble, small, sizeof small), n);
    assert_string_equal(small, "{\"kind\":\"");
    assert_int_equal(sam_profile_to_json(&marble, NULL, 0), n);

    /* Round trips through a file, including a name that needs escaping. */
    sam_profile profiles[2] = {preset("skin"), marble};
    snprintf(profiles[0].name, sizeof profiles[0].name, "we\"ird\\name");
    for (int i = 0; i < 2; i++) {
        char path[512];
        sam_test_tmp_path(path, sizeof path, i ? "profile_roundtrip_dipole.json"
                                               : "profile_roundtrip_skin.json");
        sam_profile_to_json(&profiles[i], buf, sizeof buf);
        sam_test_write_text(path, buf);
        sam_profile back;
        sam_error err;
        if (sam_profile_load(path, &back, &err) != SAM_OK)
            fail_msg("%s", err.message);
        assert_memory_equal(&back, &profiles[i], sizeof back);
    }
}

static void test_load_good_files(void **state)
{
    (void)state;
    sam_profile p;
    sam_error err;
    assert_int_equal(sam_profile_load(SAM_TEST_DATA_DIR "/profile_jade.json", &p, &err), SAM_OK);
    assert_int_equal(p.kind, SAM_PROFILE_DIPOLE);
    assert_string_equal(p.name, "jade_like");
    assert_true(p.sigma_s_prime[0] == 0.657f && p.sigma_a[2] == 0.0199f && p.eta == 1.5f);

    assert_int_equal(sam_profile_load(SAM_TEST_DATA_DIR "/profile_two_layer.json", &p, &err),
                     SAM_OK);
    assert_int_equal(p.kind, SAM_PROFILE_GAUSSIAN_SUM);
    assert_string_equal(p.name, "profile_two_layer");
    assert_int_equal(p.gaussian_count, 3);
    assert_true(p.variance[2] == 2.5f && p.weight[1][1] == 0.25f);

    assert_int_equal(sam_profile_load(SAM_TEST_DATA_DIR "/profile_dipole.txt", &p, &err), SAM_OK);
    sam_profile marble = preset("marble");
    assert_int_equal(p.kind, SAM_PROFILE_DIPOLE);
    assert_string_equal(p.name, "custom_marble");
    assert_memory_equal(p.sigma_s_prime, marble.sigma_s_prime, sizeof p.sigma_s_prime);
    assert_memory_equal(p.sigma_a, marble.sigma_a, sizeof p.sigma_a);
    assert_true(p.eta == marble.eta);

    assert_int_equal(sam_profile_load(SAM_TEST_DATA_DIR "/profile_gaussians.txt", &p, &err),
                     SAM_OK);
    assert_int_equal(p.gaussian_count, 4);
    assert_string_equal(p.name, "profile_gaussians");
    assert_true(p.variance[3] == 1.99f && p.weight[3][0] == 0.358f && p.weight[2][2] == 0.0f);

    /* from_spec: presets first, then files */
    assert_int_equal(sam_profile_from_spec("Ketchup", &p, &err), SAM_OK);
    assert_string_equal(p.name, "ketchup");
    assert_int_equal(sam_profile_from_spec(SAM_TEST_DATA_DIR "/profile_jade.json", &p, &err),
                     SAM_OK);
    assert_string_equal(p.name, "jade_like");
    /* The artist and measured materials shipped as examples. */
    assert_int_equal(sam_profile_load(SAM_SOURCE_DIR "/scenes/materials/skin_burley.json", &p, &err), SAM_OK);
    assert_string_equal(p.name, "skin_burley");
    assert_int_equal(p.gaussian_count, 8);
    assert_true(p.fit_source_error[0] > 0);
    assert_int_equal(sam_profile_load(SAM_SOURCE_DIR "/scenes/materials/jade_radius.json", &p, &err), SAM_OK);
    assert_string_equal(p.name, "jade_radius");
    assert_int_equal(sam_profile_load(SAM_SOURCE_DIR "/scenes/materials/skin_table.json", &p, &err), SAM_OK);
    assert_string_equal(p.name, "skin_table");
    assert_true(p.fit_source_error[0] > 0 && p.fit_source_error[0] < 0.01f);
    assert_int_equal(sam_profile_from_spec("ketchupp", &p, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "'ketchupp'"));
    assert_non_null(strstr(err.message, "wholemilk"));
}

/* Burley's energy within r, closed form: A (1 - e^{-r/d} / 4 - 3 e^{-r/3d} / 4). */
static double burley_energy(double albedo, double d, double r)
{
    return albedo * (1 - 0.25 * exp(-r / d) - 0.75 * exp(-r / (3 * d)));
}

/* A sum of Gaussians' energy within r. */
static double gaussian_energy(const sam_profile *p, int c, double r)
{
    double e = 0;
    for (uint32_t i = 0; i < p->gaussian_count; i++)
        e += p->weight[i][c] * -expm1(-r * r / (2 * p->variance[i]));
    return e;
}

/* An artist's skin (surface albedo and mean free path per channel) keeps
 * its albedo as its total reflectance, misplaces at most the reported
 * fraction of its energy (checked here against Burley's closed-form
 * energy), scales with its distances, and a scatter radius d gives the
 * profile of the mean free path it stands for. */
static void test_burley_profile(void **state)
{
    (void)state;
    const float albedo[3] = {0.83f, 0.53f, 0.38f}, mfp[3] = {3.67f, 1.37f, 0.68f};
    sam_profile p;
    sam_error err;
    assert_int_equal(sam_profile_burley(albedo, mfp, SAM_BURLEY_MEAN_FREE_PATH, &p, &err), SAM_OK);
    assert_int_equal(p.kind, SAM_PROFILE_GAUSSIAN_SUM);
    assert_int_equal(p.gaussian_count, 8);
    assert_string_equal(p.name, "burley");
    float total[3];
    sam_profile_total_reflectance(&p, total);
    for (int c = 0; c < 3; c++) {
        const double d = sam_profile_burley_shape(albedo[c], mfp[c]);
        assert_true(fabs(d - mfp[c] / (1.9 - albedo[c] + 3.5 * (albedo[c] - 0.8) * (albedo[c] - 0.8))) < 1e-6);
        double worst = 0, worst_r = 0;
        for (double r = 1e-3 * d; r < 40 * d; r *= 1.01) {
            const double e = fabs(gaussian_energy(&p, c, r) - burley_energy(albedo[c], d, r)) / albedo[c];
            if (e > worst)
                worst = e, worst_r = r / d;
        }
        float rd[3];
        const double B = albedo[c] * (exp(-1.0) + exp(-1.0 / 3)) / (8 * 3.14159265358979 * d * d);
        sam_profile_eval(&p, (float)d, rd);
        printf("burley skin channel %d: d %.3f mm, total %.5f, reported energy error %.4f, measured %.4f at %.2f d, "
               "R_d(d) %.4g against %.4g\n",
               c, d, (double)total[c], (double)p.fit_source_error[c], worst, worst_r, (double)rd[c], B);
        assert_true(fabs(total[c] - albedo[c]) < 1e-5);
        assert_true(p.fit_source_error[c] < 0.02f);
        assert_true(fabs(worst - p.fit_source_error[c]) < 0.1 * p.fit_source_error[c] + 1e-4);
        assert_true(fabs(rd[c] / B - 1) < 0.05);
    }
    /* Twice the distances: every radius doubles. */
    const float twice[3] = {2 * mfp[0], 2 * mfp[1], 2 * mfp[2]};
    sam_profile q;
    assert_int_equal(sam_profile_burley(albedo, twice, SAM_BURLEY_MEAN_FREE_PATH, &q, &err), SAM_OK);
    assert_float_equal(sam_profile_radius(&q, 0.01f) / sam_profile_radius(&p, 0.01f), 2.0, 2e-3);
    /* d given directly. */
    float d[3];
    for (int c = 0; c < 3; c++)
        d[c] = (float)sam_profile_burley_shape(albedo[c], mfp[c]);
    assert_int_equal(sam_profile_burley(albedo, d, SAM_BURLEY_SCATTER_RADIUS, &q, &err), SAM_OK);
    for (uint32_t i = 0; i < 8; i++) {
        assert_float_equal(q.variance[i], p.variance[i], 1e-4 * p.variance[i]);
        for (int c = 0; c < 3; c++)
            assert_float_equal(q.weight[i][c], p.weight[i][c], 1e-4);
    }
    /* Errors name the parameter and value. */
    const float bad_albedo[3] = {1.5f, 0.5f, 0.5f}, zero[3] = {0, 0, 0}, bad_distance[3] = {1, 0, 1};
    assert_int_equal(sam_profile_burley(bad_albedo, mfp, SAM_BURLEY_MEAN_FREE_PATH, &q, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "albedo[0] 1.5 must lie in [0, 1]"));
    assert_int_equal(sam_profile_burley(albedo, bad_distance, SAM_BURLEY_SCATTER_RADIUS, &q, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "scatter_radius[1] 0 must be > 0"));
    assert_int_equal(sam_profile_burley(zero, mfp, SAM_BURLEY_MEAN_FREE_PATH, &q, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "reflects no light"));
}

/* A measured profile: the skin preset sampled at 49 radii (as a
 * measurement would give it) comes back as the preset, within the
 * table's own interpolation. */
static void test_table_profile(void **state)
{
    (void)state;
    sam_profile skin = preset("skin"), p;
    float r[49], rd[49][3];
    r[0] = 0;
    for (int i = 1; i < 49; i++)
        r[i] = 0.005f * powf(4000.0f, (float)(i - 1) / 47.0f);
    for (int i = 0; i < 49; i++)
        sam_profile_eval(&skin, r[i], rd[i]);
    sam_error err;
    const float(*crd)[3] = rd;
    assert_int_equal(sam_profile_table(49, r, crd, &p, &err), SAM_OK);
    assert_string_equal(p.name, "table");
    float total[3], want[3];
    sam_profile_total_reflectance(&p, total);
    sam_profile_total_reflectance(&skin, want);
    for (int c = 0; c < 3; c++) {
        double worst = 0;
        for (double x = 1e-3; x < 40; x *= 1.01)
            worst = fmax(worst, fabs(gaussian_energy(&p, c, x) - gaussian_energy(&skin, c, x)) / want[c]);
        printf("skin table channel %d: total %.5f (preset %.5f), reported energy error %.4f, against the preset "
               "%.4f\n",
               c, (double)total[c], (double)want[c], (double)p.fit_source_error[c], worst);
        assert_true(fabs(total[c] / want[c] - 1) < 0.01);
        assert_true(p.fit_source_error[c] < 0.01f);
        assert_true(worst < 0.005);
    }
    /* Errors: order, sign, size. */
    float swapped[49];
    memcpy(swapped, r, sizeof swapped);
    swapped[10] = swapped[9];
    assert_int_equal(sam_profile_table(49, swapped, crd, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "radius_mm[10]"));
    assert_non_null(strstr(err.message, "must ascend"));
    rd[3][1] = -1;
    assert_int_equal(sam_profile_table(49, r, crd, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "rd[3][1] -1 must be >= 0"));
    assert_int_equal(sam_profile_table(1, r, crd, &p, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "1 points, expected 2..4096"));
}

/* A profile nested deeper than the JSON parser goes says so. */
static void test_profile_nesting_too_deep(void **state)
{
    (void)state;
    enum { DEPTH = 1100 };
    char text[2 * DEPTH + 32];
    size_t n = (size_t)snprintf(text, sizeof text, "{\"type\": ");
    for (int i = 0; i < DEPTH; ++i)
        text[n++] = '[';
    for (int i = 0; i < DEPTH; ++i)
        text[n++] = ']';
    text[n++] = '}';
    sam_profile p;
    sam_error err;
    assert_int_equal(sam_profile_parse_json(text, n, "deep.json", &p, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "deep.json:1:"));
    assert_non_null(strstr(err.message, "nest deeper than 1000 levels"));
}

typedef struct bad_case {
    const char *file;     /* name under the temporary directory */
    const char *contents; /* NULL: do not create the file */
    sam_status status;
    const char *needle1;  /* must appear in the message, with the file name */
    const char *needle2;
} bad_case;

static void test_load_bad_files(void **state)
{
    (void)state;
    static const bad_case cases[] = {
        {"profile_unknown_key.json",
         "{\"type\":\"gaussians\",\"gaussians\":[{\"variance\":1,\"weight\":[1,1,1]},"
         "{\"variance\":2,\"weight\":[1,1,1]},{\"variance\":3,\"wieght\":[1,1,1]}]}",
         SAM_ERR_FORMAT, "gaussians[2].wieght", "unknown key"},
        {"profile_unknown_top.json", "{\"type\":\"dipole\",\"colour\":1}", SAM_ERR_FORMAT,
         ": colour: unknown key", NULL},
        {"profile_negative_variance.json",
         "{\"type\":\"gaussians\",\"gaussians\":[{\"variance\":-0.5,\"weight\":[1,1,1]}]}",
         SAM_ERR_FORMAT, "gaussians[0].variance", "-0.5 must be > 0"},
        {"profile_negative_weight.json",
         "{\"type\":\"gaussians\",\"gaussians\":[{\"variance\":0.5,\"weight\":[1,-1,1]}]}",
         SAM_ERR_FORMAT, "gaussians[0].weight[1]", "-1 must be >= 0"},
        {"profile_infinite.json",
         "{\"type\":\"dipole\",\"sigma_s_prime\":[1,1e999,1],\"sigma_a\":[0,0,0],\"eta\":1.3}",
         SAM_ERR_FORMAT, "sigma_s_prime[1]", "not a finite"},
        {"profile_nan.json",
         "{\"type\":\"dipole\",\n\"sigma_s_prime\":[1,NaN,1],\"sigma_a\":[0,0,0],\"eta\":1.3}",
         SAM_ERR_FORMAT, ":2:", "syntax error"},
        {"profile_missing_eta.json",
         "{\"type\":\"dipole\",\"sigma_s_prime\":[1,1,1],\"sigma_a\":[0,0,0]}", SAM_ERR_FORMAT,
         "missing key \"eta\"", NULL},
        {"profile_bad_eta.json",
         "{\"type\":\"dipole\",\"sigma_s_prime\":[1,1,1],\"sigma_a\":[0,0,0],\"eta\":9}",
         SAM_ERR_FORMAT, "eta: 9", NULL},
        {"profile_two_values.json",
         "{\"type\":\"dipole\",\"sigma_s_prime\":[1,1],\"sigma_a\":[0,0,0],\"eta\":1.3}",
         SAM_ERR_FORMAT, "sigma_s_prime", "found 2"},
        {"profile_string_weight.json",
         "{\"type\":\"gaussians\",\"gaussians\":[{\"variance\":1,\"weight\":\"red\"}]}",
         SAM_ERR_FORMAT, "gaussians[0].weight", "found a string"},
        {"profile_wrong_kind.json", "{\"type\":\"gaussians\",\"eta\":1.3,\"gaussians\":[]}",
         SAM_ERR_FORMAT, "eta: not allowed", NULL},
        {"profile_bad_type.json", "{\"type\":\"multipole\"}", SAM_ERR_FORMAT, "\"multipole\"",
         NULL},
        {"profile_duplicate.json",
         "{\"type\":\"dipole\",\"type\":\"dipole\"}", SAM_ERR_FORMAT, "type: duplicate key",
         NULL},
        {"profile_trailing.json",
         "{\"type\":\"gaussians\",\"gaussians\":[{\"variance\":1,\"weight\":[1,1,1]}]} x",
         SAM_ERR_FORMAT, ":1:", "syntax error"},
        {"profile_array.json", "[1, 2]", SAM_ERR_FORMAT, "top level", NULL},
        {"profile_burley_both.json",
         "{\"type\":\"burley\",\"albedo\":[0.5,0.5,0.5],\"mean_free_path\":[1,1,1],\"scatter_radius\":[1,1,1]}",
         SAM_ERR_FORMAT, "one of \"mean_free_path\" and \"scatter_radius\", found both", NULL},
        {"profile_burley_neither.json", "{\"type\":\"burley\",\"albedo\":[0.5,0.5,0.5]}", SAM_ERR_FORMAT,
         "found neither", NULL},
        {"profile_burley_eta.json", "{\"type\":\"burley\",\"albedo\":[0.5,0.5,0.5],\"eta\":1.3}",
         SAM_ERR_FORMAT, "eta: not allowed in a \"burley\" profile", NULL},
        {"profile_burley_albedo.json",
         "{\"type\":\"burley\",\"albedo\":[0.5,2,0.5],\"scatter_radius\":[1,1,1]}", SAM_ERR_FORMAT,
         "albedo[1]", "must lie in [0, 1]"},
        {"profile_burley_radius.json",
         "{\"type\":\"burley\",\"albedo\":[0.5,0.5,0.5],\"scatter_radius\":[1,-1,1]}", SAM_ERR_FORMAT,
         "scatter_radius[1]", "must be > 0"},
        {"profile_table_lengths.json", "{\"type\":\"table\",\"radius_mm\":[0,1,2],\"rd\":[[1,1,1],[0,0,0]]}",
         SAM_ERR_FORMAT, "rd: 2 entries, but radius_mm has 3", NULL},
        {"profile_table_order.json", "{\"type\":\"table\",\"radius_mm\":[0,2,1],\"rd\":[[1,1,1],[1,1,1],[0,0,0]]}",
         SAM_ERR_FORMAT, "radius_mm[2] 1 does not exceed radius_mm[1] 2", NULL},
        {"profile_table_rd.json", "{\"type\":\"table\",\"radius_mm\":[0,1],\"rd\":[[1,1,1],[1,\"x\",1]]}",
         SAM_ERR_FORMAT, "rd[1]", NULL},
        {"profile_table_missing.json", "{\"type\":\"table\",\"radius_mm\":[0,1]}", SAM_ERR_FORMAT,
         "missing key \"rd\" of a table profile", NULL},
        {"profile_empty.json", "", SAM_ERR_FORMAT, "empty", NULL},
        {"profile_blank.txt", "  \n\t\n", SAM_ERR_FORMAT, "empty", NULL},
        {"profile_comments.txt", "# nothing here\n", SAM_ERR_FORMAT, "no profile", NULL},
        {"profile_missing.json", NULL, SAM_ERR_IO, "cannot open", NULL},
        {"profile_nan.txt", "# weights\ngaussian 1 1 1 1\ngaussian 2 nan 1 1\n", SAM_ERR_FORMAT,
         ":3:", "nan is not a finite"},
        {"profile_negative_variance.txt", "gaussian -0.25 1 1 1\n", SAM_ERR_FORMAT, ":1:",
         "variance: -0.25 must be > 0"},
        {"profile_bad_token.txt", "gaussian 0.25 1 1x 1\n", SAM_ERR_FORMAT, ":1:",
         "'1x' is not a number"},
        {"profile_missing_eta.txt", "dipole\nsigma_s_prime 1 1 1\nsigma_a 0 0 0\n",
         SAM_ERR_FORMAT, "no 'eta' line", NULL},
        {"profile_outside_block.txt", "\n\nsigma_a 0 0 0\n", SAM_ERR_FORMAT, ":3:",
         "outside a dipole block"},
        {"profile_keyword.txt", "gausian 1 1 1 1\n", SAM_ERR_FORMAT, ":1:",
         "unknown keyword 'gausian'"},
        {"profile_arity.txt", "gaussian 1 1 1\n", SAM_ERR_FORMAT, ":1:", "found 3"},
        {"profile_mixed.txt", "gaussian 1 1 1 1\ndipole\n", SAM_ERR_FORMAT, ":2:", NULL},
        {"profile_nul.txt", "gaussian 1 1 1 1\n", SAM_ERR_FORMAT, "NUL byte", NULL},
    };
    char path[512];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_case *bc = &cases[i];
        sam_test_tmp_path(path, sizeof path, bc->file);
        if (bc->contents && strcmp(bc->file, "profile_nul.txt") == 0)
            sam_test_write_file(path, bc->contents, strlen(bc->contents) + 1);
        else if (bc->contents)
            sam_test_write_text(path, bc->contents);
        else
            remove(path);
        sam_profile p;
        sam_error err;
        sam_status s = sam_profile_load(path, &p, &err);
        if (s != bc->status || !strstr(err.message, bc->file) ||
            (bc->needle1 && !strstr(err.message, bc->needle1)) ||
            (bc->needle2 && !strstr(err.message, bc->needle2)))
            fail_msg("%s: status %d, message: %s", bc->file, (int)s,
                     s == SAM_OK ? "(none)" : err.message);
    }

    /* 33 gaussians: one too many, in both formats */
    char text[4096] = "";
    size_t len = 0;
    for (int i = 0; i < 33; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, "gaussian %d 1 1 1\n", i + 1);
    sam_test_tmp_path(path, sizeof path, "profile_33.txt");
    sam_test_write_text(path, text);
    sam_profile p;
    sam_error err;
    assert_int_equal(sam_profile_load(path, &p, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "profile_33.txt:33: too many gaussians"));
    len = (size_t)snprintf(text, sizeof text, "{\"type\":\"gaussians\",\"gaussians\":[");
    for (int i = 0; i < 33; i++)
        len += (size_t)snprintf(text + len, sizeof text - len,
                                "%s{\"variance\":%d,\"weight\":[1,1,1]}", i ? "," : "", i + 1);
    snprintf(text + len, sizeof text - len, "]}");
    sam_test_tmp_path(path, sizeof path, "profile_33.json");
    sam_test_write_text(path, text);
    assert_int_equal(sam_profile_load(path, &p, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "profile_33.json: gaussians: 33 entries"));
}

/* Every prefix of a valid file loads or fails cleanly. */
static void check_prefixes(const char *source, const char *tmp_name)
{
    uint8_t *data;
    size_t size;
    assert_int_equal(sam_read_file(source, &data, &size, NULL), SAM_OK);
    assert_true(size > 0);
    char path[512];
    sam_test_tmp_path(path, sizeof path, tmp_name);
    int loaded = 0;
    for (size_t n = 0; n <= size; n++) {
        sam_test_write_file(path, data, n);
        sam_profile p;
        sam_error err;
        sam_status s = sam_profile_load(path, &p, &err);
        if (s == SAM_OK) {
            loaded++;
        } else {
            assert_int_equal(s, SAM_ERR_FORMAT);
            assert_non_null(strstr(err.message, tmp_name));
        }
    }
    assert_true(loaded >= 1); /* at least the whole file */
    free(data);
}

static void test_truncated_files(void **state)
{
    (void)state;
    check_prefixes(SAM_TEST_DATA_DIR "/profile_two_layer.json", "profile_prefix.json");
    check_prefixes(SAM_TEST_DATA_DIR "/profile_dipole.txt", "profile_prefix.txt");
}

/* The direct kernel fits every channel: eq.-2 error far below eq. 1's for
 * skin's green and blue, each channel summing to 1, symmetric. */
static void test_direct_kernel(void **state)
{
    (void)state;
    for (size_t i = 0; i < sam_profile_preset_count(); ++i) {
        sam_profile p;
        sam_separable_kernel direct, eq1;
        assert_int_equal(sam_profile_preset(sam_profile_preset_name(i), &p, NULL), SAM_OK);
        assert_int_equal(sam_profile_separable_kernel_direct(&p, 17, &direct, NULL), SAM_OK);
        assert_int_equal(sam_profile_separable_kernel(&p, 17, &eq1, NULL), SAM_OK);
        assert_memory_equal(direct.offset_mm, eq1.offset_mm, sizeof direct.offset_mm);
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (uint32_t k = 0; k < 17; ++k) {
                sum += direct.weight[k][c];
                assert_float_equal(direct.weight[k][c], direct.weight[16 - k][c], 1e-7);
            }
            assert_float_equal(sum, 1.0, 1e-5);
            float e_direct = sam_profile_kernel_error(&p, &direct, c);
            float e_eq1 = sam_profile_kernel_error(&p, &eq1, c);
            /* The targets are masses within +-width, renormalised: only the
             * <= 1% tail separates the two. */
            assert_true(e_direct <= 0.011f);
            assert_true(e_direct <= e_eq1 + 1e-6f);
        }
    }
    sam_profile skin;
    sam_separable_kernel k;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    assert_int_equal(sam_profile_separable_kernel_direct(&skin, 17, &k, NULL), SAM_OK);
    printf("skin direct kernel eq.-2 error: %.4f %.4f %.4f\n", sam_profile_kernel_error(&skin, &k, 0),
           sam_profile_kernel_error(&skin, &k, 1), sam_profile_kernel_error(&skin, &k, 2));
    assert_int_equal(sam_profile_separable_kernel_direct(&skin, 8, &k, NULL), SAM_ERR_INVALID_ARGUMENT);
}

/* Jimenez et al. report the first eigenvalue of skin's 2D kernel holding
 * about 80% of its energy: a best rank-one fit then misses by sqrt(0.2). */
#define RANK_ONE_BOUND 0.4472136f

/* The fit2d kernel: the layout of the others, each channel summing to 1,
 * non-negative and symmetric, and a 2D error no larger than the marginal's
 * (the direct kernel) and below RANK_ONE_BOUND. */
static void test_fit2d_kernel(void **state)
{
    (void)state;
    const uint32_t counts[3] = {9, 17, 33};
    for (size_t i = 0; i < sam_profile_preset_count(); i++) {
        sam_profile p = preset(sam_profile_preset_name(i));
        for (int t = 0; t < 3; t++) {
            uint32_t taps = counts[t];
            sam_separable_kernel fit, direct;
            sam_error err;
            assert_int_equal(sam_profile_separable_kernel_fit2d(&p, taps, &fit, &err), SAM_OK);
            assert_int_equal(sam_profile_separable_kernel_direct(&p, taps, &direct, &err), SAM_OK);
            assert_int_equal(fit.taps, taps);
            assert_true(fit.width_mm == direct.width_mm);
            assert_memory_equal(fit.offset_mm, direct.offset_mm, sizeof fit.offset_mm);
            float e_fit[3], e_direct[3];
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                for (uint32_t k = 0; k < taps; k++) {
                    assert_true(fit.weight[k][c] >= 0);
                    assert_true(fit.weight[k][c] == fit.weight[taps - 1 - k][c]);
                    sum += fit.weight[k][c];
                }
                if (!(fabs(sum - 1) < 1e-5))
                    fail_msg("%s taps %u channel %d: weights sum to %.8f", p.name, taps, c, sum);
                assert_true(fit.strength[c] == 1.0f && fit.falloff[c] == 1.0f);
                e_fit[c] = sam_profile_kernel_error_2d(&p, &fit, c);
                e_direct[c] = sam_profile_kernel_error_2d(&p, &direct, c);
            }
            print_message("2D error %-9s %2u taps: fit2d %.4f %.4f %.4f  marginal %.4f %.4f %.4f\n",
                          p.name, taps, (double)e_fit[0], (double)e_fit[1], (double)e_fit[2],
                          (double)e_direct[0], (double)e_direct[1], (double)e_direct[2]);
            for (int c = 0; c < 3; c++) {
                if (!(e_fit[c] <= e_direct[c]))
                    fail_msg("%s taps %u channel %d: fit2d 2D error %.5f above the marginal's %.5f",
                             p.name, taps, c, (double)e_fit[c], (double)e_direct[c]);
                /* The bound is the paper's, for skin; the dipole presets
                 * stay below 0.30 (measured), so it holds them too. */
                if (!(e_fit[c] < RANK_ONE_BOUND))
                    fail_msg("%s taps %u channel %d: fit2d 2D error %.5f above sqrt(0.2)", p.name,
                             taps, c, (double)e_fit[c]);
            }
        }
    }
}

/* Mass of a unit-energy 1D Gaussian of variance v over [lo, hi]. */
static double gaussian_mass_1d(double v, double lo, double hi)
{
    return 0.5 * (erf(hi / sqrt(2 * v)) - erf(lo / sqrt(2 * v)));
}

/* sam_profile_kernel_error_2d integrates the profile numerically; skin is a
 * sum of Gaussians, whose cell masses are products of erf differences.
 * Skin's narrowest Gaussian (variance 0.0064 mm^2) is wider than the
 * centre cell but narrower than the next, the hard case for quadrature. */
static void test_kernel_error_2d_closed_form(void **state)
{
    (void)state;
    sam_profile skin = preset("skin");
    const uint32_t counts[3] = {9, 17, 33};
    sam_status (*const makers[3])(const sam_profile *, uint32_t, sam_separable_kernel *,
                                  sam_error *) = {sam_profile_separable_kernel,
                                                  sam_profile_separable_kernel_direct,
                                                  sam_profile_separable_kernel_fit2d};
    double worst = 0;
    for (int t = 0; t < 3; t++) {
        for (int m = 0; m < 3; m++) {
            sam_separable_kernel k;
            assert_int_equal(makers[m](&skin, counts[t], &k, NULL), SAM_OK);
            /* Cells between the midpoints of the offsets, ending at +-width. */
            uint32_t n = k.taps;
            double edge[SAM_KERNEL_MAX_TAPS + 1];
            edge[0] = -(double)k.width_mm;
            edge[n] = k.width_mm;
            for (uint32_t a = 1; a < n; a++)
                edge[a] = 0.5 * ((double)k.offset_mm[a - 1] + k.offset_mm[a]);
            for (int c = 0; c < 3; c++) {
                double total = 0, num = 0, den = 0;
                for (uint32_t g = 0; g < skin.gaussian_count; g++)
                    total += skin.weight[g][c];
                for (uint32_t a = 0; a < n; a++) {
                    for (uint32_t b = 0; b < n; b++) {
                        double s = 0;
                        for (uint32_t g = 0; g < skin.gaussian_count; g++)
                            s += skin.weight[g][c] *
                                 gaussian_mass_1d(skin.variance[g], edge[a], edge[a + 1]) *
                                 gaussian_mass_1d(skin.variance[g], edge[b], edge[b + 1]);
                        s /= total;
                        double d = s - (double)k.weight[a][c] * k.weight[b][c];
                        num += d * d;
                        den += s * s;
                    }
                }
                double want = sqrt(num / den);
                double got = sam_profile_kernel_error_2d(&skin, &k, c);
                double rel = fabs(got - want) / want;
                if (!(rel < 1e-5))
                    fail_msg("skin taps %u kernel %d channel %d: 2D error %.8f, closed form %.8f",
                             n, m, c, got, want);
                worst = fmax(worst, rel);
            }
        }
    }
    print_message("kernel_error_2d vs closed form (skin): worst relative difference %.2e\n", worst);
}

static void test_fit2d_edge_cases(void **state)
{
    (void)state;
    /* A channel with no energy keeps only its centre tap; its 2D error is
     * infinite as in sam_profile_kernel_error. */
    const float variance[1] = {1.0f};
    const float weight[1][3] = {{1, 0.5f, 0}};
    sam_profile p;
    assert_int_equal(sam_profile_gaussian_sum(1, variance, weight, &p, NULL), SAM_OK);
    sam_separable_kernel k;
    assert_int_equal(sam_profile_separable_kernel_fit2d(&p, 17, &k, NULL), SAM_OK);
    for (uint32_t i = 0; i < 17; i++)
        assert_true(k.weight[i][2] == (i == 8 ? 1.0f : 0.0f));
    assert_true(isinf(sam_profile_kernel_error_2d(&p, &k, 2)));
    /* Red and green have the same shape, so the same weights. */
    for (uint32_t i = 0; i < 17; i++)
        assert_float_equal(k.weight[i][0], k.weight[i][1], 1e-7);
    assert_true(sam_profile_kernel_error_2d(&p, &k, 0) < 0.05f);

    sam_profile skin = preset("skin");
    const uint32_t bad[] = {0, 7, 8, 16, 18, 34, 35};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sam_error err;
        assert_int_equal(sam_profile_separable_kernel_fit2d(&skin, bad[i], &k, &err),
                         SAM_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(err.message, "taps"));
    }
    assert_int_equal(sam_profile_separable_kernel_fit2d(NULL, 17, &k, NULL),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_profile_separable_kernel_fit2d(&skin, 17, NULL, NULL),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_profile_separable_kernel_fit2d(&skin, 17, &k, NULL), SAM_OK);
    assert_true(isnan(sam_profile_kernel_error_2d(&skin, &k, -1)));
    assert_true(isnan(sam_profile_kernel_error_2d(&skin, &k, 3)));
    assert_true(isnan(sam_profile_kernel_error_2d(NULL, &k, 0)));
    assert_true(isnan(sam_profile_kernel_error_2d(&skin, NULL, 0)));
    k.width_mm = NAN;
    assert_true(isnan(sam_profile_kernel_error_2d(&skin, &k, 0)));
    k.width_mm = 1;
    k.taps = 16;
    assert_true(isnan(sam_profile_kernel_error_2d(&skin, &k, 0)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_direct_kernel),
        cmocka_unit_test(test_fit2d_kernel),
        cmocka_unit_test(test_kernel_error_2d_closed_form),
        cmocka_unit_test(test_fit2d_edge_cases),
        cmocka_unit_test(test_presets),
        cmocka_unit_test(test_dipole_eval_matches_formula),
        cmocka_unit_test(test_dipole_total_closed_form_vs_numeric),
        cmocka_unit_test(test_gaussian_sum_integrates_to_weights),
        cmocka_unit_test(test_radius_bounds_remaining_energy),
        cmocka_unit_test(test_slab_transmission_vs_numeric),
        cmocka_unit_test(test_fit_every_preset),
        cmocka_unit_test(test_fit_exact_for_small_sums),
        cmocka_unit_test(test_fit_of_a_larger_sum),
        cmocka_unit_test(test_fit_error_detects_bad_fits),
        cmocka_unit_test(test_kernel_every_preset),
        cmocka_unit_test(test_kernel_recovers_known_parameters),
        cmocka_unit_test(test_kernel_rejects_bad_taps),
        cmocka_unit_test(test_marginal_mass),
        cmocka_unit_test(test_constructors_validate),
        cmocka_unit_test(test_to_json),
        cmocka_unit_test(test_burley_profile),
        cmocka_unit_test(test_table_profile),
        cmocka_unit_test(test_load_good_files),
        cmocka_unit_test(test_load_bad_files),
        cmocka_unit_test(test_profile_nesting_too_deep),
        cmocka_unit_test(test_truncated_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
