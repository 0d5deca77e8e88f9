/*
 * sam_truth (the CPU ground truth of eq. 7) against closed forms: an
 * infinite-like slab, a small patch at a known distance, L_d against
 * sam_light_irradiance with and without occluders, determinism across
 * thread counts, and argument errors.
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

#include "sam/sam_light.h"
#include "sam/sam_mesh.h"
#include "sam/sam_truth.h"
#include "sam_test.h"

#define PI 3.14159265358979323846

static sam_truth *make(const sam_truth_scene *scene, const sam_truth_settings *settings)
{
    sam_truth *t;
    sam_error err;
    if (sam_truth_create(scene, settings, &t, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return t;
}

static void translucency(sam_truth *t, size_t count, const float *p, const float *n, float *out)
{
    sam_error err;
    if (sam_truth_translucency(t, count, p, n, out, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

static sam_truth_scene scene_of(const sam_mesh *m, float mm_per_unit, const sam_profile *profile,
                                const sam_light *lights, size_t light_count)
{
    sam_truth_scene s = {.vertex_count = m->vertex_count, .positions = m->positions, .normals = m->normals,
                         .triangle_count = m->triangle_count, .triangles = m->triangles,
                         .mm_per_unit = mm_per_unit, .profile = profile, .lights = lights,
                         .light_count = light_count};
    return s;
}

static sam_light directional(float x, float y, float z, float intensity)
{
    sam_light l = {.type = SAM_LIGHT_DIRECTIONAL, .color = {1, 1, 1}, .intensity = intensity, .shadow = 1};
    float len = sqrtf(x * x + y * y + z * z);
    l.direction[0] = x / len, l.direction[1] = y / len, l.direction[2] = z / len;
    return l;
}

static double rel_err(double a, double b)
{
    return fabs(a - b) / fabs(b);
}

/* ------------------------------------------------------------------------ */

/* A directional light E straight down on a thin slab of thickness d: below
 * the centre, the back side is the top face, an infinite plane at distance
 * d, so eq. 7 integrates each Gaussian to E w_i exp(-d^2 / 2 v_i). */
static void test_slab_closed_form(void **state)
{
    (void)state;
    const float variance[2] = {0.5f, 2.0f};
    const float weight[2][3] = {{0.4f, 0.3f, 0.2f}, {0.3f, 0.4f, 0.5f}};
    sam_profile profile;
    assert_int_equal(sam_profile_gaussian_sum(2, variance, weight, &profile, NULL), SAM_OK);
    const float radius = sam_profile_radius(&profile, SAM_TRUTH_RADIUS_TOLERANCE);
    const double width = ceil(10.0 * radius), d = 1.5, e = 2.5;
    sam_mesh mesh;
    sam_test_shape_mesh("slab", 64, width, d, 0, &mesh);
    sam_light light = directional(0, -1, 0, (float)e);
    sam_truth_scene scene = scene_of(&mesh, 1.0f, &profile, &light, 1);
    sam_truth_settings set;
    sam_truth_default_settings(&set);
    set.sample_count = 1u << 18;
    sam_truth *t = make(&scene, &set);
    print_message("slab %.0f x %.0f x %.1f mm (radius %.2f mm), %u triangles: %llu samples, %llu lit, "
                  "dA %.4f mm^2, %.3f s\n",
                  width, width, d, radius, mesh.triangle_count, (unsigned long long)sam_truth_sample_count(t),
                  (unsigned long long)sam_truth_lit_sample_count(t), sam_truth_sample_area(t), sam_truth_seconds(t));

    /* Bottom centre (looking down), top centre (its back side, the bottom
     * face, is unlit), and an uncovered texel. */
    const float pos[9] = {0, (float)(-d / 2), 0, 0, (float)(d / 2), 0, 0, 0, 0};
    const float nrm[9] = {0, -1, 0, 0, 1, 0, 0, 0, 0};
    float out[9];
    translucency(t, 3, pos, nrm, out);
    for (int c = 0; c < 3; ++c) {
        double expected = 0;
        for (int g = 0; g < 2; ++g)
            expected += e * weight[g][c] * exp(-d * d / (2.0 * variance[g]));
        print_message("  channel %d: truth %.6f, closed form %.6f, error %.3f%%\n", c, out[c], expected,
                      100 * rel_err(out[c], expected));
        assert_true(rel_err(out[c], expected) < 0.01);
        assert_true(out[3 + c] == 0.0f);
        assert_true(out[6 + c] == 0.0f);
    }

    /* Every top-face sample sees the light (no self-shadowing from its own
     * face), the bottom gets none, and only the top is lit. */
    uint32_t top = 0, bottom = 0;
    for (uint64_t i = 0; i < sam_truth_sample_count(t); i += 97) {
        float p[3], n[3], l[3];
        assert_int_equal(sam_truth_sample(t, i, p, n, l, NULL), SAM_OK);
        if (n[1] > 0.999f) {
            /* the cosine only: normals bend towards the rim near the edges */
            top++;
            for (int c = 0; c < 3; ++c)
                assert_true(fabsf(l[c] - (float)e * n[1]) <= 1e-6f * (float)e);
        } else if (n[1] < -0.999f) {
            bottom++;
            assert_true(l[0] == 0 && l[1] == 0 && l[2] == 0);
        }
    }
    /* The rim's vertex normals are smooth, so the upper half of the sides
     * (two segments high) leans towards the light too. */
    double side = 4 * width * d, face = width * width;
    double lit_share = (double)sam_truth_lit_sample_count(t) / (double)sam_truth_sample_count(t);
    double expected_share = (face + side / 2) / (2 * face + side);
    print_message("  checked %u top and %u bottom samples; lit share %.4f (top and upper sides' area share %.4f)\n",
                  top, bottom, lit_share, expected_share);
    assert_true(top > 100 && bottom > 100);
    assert_true(fabs(lit_share - expected_share) < 0.005);
    sam_truth_destroy(t);
    sam_mesh_destroy(&mesh);
}

/* A square of side a at z = -D facing -z, lit from below; the query at the
 * origin looks up (+z), so the square is its back side (eq. 13-14). */
static void square_at(float a, float depth, float pos[12], float nrm[12], uint32_t tri[6])
{
    const float corner[4][2] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}};
    for (int k = 0; k < 4; ++k) {
        pos[3 * k] = a * corner[k][0], pos[3 * k + 1] = a * corner[k][1], pos[3 * k + 2] = -depth;
        nrm[3 * k] = 0, nrm[3 * k + 1] = 0, nrm[3 * k + 2] = -1;
    }
    /* clockwise seen from +z: the faces' normals point to -z */
    const uint32_t t[6] = {0, 2, 1, 0, 3, 2};
    memcpy(tri, t, sizeof t);
}

/* The truth of square_at's square (its triangles `tri`) under one light,
 * from 4096 samples. */
static sam_truth *square_truth(const float pos[12], const float nrm[12], const uint32_t tri[6], float mm_per_unit,
                               const sam_profile *profile, const sam_light *light)
{
    sam_truth_scene scene = {.vertex_count = 4, .positions = pos, .normals = nrm, .triangle_count = 2,
                             .triangles = tri, .mm_per_unit = mm_per_unit, .profile = profile,
                             .lights = light, .light_count = 1};
    sam_truth_settings set;
    sam_truth_default_settings(&set);
    set.sample_count = 4096;
    return make(&scene, &set);
}

static double patch_truth(const sam_profile *profile, float a, float depth, float mm_per_unit, float e)
{
    float pos[12], nrm[12];
    uint32_t tri[6];
    square_at(a, depth, pos, nrm, tri);
    sam_light light = directional(0, 0, 1, e);
    sam_truth *t = square_truth(pos, nrm, tri, mm_per_unit, profile, &light);
    const float q[3] = {0, 0, 0}, n[3] = {0, 0, 1};
    float out[3];
    translucency(t, 1, q, n, out);
    /* The normal reversed: the square is in front, not behind. */
    const float n_down[3] = {0, 0, -1};
    float front[3];
    translucency(t, 1, q, n_down, front);
    assert_true(front[0] == 0 && front[1] == 0 && front[2] == 0);
    sam_truth_destroy(t);
    return out[0];
}

static void test_small_patch(void **state)
{
    (void)state;
    /* A dipole (the R_d table's hardest shape) and a tiny square: R_d is
     * constant over it to 1e-4, so the truth is R_d(D) E a^2. */
    sam_profile marble;
    assert_int_equal(sam_profile_preset("marble", &marble, NULL), SAM_OK);
    const float a = 0.02f, depth = 1.0f, e = 3.0f;
    double truth = patch_truth(&marble, a, depth, 1.0f, e);
    float rd[3];
    sam_profile_eval(&marble, depth, rd);
    double expected = (double)rd[0] * e * a * a;
    print_message("marble, %.2f mm square at %.1f mm: truth %.6e, R_d(D) E a^2 %.6e, error %.4f%%\n", a, depth,
                  truth, expected, 100 * rel_err(truth, expected));
    assert_true(rel_err(truth, expected) < 1e-3);

    /* A square large against the Gaussian (a = 2 sigma): R_d varies over it
     * by 40%, so this checks the integration itself against the closed form
     * exp(-D^2/2v)/(2 pi v) (sqrt(2 pi v) erf(a / (2 sqrt(2v))))^2, in a
     * scene whose model unit is 10 mm. */
    const float v = 0.25f, w[1][3] = {{1, 1, 1}};
    sam_profile gauss;
    assert_int_equal(sam_profile_gaussian_sum(1, &v, w, &gauss, NULL), SAM_OK);
    const double a_mm = 1.0, d_mm = 1.0;
    truth = patch_truth(&gauss, (float)(a_mm / 10), (float)(d_mm / 10), 10.0f, e);
    double side = sqrt(2 * PI * v) * erf(a_mm / (2 * sqrt(2.0 * v)));
    expected = e * exp(-d_mm * d_mm / (2 * v)) / (2 * PI * v) * side * side;
    double naive = e * exp(-d_mm * d_mm / (2 * v)) / (2 * PI * v) * a_mm * a_mm;
    print_message("gaussian v %.2f, %.1f mm square at %.1f mm: truth %.6e, closed form %.6e, error %.4f%% "
                  "(R_d(D) E a^2 would be %.6e)\n",
                  v, a_mm, d_mm, truth, expected, 100 * rel_err(truth, expected), naive);
    assert_true(rel_err(truth, expected) < 2e-3);

    /* The same square facing the query (normals +z, lit from above): behind
     * the tangent plane (eq. 13) but facing the same way (fails eq. 14). */
    float pos[12], nrm[12];
    uint32_t tri[6];
    square_at(a, depth, pos, nrm, tri);
    for (int k = 0; k < 4; ++k)
        nrm[3 * k + 2] = 1;
    const uint32_t up[6] = {0, 1, 2, 0, 2, 3};
    sam_light light = directional(0, 0, -1, e);
    sam_truth *t = square_truth(pos, nrm, up, 1.0f, &marble, &light);
    const float q[3] = {0, 0, 0}, n[3] = {0, 0, 1};
    float out[3];
    translucency(t, 1, q, n, out);
    print_message("square facing the query: %llu lit samples, truth %g\n",
                  (unsigned long long)sam_truth_lit_sample_count(t), out[0]);
    assert_int_equal(sam_truth_lit_sample_count(t), 4096);
    assert_true(out[0] == 0 && out[1] == 0 && out[2] == 0);
    sam_truth_destroy(t);
}

/* ------------------------------------------------------------------------ */

/* A 10 x 10 ground (y = 0, facing up) and a 2 x 2 occluder at y = 2.5. */
static void ground_and_occluder(float pos[24], float nrm[24], uint32_t tri[12])
{
    const float xz[4][2] = {{-1, -1}, {-1, 1}, {1, 1}, {1, -1}}; /* counter-clockwise seen from +y */
    for (int q = 0; q < 2; ++q)
        for (int k = 0; k < 4; ++k) {
            float s = q ? 1.0f : 5.0f;
            float *p = pos + 3 * (4 * q + k), *n = nrm + 3 * (4 * q + k);
            p[0] = s * xz[k][0], p[1] = q ? 2.5f : 0.0f, p[2] = s * xz[k][1];
            n[0] = 0, n[1] = 1, n[2] = 0;
        }
    const uint32_t t[12] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    memcpy(tri, t, sizeof t);
}

static float rho_dt_linear(const void *user, float c)
{
    return 0.5f + *(const float *)user * c;
}

/* Where a light at the origin's +y side is fully hidden from a ground point
 * (|x|, |z| < hidden), fully seen (|x| or |z| > seen), or in between. */
typedef struct light_case {
    const char *name;
    sam_light light;
    float hidden, seen;
} light_case;

static void test_irradiance_and_shadows(void **state)
{
    (void)state;
    float pos[24], nrm[24];
    uint32_t tri[12];
    ground_and_occluder(pos, nrm, tri);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    const float k_rho = 0.4f, env_rho = 0.9f;
    float sh[9][3] = {{0}};
    for (int c = 0; c < 3; ++c)
        sh[0][c] = (float)(2 * sqrt(PI)) * 0.1f * (float)(c + 1); /* constant radiance 0.1, 0.2, 0.3 */

    light_case cases[4] = {
        {"point", {.type = SAM_LIGHT_POINT, .color = {1, 0.5f, 0.25f}, .intensity = 20, .shadow = 1,
                   .position = {0, 5, 0}}, 1.9f, 2.1f},
        {"spot", {.type = SAM_LIGHT_SPOT, .color = {1, 1, 1}, .intensity = 20, .shadow = 1, .position = {0, 5, 0},
                  .direction = {0, -1, 0}, .inner_angle_deg = 30, .outer_angle_deg = 60}, 1.9f, 2.1f},
        {"directional", directional(0, -1, 0, 2), 0.9f, 1.1f},
        /* a 1 x 1 square at y = 5 facing down: the occluder hides it fully
         * within 1.5 of the axis and not at all beyond 2.5 */
        {"area", {.type = SAM_LIGHT_AREA, .color = {1, 1, 1}, .intensity = 5, .shadow = 1, .vertex_count = 4,
                  .vertices = {{-0.5f, 5, -0.5f}, {0.5f, 5, -0.5f}, {0.5f, 5, 0.5f}, {-0.5f, 5, 0.5f}},
                  .normal = {0, -1, 0}, .area = 1}, 1.4f, 2.6f},
    };
    for (int ci = 0; ci < 4; ++ci)
        for (int shadow = 1; shadow >= 0; --shadow) {
            light_case *lc = &cases[ci];
            lc->light.shadow = shadow;
            sam_truth_scene scene = {.vertex_count = 8, .positions = pos, .normals = nrm, .triangle_count = 4,
                                     .triangles = tri, .mm_per_unit = 1.0f, .profile = &skin,
                                     .lights = &lc->light, .light_count = 1, .sh = (const float (*)[3])sh,
                                     .environment_rho_dt = env_rho, .rho_dt = rho_dt_linear,
                                     .rho_dt_user = &k_rho};
            sam_truth_settings set;
            sam_truth_default_settings(&set);
            set.sample_count = 4096;
            sam_truth *t = make(&scene, &set);
            uint32_t hidden = 0, seen = 0, partial = 0;
            double worst = 0;
            for (uint64_t i = 0; i < sam_truth_sample_count(t); ++i) {
                float p[3], n[3], l[3], e[3], env[3];
                assert_int_equal(sam_truth_sample(t, i, p, n, l, NULL), SAM_OK);
                if (p[1] != 0.0f)
                    continue; /* the occluder's own samples */
                assert_int_equal(sam_light_irradiance(&lc->light, p, n, e), SAM_OK);
                sam_light_sh9_irradiance((const float (*)[3])sh, n, env);
                /* the cosine the runtime gives rho_dt (lights.glsl) */
                float c;
                if (lc->light.type == SAM_LIGHT_DIRECTIONAL) {
                    c = -n[1] * lc->light.direction[1];
                } else {
                    const float *to = lc->light.type == SAM_LIGHT_AREA ? (const float[3]){0, 5, 0}
                                                                       : lc->light.position;
                    float d[3] = {to[0] - p[0], to[1] - p[1], to[2] - p[2]};
                    c = (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                }
                float ax = fabsf(p[0]), az = fabsf(p[2]);
                int in_shadow = shadow && ax < lc->hidden && az < lc->hidden;
                int in_light = !shadow || ax > lc->seen || az > lc->seen;
                for (int k = 0; k < 3; ++k) {
                    double full = (double)e[k] * rho_dt_linear(&k_rho, c) + env[k] * env_rho;
                    double dark = env[k] * env_rho;
                    if (in_shadow)
                        worst = fmax(worst, rel_err(l[k], dark));
                    else if (in_light)
                        worst = fmax(worst, rel_err(l[k], full));
                    else
                        assert_true(l[k] >= dark * (1 - 1e-6) && l[k] <= full * (1 + 1e-6));
                }
                hidden += (uint32_t)in_shadow, seen += (uint32_t)in_light;
                partial += (uint32_t)(!in_shadow && !in_light);
            }
            print_message("%-11s shadow %d: %u hidden, %u seen, %u between; worst relative error %.2e\n", lc->name,
                          shadow, hidden, seen, partial, worst);
            assert_true(worst < 1e-5);
            assert_true(seen > 100);
            if (shadow)
                assert_true(hidden > 20);
            sam_truth_destroy(t);
        }
}

/* ------------------------------------------------------------------------ */

/* Progress: fractions never fall within a stage, and each stage ends at 1. */
typedef struct progress_log {
    int calls, irradiance_done, translucency_done, backwards;
    const char *stage;
    double last;
} progress_log;

static void log_progress(void *user, const char *stage, double fraction)
{
    progress_log *log = user;
    if (log->stage && strcmp(stage, log->stage) == 0 && fraction < log->last)
        log->backwards++;
    log->calls++;
    log->stage = stage;
    log->last = fraction;
    if (fraction == 1.0) {
        log->irradiance_done += strcmp(stage, "irradiance") == 0;
        log->translucency_done += strcmp(stage, "translucency") == 0;
    }
}

static void test_deterministic_across_threads(void **state)
{
    (void)state;
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    sam_mesh mesh;
    sam_test_shape_mesh("slab", 32, 40.0, 2.0, 0, &mesh);
    sam_light lights[2] = {directional(0.3f, -1, 0.2f, 1.5f),
                           {.type = SAM_LIGHT_AREA, .color = {1, 0.8f, 0.6f}, .intensity = 3, .shadow = 1,
                            .vertex_count = 3, .vertices = {{-5, 10, -5}, {5, 10, -5}, {0, 10, 5}},
                            .normal = {0, -1, 0}, .area = 50}};
    sam_truth_scene scene = scene_of(&mesh, 1.0f, &skin, lights, 2);
    enum { QUERIES = 400 };
    float pos[3 * QUERIES], nrm[3 * QUERIES];
    for (int q = 0; q < QUERIES; ++q) {
        pos[3 * q] = -15 + 30 * (float)(q % 20) / 19, pos[3 * q + 1] = -1;
        pos[3 * q + 2] = -15 + 30 * (float)(q / 20) / 19;
        nrm[3 * q] = 0, nrm[3 * q + 1] = -1, nrm[3 * q + 2] = 0;
    }
    float out[3][3 * QUERIES];
    uint64_t seeds[3] = {7, 7, 8};
    for (int run = 0; run < 3; ++run) {
        progress_log log = {0};
        sam_truth_settings set;
        sam_truth_default_settings(&set);
        set.sample_count = 60000;
        set.seed = seeds[run];
        set.threads = run == 0 ? 1 : 2;
        set.progress = log_progress;
        set.progress_user = &log;
        sam_truth *t = make(&scene, &set);
        translucency(t, QUERIES, pos, nrm, out[run]);
        print_message("seed %llu, %d thread(s): %.3f s, %d progress calls\n", (unsigned long long)seeds[run],
                      set.threads, sam_truth_seconds(t), log.calls);
        assert_true(sam_truth_seconds(t) > 0);
        assert_int_equal(log.irradiance_done, 1);
        assert_int_equal(log.translucency_done, 1);
        assert_int_equal(log.backwards, 0);
        sam_truth_destroy(t);
    }
    assert_memory_equal(out[0], out[1], sizeof out[0]);
    /* Another seed: other samples, the same integral. */
    double sum[2] = {0, 0};
    for (int k = 0; k < 3 * QUERIES; ++k)
        sum[0] += out[0][k], sum[1] += out[2][k];
    print_message("mean of the queries: seed 7 %.6f, seed 8 %.6f (%.3f%% apart)\n", sum[0] / (3 * QUERIES),
                  sum[1] / (3 * QUERIES), 100 * rel_err(sum[1], sum[0]));
    assert_memory_not_equal(out[0], out[2], sizeof out[0]);
    assert_true(sum[0] > 0 && rel_err(sum[1], sum[0]) < 0.01);
    sam_mesh_destroy(&mesh);
}

/* ------------------------------------------------------------------------ */

/* The far field: on a marble sphere lit from one side (the profile's
 * radius spans the whole ball, the slow case for exact queries), every
 * query with a 1% tolerance is within 1% of the exact sum, and the
 * approximation is used (fewer seconds). */
static void test_far_field(void **state)
{
    (void)state;
    sam_profile marble;
    assert_int_equal(sam_profile_preset("marble", &marble, NULL), SAM_OK);
    sam_mesh mesh;
    sam_test_shape_mesh("sphere", 24, 1.0, 0, 0, &mesh);
    sam_light light = directional(1, 0.2f, 0.1f, 2.0f);
    sam_truth_scene scene = scene_of(&mesh, 30.0f, &marble, &light, 1);
    /* The query points: every vertex, normals outward. */
    uint32_t count = mesh.vertex_count;
    float *out[2] = {malloc(sizeof(float) * 3 * count), malloc(sizeof(float) * 3 * count)};
    assert_non_null(out[0]);
    assert_non_null(out[1]);
    double seconds[2];
    const float tolerance[2] = {0.0f, 0.01f};
    for (int run = 0; run < 2; ++run) {
        sam_truth_settings set;
        sam_truth_default_settings(&set);
        set.sample_count = 200000;
        set.far_field_tolerance = tolerance[run];
        sam_truth *t = make(&scene, &set);
        double start = sam_seconds();
        translucency(t, count, mesh.positions, mesh.normals, out[run]);
        seconds[run] = sam_seconds() - start;
        sam_truth_destroy(t);
    }
    double worst = 0, total = 0;
    for (uint32_t k = 0; k < 3 * count; ++k) {
        double exact = out[0][k], approx = out[1][k];
        total += exact;
        if (exact > 0)
            worst = fmax(worst, fabs(approx - exact) / exact);
        else
            assert_true(approx == 0);
    }
    print_message("far field 1%%: %u queries, exact %.3f s, approximate %.3f s (%.1fx); worst relative error %.5f\n",
                  count, seconds[0], seconds[1], seconds[0] / seconds[1], worst);
    assert_true(total > 0);
    assert_true(worst <= 0.0101);
    assert_true(seconds[1] < seconds[0]);
    free(out[0]);
    free(out[1]);
    sam_mesh_destroy(&mesh);
}

static void expect_create_error(const sam_truth_scene *scene, const sam_truth_settings *set, const char *needle)
{
    sam_truth *t = (sam_truth *)1;
    sam_error err;
    sam_error_clear(&err);
    assert_int_equal(sam_truth_create(scene, set, &t, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_null(t);
    if (!strstr(err.message, needle))
        fail_msg("expected \"%s\" in \"%s\"", needle, err.message);
}

static void test_argument_errors(void **state)
{
    (void)state;
    float pos[12], nrm[12];
    uint32_t tri[6];
    square_at(0.5f, 1.0f, pos, nrm, tri);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    sam_light light = directional(0, 0, 1, 1);
    const sam_truth_scene good = {.vertex_count = 4, .positions = pos, .normals = nrm, .triangle_count = 2,
                                  .triangles = tri, .mm_per_unit = 1.0f, .profile = &skin, .lights = &light,
                                  .light_count = 1};
    sam_truth_settings set;
    sam_truth_default_settings(&set);
    sam_truth_scene s;

    expect_create_error(NULL, &set, "scene");
    expect_create_error(&good, NULL, "settings");
    assert_int_equal(sam_truth_create(&good, &set, NULL, NULL), SAM_ERR_INVALID_ARGUMENT);
    s = good, s.vertex_count = 0;
    expect_create_error(&s, &set, "vertex_count");
    s = good, s.triangle_count = 0;
    expect_create_error(&s, &set, "triangle_count");
    s = good, s.normals = NULL;
    expect_create_error(&s, &set, "normals");
    s = good, s.profile = NULL;
    expect_create_error(&s, &set, "profile");
    s = good, s.mm_per_unit = 0;
    expect_create_error(&s, &set, "mm_per_unit");
    s = good, s.mm_per_unit = NAN;
    expect_create_error(&s, &set, "mm_per_unit");
    s = good, s.light_count = 2, s.lights = NULL;
    expect_create_error(&s, &set, "lights");
    uint32_t bad_tri[6] = {0, 2, 1, 0, 3, 4};
    s = good, s.triangles = bad_tri;
    expect_create_error(&s, &set, "triangles[5]");
    float bad_pos[12];
    memcpy(bad_pos, pos, sizeof pos);
    bad_pos[7] = NAN;
    s = good, s.positions = bad_pos;
    expect_create_error(&s, &set, "vertex 2");
    float bad_nrm[12];
    memcpy(bad_nrm, nrm, sizeof nrm);
    bad_nrm[9] = bad_nrm[10] = bad_nrm[11] = 0;
    s = good, s.normals = bad_nrm;
    expect_create_error(&s, &set, "vertex 3");
    sam_light bad_light = light;
    bad_light.intensity = -1;
    s = good, s.lights = &bad_light;
    expect_create_error(&s, &set, "lights[0]");
    bad_light = light, bad_light.type = SAM_LIGHT_AREA, bad_light.vertex_count = 2;
    expect_create_error(&s, &set, "vertex_count 2");
    float sh[9][3] = {{0}};
    s = good, s.sh = (const float (*)[3])sh, s.environment_rho_dt = -1;
    expect_create_error(&s, &set, "environment_rho_dt");
    sam_truth_settings bad_set = set;
    bad_set.sample_count = (uint64_t)UINT32_MAX + 1;
    expect_create_error(&good, &bad_set, "sample_count");
    bad_set = set, bad_set.threads = -1;
    expect_create_error(&good, &bad_set, "threads");

    /* The automatic count: this quarter of a square millimetre gets the
     * minimum; the same square at 10^4 mm per unit the maximum. */
    sam_truth *t = make(&good, &set);
    assert_int_equal(sam_truth_sample_count(t), SAM_TRUTH_MIN_SAMPLES);
    sam_error err;
    const float q[3] = {0, 0, 0}, n[3] = {0, 0, 1}, nan_q[3] = {0, NAN, 0};
    float out[3];
    assert_int_equal(sam_truth_translucency(NULL, 1, q, n, out, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_truth_translucency(t, 0, q, n, out, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "count"));
    assert_int_equal(sam_truth_translucency(t, 1, NULL, n, out, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "positions"));
    assert_int_equal(sam_truth_translucency(t, 1, nan_q, n, out, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "position 0"));
    assert_int_equal(sam_truth_translucency(t, 1, q, nan_q, out, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "normal 0"));
    assert_int_equal(sam_truth_sample(t, SAM_TRUTH_MIN_SAMPLES, NULL, NULL, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "out of range"));
    assert_int_equal(sam_truth_sample(NULL, 0, NULL, NULL, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    sam_truth_destroy(t);
    sam_truth_destroy(NULL);

    s = good, s.mm_per_unit = 1e4f, s.light_count = 0;
    t = make(&s, &set);
    assert_int_equal(sam_truth_sample_count(t), SAM_TRUTH_MAX_SAMPLES);
    assert_int_equal(sam_truth_lit_sample_count(t), 0);
    translucency(t, 1, q, n, out);
    assert_true(out[0] == 0 && out[1] == 0 && out[2] == 0);
    sam_truth_destroy(t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slab_closed_form),
        cmocka_unit_test(test_small_patch),
        cmocka_unit_test(test_irradiance_and_shadows),
        cmocka_unit_test(test_deterministic_across_threads),
        cmocka_unit_test(test_far_field),
        cmocka_unit_test(test_argument_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
