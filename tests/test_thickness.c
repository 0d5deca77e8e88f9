/*
 * sam_thickness (the local-thickness technique's precompute) against what
 * its estimator gives analytically: a slab's depth, a sphere's radius, the
 * cap on an open mesh; the ray rule; bit-identical results for any thread
 * count; refused input; and the ring median that removes lone outliers.
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

#include "sam/sam_mesh.h"
#include "sam/sam_thickness.h"
#include "sam_test.h"

static sam_thickness_surface surface_of(const sam_mesh *m)
{
    sam_thickness_surface s = {m->vertex_count, m->positions, m->normals, m->triangle_count, m->triangles};
    return s;
}

/* Thickness of every vertex of `m` (caller frees). */
static float *thickness_of(const sam_mesh *m, float mm_per_unit, const sam_thickness_settings *set)
{
    float *t = malloc(m->vertex_count * sizeof *t);
    assert_non_null(t);
    sam_thickness_surface s = surface_of(m);
    sam_error err;
    if (sam_thickness_compute(&s, mm_per_unit, set, NULL, NULL, t, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return t;
}

/* The rule's own numbers: unit vectors in the upper hemisphere whose mean
 * z^2 (cos^2 theta) is exactly 1/2, the cosine-weighted mean, for every
 * strata count; mean z (cos theta) tends to 2/3 and the mean direction to
 * the axis. Out of range writes nothing. */
static void test_rule(void **state)
{
    (void)state;
    static float d[3 * SAM_THICKNESS_MAX_STRATA * SAM_THICKNESS_MAX_STRATA];
    for (uint32_t k = 1; k <= SAM_THICKNESS_MAX_STRATA; ++k) {
        sam_thickness_directions(k, d);
        double z2 = 0, z = 0, x = 0, y = 0;
        for (uint32_t i = 0; i < k * k; ++i) {
            const float *v = d + 3 * i;
            assert_true(fabs(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - 1.0) < 1e-6);
            assert_true(v[2] > 0);
            z2 += v[2] * v[2], z += v[2], x += v[0], y += v[1];
        }
        z2 /= k * k, z /= k * k, x /= k * k, y /= k * k;
        if (k == 1 || k == 8 || k == 32)
            print_message("strata %u: mean cos^2 %.7f, mean cos %.5f, mean direction (%.1e, %.1e)\n", k, z2, z, x, y);
        assert_true(fabs(z2 - 0.5) < 1e-6);
        if (k >= 8) {
            assert_true(fabs(z - 2.0 / 3.0) < 0.01);
            assert_true(fabs(x) < 1e-6 && fabs(y) < 1e-6);
        }
    }
    d[0] = 7.0f;
    sam_thickness_directions(0, d);
    sam_thickness_directions(SAM_THICKNESS_MAX_STRATA + 1, d);
    assert_true(d[0] == 7.0f);
}

/* A 40 x 40 x 2 mm slab. Every ray of the rule from a face vertex at least
 * D tan(theta_max) from the slab's sides reaches the opposite face, at
 * depth exactly D below the tangent plane (origin e deep, d cos theta =
 * D - e): t = D whatever the ray count. (The plain cosine-weighted mean of
 * the chords would be 2D: E[1 / cos theta] = 2.) Closer to the sides, some
 * rays end on a side wall, shallower: t <= D there. */
static void test_slab_depth(void **state)
{
    (void)state;
    const double size = 1.0, depth = 0.05, mm = 40.0, d_mm = depth * mm;
    sam_mesh m;
    sam_test_shape_mesh("slab", 40, size, depth, 0, &m);
    sam_thickness_settings set;
    sam_thickness_default_settings(&set);
    float *t = thickness_of(&m, (float)mm, &set);
    /* The rule's steepest ring: sin^2 theta = (k - 0.5) / k. */
    double s2 = (set.strata - 0.5) / set.strata, reach = depth * sqrt(s2 / (1 - s2));
    double worst_inner = 0, centre = -1, centre_r = INFINITY;
    uint32_t inner = 0, face = 0;
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        const float *p = m.positions + 3 * v, *n = m.normals + 3 * v;
        if (fabsf(n[1]) != 1.0f)
            continue;
        ++face;
        if (!(t[v] > 0 && t[v] <= d_mm * (1 + 1e-5)))
            fail_msg("face vertex %u at (%g, %g, %g): %g mm, deeper than the slab's %g", v, p[0], p[1], p[2],
                     (double)t[v], d_mm);
        double edge = 0.5 * size - fmax(fabs(p[0]), fabs(p[2]));
        if (edge >= reach) {
            worst_inner = fmax(worst_inner, fabs(t[v] - d_mm) / d_mm);
            ++inner;
        }
        double r = hypot(p[0], p[2]);
        if (r < centre_r)
            centre_r = r, centre = t[v];
    }
    print_message("slab %g mm: %u face vertices, %u at least %.3g mm from the sides: worst relative error %.2e; "
                  "centre %.6f mm\n",
                  d_mm, face, inner, reach * mm, worst_inner, centre);
    assert_true(inner > 200);
    assert_true(worst_inner < 1e-4);
    assert_true(fabs(centre - d_mm) < 0.01 * d_mm);
    free(t);
    sam_mesh_destroy(&m);
}

/* Depth of a sphere of radius r's far side below the tangent plane at a
 * surface point, for the ray at cos theta = c from the inverted normal out
 * of o, e deep on the radius: e + d c, d the exit distance. */
static double sphere_depth(double r, double e, double c)
{
    double q = r - e, s2 = 1 - c * c;
    return e + c * (q * c + sqrt(r * r - q * q * s2));
}

/* A sphere of radius 30 mm: the chord at angle theta is 2R cos theta, so
 * the cosine-weighted mean depth 2R E[cos^2 theta] is R, and the rule
 * averages cos^2 exactly. Predicted for the rule with the origin's offset
 * as well; the mesh (a 64-segment cube-sphere) is within its sagitta. */
static void test_sphere_radius(void **state)
{
    (void)state;
    const double size = 1.0, mm = 60.0, r = 0.5 * size * mm;
    sam_mesh m;
    sam_test_shape_mesh("sphere", 64, size, 0, 0, &m);
    sam_thickness_settings set;
    sam_thickness_default_settings(&set);
    float *t = thickness_of(&m, (float)mm, &set);
    static float d[3 * 64];
    sam_thickness_directions(set.strata, d);
    double e = set.offset * sqrt(3.0) * size * mm, predicted = 0, exact_rule = 0;
    for (uint32_t k = 0; k < set.strata * set.strata; ++k) {
        predicted += sphere_depth(r, e, d[3 * k + 2]);
        exact_rule += sphere_depth(r, 0, d[3 * k + 2]);
    }
    predicted /= set.strata * set.strata;
    exact_rule /= set.strata * set.strata;
    double lo = INFINITY, hi = 0;
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        lo = fmin(lo, t[v]), hi = fmax(hi, t[v]);
    print_message("sphere R = %g mm: rule without offset %.6f, predicted %.6f, mesh %.6f .. %.6f mm\n", r, exact_rule,
                  predicted, lo, hi);
    assert_true(fabs(exact_rule - r) < 1e-6 * r);
    assert_true(fabs(lo - predicted) < 0.005 * r && fabs(hi - predicted) < 0.005 * r);
    free(t);
    sam_mesh_destroy(&m);
}

/* The through statistic on the sphere of the test above: the mean depth
 * of the rays within 30 degrees of -n, 2R cos^2 theta each (with the
 * offset); on the slab of test_slab_depth, D at the centre, as the mean. */
static void test_through(void **state)
{
    (void)state;
    const double mm = 60.0, r = 0.5 * mm;
    sam_mesh m;
    sam_test_shape_mesh("sphere", 64, 1.0, 0, 0, &m);
    sam_thickness_settings set;
    sam_thickness_default_settings(&set);
    set.statistic = SAM_THICKNESS_THROUGH;
    float *t = thickness_of(&m, (float)mm, &set);
    static float d[3 * 64];
    sam_thickness_directions(set.strata, d);
    double e = set.offset * sqrt(3.0) * mm, predicted = 0;
    uint32_t rays = 0;
    for (uint32_t k = 0; k < set.strata * set.strata; ++k)
        if (d[3 * k + 2] * d[3 * k + 2] >= 0.75f) {
            predicted += sphere_depth(r, e, d[3 * k + 2]);
            rays++;
        }
    predicted /= rays;
    double lo = INFINITY, hi = 0;
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        lo = fmin(lo, t[v]), hi = fmax(hi, t[v]);
    print_message("sphere R = %g mm, through (%u rays): predicted %.6f, mesh %.6f .. %.6f mm\n", r, rays, predicted,
                  lo, hi);
    assert_true(rays == 2 * set.strata);
    assert_true(predicted > 1.5 * r && predicted < 2 * r);
    assert_true(fabs(lo - predicted) < 0.005 * r && fabs(hi - predicted) < 0.005 * r);
    free(t);
    sam_mesh_destroy(&m);

    sam_test_shape_mesh("slab", 40, 1.0, 0.05, 0, &m);
    t = thickness_of(&m, 40.0f, &set);
    double centre = -1, centre_r = INFINITY;
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        const float *p = m.positions + 3 * v;
        if (fabsf(m.normals[3 * v + 1]) == 1.0f && hypot(p[0], p[2]) < centre_r)
            centre_r = hypot(p[0], p[2]), centre = t[v];
    }
    print_message("slab 2 mm, through at the centre: %.6f mm\n", centre);
    assert_true(fabs(centre - 2.0) < 0.01 * 2.0);
    free(t);
    sam_mesh_destroy(&m);
}

/* An open square: every ray from below misses, so every vertex gets the
 * cap's depth, e + C mean(cos theta), C the bounding-box diagonal. */
static void test_misses_take_the_cap(void **state)
{
    (void)state;
    const float pos[4 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const float nrm[4 * 3] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
    sam_thickness_surface s = {4, pos, nrm, 2, tri};
    sam_thickness_settings set;
    sam_thickness_default_settings(&set);
    float t[4];
    sam_error err;
    assert_int_equal(sam_thickness_compute(&s, 10.0f, &set, NULL, NULL, t, &err), SAM_OK);
    static float d[3 * 64];
    sam_thickness_directions(set.strata, d);
    double cap = sqrt(2.0), mean_cos = 0;
    for (uint32_t k = 0; k < 64; ++k)
        mean_cos += d[3 * k + 2] / 64.0;
    double want = 10.0 * (set.offset * cap + cap * mean_cos);
    for (int v = 0; v < 4; ++v) {
        print_message("open square, vertex %d: %.6f mm, the cap's %.6f\n", v, (double)t[v], want);
        assert_true(fabs(t[v] - want) < 1e-5 * want);
    }
}

/* The knot (strands close to each other) with 1, 2, 3 and all threads, and
 * another ray count: the same bits. */
static void test_threads_bit_identical(void **state)
{
    (void)state;
    sam_mesh m;
    sam_test_shape_mesh("knot", 320, 0, 0, 0, &m);
    sam_thickness_settings set;
    sam_thickness_default_settings(&set);
    set.strata = 5;
    set.threads = 1;
    float *one = thickness_of(&m, 40.0f, &set);
    for (int threads = 0; threads <= 3; ++threads) {
        set.threads = threads;
        float *t = thickness_of(&m, 40.0f, &set);
        size_t differ = 0;
        for (uint32_t v = 0; v < m.vertex_count; ++v)
            differ += memcmp(t + v, one + v, sizeof *t) != 0;
        print_message("knot, %u vertices, %d threads (0 = all): %zu differ from 1 thread\n", m.vertex_count, threads,
                      differ);
        assert_int_equal(differ, 0);
        free(t);
    }
    free(one);
    sam_mesh_destroy(&m);
}

static int cancel_at_once(void *user, uint64_t done, uint64_t total)
{
    (void)done;
    (void)total;
    ++*(int *)user;
    return 1;
}

/* Each refusal names what is wrong. */
static void test_refused_input(void **state)
{
    (void)state;
    float pos[4 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    float nrm[4 * 3] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    uint32_t tri[6] = {0, 1, 2, 0, 2, 7};
    sam_thickness_surface s = {4, pos, nrm, 2, tri};
    float t[4];
    sam_error err;
    assert_int_equal(sam_thickness_compute(&s, 1.0f, NULL, NULL, NULL, t, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("%s\n", err.message);
    assert_non_null(strstr(err.message, "triangle 1 names vertex 7"));
    tri[5] = 3;
    nrm[5] = 0;
    assert_int_equal(sam_thickness_compute(&s, 1.0f, NULL, NULL, NULL, t, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("%s\n", err.message);
    assert_non_null(strstr(err.message, "vertex 1's normal"));
    nrm[5] = 1;
    assert_int_equal(sam_thickness_compute(&s, 0.0f, NULL, NULL, NULL, t, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "mm_per_unit"));
    sam_thickness_settings set;
    sam_thickness_default_settings(&set);
    set.strata = 33;
    assert_int_equal(sam_thickness_compute(&s, 1.0f, &set, NULL, NULL, t, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("%s\n", err.message);
    assert_non_null(strstr(err.message, "got 33"));
    sam_thickness_default_settings(&set);
    set.offset = 0;
    assert_int_equal(sam_thickness_compute(&s, 1.0f, &set, NULL, NULL, t, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "offset"));
    int calls = 0;
    assert_int_equal(sam_thickness_compute(&s, 1.0f, NULL, cancel_at_once, &calls, t, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(calls, 1);
    assert_non_null(strstr(err.message, "cancelled"));
    s.triangle_count = 0;
    assert_int_equal(sam_thickness_compute(&s, 1.0f, NULL, NULL, NULL, t, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("%s\n", err.message);
}

/* The ring median on a chain of 12 vertices (ring: the two neighbours):
 * a lone vertex that reads almost no thickness (a scan's crack behind it)
 * takes its neighbours'; a thin part three vertices wide keeps its own; an
 * end, with two values, takes their mean. Bad rings are refused. */
static void test_ring_median(void **state)
{
    (void)state;
    enum { N = 12 };
    uint32_t offsets[N + 1], ring[2 * N], used = 0;
    for (uint32_t v = 0; v < N; ++v) {
        offsets[v] = used;
        if (v > 0)
            ring[used++] = v - 1;
        if (v + 1 < N)
            ring[used++] = v + 1;
    }
    offsets[N] = used;
    float t[N], out[N];
    for (int v = 0; v < N; ++v)
        t[v] = 10.0f;
    t[3] = 0.02f;
    t[7] = t[8] = t[9] = 1.0f;
    t[0] = 12.0f;
    sam_error err;
    assert_int_equal(sam_thickness_ring_median(N, offsets, ring, t, out, &err), SAM_OK);
    assert_true(out[3] == 10.0f);
    assert_true(out[7] == 1.0f && out[8] == 1.0f && out[9] == 1.0f);
    assert_true(out[0] == 11.0f);
    assert_true(out[5] == 10.0f);
    assert_int_equal(sam_thickness_ring_median(N, offsets, ring, t, t, &err), SAM_ERR_INVALID_ARGUMENT);
    ring[4] = N;
    assert_int_equal(sam_thickness_ring_median(N, offsets, ring, t, out, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "names vertex 12"));
    ring[4] = 3;
    offsets[5] = offsets[6] + 1;
    assert_int_equal(sam_thickness_ring_median(N, offsets, ring, t, out, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "fall"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rule),
        cmocka_unit_test(test_slab_depth),
        cmocka_unit_test(test_sphere_radius),
        cmocka_unit_test(test_through),
        cmocka_unit_test(test_misses_take_the_cap),
        cmocka_unit_test(test_threads_bit_identical),
        cmocka_unit_test(test_refused_input),
        cmocka_unit_test(test_ring_median),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
