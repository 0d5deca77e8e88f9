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

#include "sam/sam_shape.h"
#include "sam/sam_uv.h"

static const double pi = 3.14159265358979323846;

/* A UV triangle list the tests build and free. */
typedef struct uv_mesh {
    uint32_t vertex_count, triangle_count;
    float *uvs;
    uint32_t *triangles;
} uv_mesh;

static void uv_mesh_alloc(uv_mesh *m, uint32_t vertex_count, uint32_t triangle_count)
{
    m->vertex_count = vertex_count;
    m->triangle_count = triangle_count;
    m->uvs = calloc(2 * (size_t)vertex_count + 1, sizeof *m->uvs);
    m->triangles = calloc(3 * (size_t)triangle_count + 1, sizeof *m->triangles);
    assert_non_null(m->uvs);
    assert_non_null(m->triangles);
}

static void uv_mesh_free(uv_mesh *m)
{
    free(m->uvs);
    free(m->triangles);
    memset(m, 0, sizeof *m);
}

enum { FLIP_NONE, FLIP_ALL, FLIP_ALTERNATE };

/* A grid of n x n quads with column lines at xs[0..n] and row lines at
 * ys[0..n] (UVs), two triangles per quad. The diagonal alternates with
 * the quad's parity so both diagonal slopes meet texel centres. `flip`
 * reverses the winding of all or every other triangle. */
static void grid_mesh(uv_mesh *m, uint32_t n, const float *xs, const float *ys, int flip)
{
    uv_mesh_alloc(m, (n + 1) * (n + 1), 2 * n * n);
    for (uint32_t j = 0; j <= n; ++j) {
        for (uint32_t i = 0; i <= n; ++i) {
            m->uvs[2 * (j * (n + 1) + i)] = xs[i];
            m->uvs[2 * (j * (n + 1) + i) + 1] = ys[j];
        }
    }
    uint32_t t = 0;
    for (uint32_t j = 0; j < n; ++j) {
        for (uint32_t i = 0; i < n; ++i) {
            uint32_t v00 = j * (n + 1) + i, v10 = v00 + 1, v01 = v00 + n + 1, v11 = v01 + 1;
            uint32_t q[2][3];
            if ((i + j) % 2 == 0) {
                uint32_t a[2][3] = { { v00, v10, v11 }, { v00, v11, v01 } };
                memcpy(q, a, sizeof q);
            } else {
                uint32_t a[2][3] = { { v00, v10, v01 }, { v10, v11, v01 } };
                memcpy(q, a, sizeof q);
            }
            for (int k = 0; k < 2; ++k, ++t) {
                int flip_this = flip == FLIP_ALL || (flip == FLIP_ALTERNATE && t % 2 == 1);
                m->triangles[3 * t] = q[k][0];
                m->triangles[3 * t + 1] = q[k][flip_this ? 2 : 1];
                m->triangles[3 * t + 2] = q[k][flip_this ? 1 : 2];
            }
        }
    }
}

/* Lines 0, 1 and, in between, n - 1 lines each exactly on a texel centre
 * of a resolution-r grid: (floor(k r / n) + 0.5) / r. */
static void centre_lines(float *lines, uint32_t n, uint32_t r)
{
    lines[0] = 0.0f;
    lines[n] = 1.0f;
    for (uint32_t k = 1; k < n; ++k) {
        lines[k] = (float)(((double)(k * r / n) + 0.5) / r);
        /* The test is only meaningful if the line really is on a centre. */
        double texel = (double)lines[k] * r - 0.5;
        assert_true(fabs(texel - floor(texel + 0.5)) < 1e-3);
    }
}

static sam_uv_report check_ok(const uv_mesh *m, uint32_t resolution)
{
    sam_uv_report rep;
    sam_error err;
    sam_error_clear(&err);
    sam_status st = sam_uv_check(m->uvs, m->vertex_count, m->triangles, m->triangle_count, resolution, &rep, &err);
    if (st != SAM_OK)
        fail_msg("sam_uv_check failed: %s", err.message);
    assert_int_equal(rep.resolution, resolution);
    return rep;
}

static void assert_exact_cover(const uv_mesh *m, uint32_t r)
{
    sam_uv_report rep = check_ok(m, r);
    if (rep.covered_texels != (uint64_t)r * r || rep.overlap_texels != 0)
        fail_msg("resolution %u: covered %llu of %llu texels, %llu overlapping", r,
                 (unsigned long long)rep.covered_texels, (unsigned long long)r * r,
                 (unsigned long long)rep.overlap_texels);
    assert_true(rep.overlap_fraction == 0.0f);
    assert_int_equal(rep.outside_triangles, 0);
    assert_int_equal(rep.first_outside_triangle, UINT32_MAX);
    assert_int_equal(rep.degenerate_triangles, 0);
    char reason[256] = "untouched";
    assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 1);
    assert_string_equal(reason, "");
}

/* 64 x 64 quads over [0,1]^2 whose interior lines all lie exactly on texel
 * centres (and so do the grid vertices and, at 1024, the diagonals), with
 * windings `flip`: every centre is covered exactly once. */
static void assert_centre_grid_covers_once(int flip)
{
    const uint32_t resolutions[] = { 1024, 333 };
    for (size_t r = 0; r < 2; ++r) {
        float lines[65];
        centre_lines(lines, 64, resolutions[r]);
        uv_mesh m;
        grid_mesh(&m, 64, lines, lines, flip);
        assert_exact_cover(&m, resolutions[r]);
        uv_mesh_free(&m);
    }
}

static void test_grid_covers_every_texel_once(void **state)
{
    (void)state;
    assert_centre_grid_covers_once(FLIP_NONE);
    /* The plain uniform grid k/64 (exact in float) at 96 = 32 * 3 texels:
     * every odd line k/64 = (1.5 k) / 96 lies on a centre. */
    float uniform[65];
    for (int k = 0; k <= 64; ++k)
        uniform[k] = (float)k / 64.0f;
    uv_mesh m;
    grid_mesh(&m, 64, uniform, uniform, FLIP_NONE);
    assert_exact_cover(&m, 96);
    assert_exact_cover(&m, 1024);
    assert_exact_cover(&m, 1);
    uv_mesh_free(&m);
}

static void test_flipped_windings_change_nothing(void **state)
{
    (void)state;
    for (int flip = FLIP_ALL; flip <= FLIP_ALTERNATE; ++flip)
        assert_centre_grid_covers_once(flip);
}

static uint64_t next_random(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

/* Uniform in [-1, 1). */
static float random_signed(uint64_t *s)
{
    return (float)((double)(next_random(s) >> 11) * 0x1.0p-52 - 1.0);
}

/* A grid with its interior vertices moved by up to a quarter cell in both
 * axes: edges at arbitrary slopes through arbitrary float positions, still
 * watertight, so still an exact cover. */
static void jittered_grid(uv_mesh *m, uint32_t n, uint64_t seed, int flip)
{
    float lines[4097];
    for (uint32_t k = 0; k <= n; ++k)
        lines[k] = (float)k / (float)n;
    grid_mesh(m, n, lines, lines, flip);
    uint64_t s = seed;
    for (uint32_t j = 1; j < n; ++j) {
        for (uint32_t i = 1; i < n; ++i) {
            float *uv = m->uvs + 2 * (j * (n + 1) + i);
            uv[0] += 0.25f * random_signed(&s) / (float)n;
            uv[1] += 0.25f * random_signed(&s) / (float)n;
        }
    }
}

static void test_jittered_grid_is_an_exact_cover(void **state)
{
    (void)state;
    uv_mesh m;
    jittered_grid(&m, 100, 0x9e3779b97f4a7c15ull, FLIP_NONE);
    assert_exact_cover(&m, 1024);
    assert_exact_cover(&m, 333);
    uv_mesh_free(&m);
    jittered_grid(&m, 37, 12345, FLIP_ALTERNATE);
    assert_exact_cover(&m, 999);
    uv_mesh_free(&m);
}

/* A fan of 16 triangles around a vertex on a texel centre, with spokes in
 * every direction (horizontal and vertical ones included): the centre is
 * covered by exactly one of them. The same polygon fanned from a corner
 * instead must cover the same number of texels. */
static void test_fan_around_a_texel_centre(void **state)
{
    (void)state;
    const uint32_t r = 64, spokes = 16;
    uv_mesh centre_fan, corner_fan;
    uv_mesh_alloc(&centre_fan, spokes + 1, spokes);
    uv_mesh_alloc(&corner_fan, spokes, spokes - 2);
    const float c = 32.5f / 64.0f;
    centre_fan.uvs[0] = c;
    centre_fan.uvs[1] = c;
    for (uint32_t k = 0; k < spokes; ++k) {
        /* Spokes to texel centres on a 16-gon-ish ring; k = 0, 4, 8, 12 are axis aligned. */
        double a = 2.0 * pi * k / spokes;
        float u = (float)((32.5 + floor(10.0 * cos(a) + 0.5)) / 64.0);
        float v = (float)((32.5 + floor(10.0 * sin(a) + 0.5)) / 64.0);
        centre_fan.uvs[2 * (k + 1)] = corner_fan.uvs[2 * k] = u;
        centre_fan.uvs[2 * (k + 1) + 1] = corner_fan.uvs[2 * k + 1] = v;
        centre_fan.triangles[3 * k] = 0;
        centre_fan.triangles[3 * k + 1] = k + 1;
        centre_fan.triangles[3 * k + 2] = (k + 1) % spokes + 1;
    }
    for (uint32_t k = 0; k + 2 < spokes; ++k) {
        corner_fan.triangles[3 * k] = 0;
        corner_fan.triangles[3 * k + 1] = k + 1;
        corner_fan.triangles[3 * k + 2] = k + 2;
    }
    sam_uv_report a = check_ok(&centre_fan, r), b = check_ok(&corner_fan, r);
    assert_int_equal(a.overlap_texels, 0);
    assert_int_equal(b.overlap_texels, 0);
    assert_int_equal(a.degenerate_triangles, 0);
    assert_true(a.covered_texels > 200);
    assert_int_equal(a.covered_texels, b.covered_texels);
    uv_mesh_free(&centre_fan);
    uv_mesh_free(&corner_fan);
}

/* The left half of a surface reuses the right half's UVs, mirrored (so its
 * triangles are clockwise in UV): every covered texel is covered twice. */
static void test_mirrored_half_overlaps_everywhere(void **state)
{
    (void)state;
    float xs[65];
    for (int k = 0; k <= 64; ++k)
        xs[k] = (float)k / 64.0f;
    uv_mesh m;
    grid_mesh(&m, 64, xs, xs, FLIP_NONE);
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        if (m.uvs[2 * v] < 0.5f)
            m.uvs[2 * v] = 1.0f - m.uvs[2 * v];
    }
    sam_uv_report rep = check_ok(&m, 1024);
    assert_int_equal(rep.covered_texels, 512u * 1024u);
    assert_int_equal(rep.overlap_texels, 512u * 1024u);
    assert_true(rep.overlap_fraction > 0.999f);
    assert_int_equal(rep.outside_triangles, 0);
    char reason[256];
    assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 0);
    assert_non_null(strstr(reason, "more than one"));
    assert_non_null(strstr(reason, "100%"));
    assert_null(strchr(reason, '\n'));
    print_message("mirrored half: %s\n", reason);
    uv_mesh_free(&m);
}

/* Appends the square (or any quad) a b c d as two triangles. */
static void add_quad(uv_mesh *m, uint32_t *v, uint32_t *t, const float q[4][2])
{
    for (int k = 0; k < 4; ++k) {
        m->uvs[2 * (*v + k)] = q[k][0];
        m->uvs[2 * (*v + k) + 1] = q[k][1];
    }
    const uint32_t idx[6] = { 0, 1, 2, 0, 2, 3 };
    for (int k = 0; k < 6; ++k)
        m->triangles[3 * *t + k] = *v + idx[k];
    *v += 4;
    *t += 2;
}

static void assert_relative(double measured, double expected, double tolerance, const char *what)
{
    if (fabs(measured - expected) > tolerance * fabs(expected))
        fail_msg("%s: measured %.6f, expected %.6f (tolerance %.1f%%)", what, measured, expected,
                 100.0 * tolerance);
}

static void test_overlapping_squares_match_the_analytic_area(void **state)
{
    (void)state;
    const uint32_t r = 1024;
    /* Two 0.4 squares offset by 0.2 in u and v: they share a quarter of
     * either, 0.04 of 0.28 covered, 1/7. Bounds off the texel lattice. */
    {
        uv_mesh m;
        uv_mesh_alloc(&m, 8, 4);
        uint32_t v = 0, t = 0;
        const float a = 0.1037f, b = a + 0.2f, s = 0.4f;
        const float sq1[4][2] = { { a, a }, { a + s, a }, { a + s, a + s }, { a, a + s } };
        const float sq2[4][2] = { { b, b }, { b + s, b }, { b + s, b + s }, { b, b + s } };
        add_quad(&m, &v, &t, sq1);
        add_quad(&m, &v, &t, sq2);
        sam_uv_report rep = check_ok(&m, r);
        assert_relative(rep.overlap_fraction, 0.04 / 0.28, 0.01, "quarter-overlap fraction");
        assert_relative((double)rep.overlap_texels, 0.04 * r * r, 0.01, "quarter-overlap texels");
        assert_relative((double)rep.covered_texels, 0.28 * r * r, 0.01, "quarter-overlap coverage");
        char reason[256];
        assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 0);
        assert_non_null(strstr(reason, "% of the covered atlas texels are covered by more than one triangle"));
        uv_mesh_free(&m);
    }
    /* A 0.4 square turned by 30 degrees, clockwise, inside a 0.9 square:
     * 0.16 of 0.81 covered twice. */
    {
        uv_mesh m;
        uv_mesh_alloc(&m, 8, 4);
        uint32_t v = 0, t = 0;
        const float big[4][2] = { { 0.05f, 0.05f }, { 0.95f, 0.05f }, { 0.95f, 0.95f }, { 0.05f, 0.95f } };
        float turned[4][2];
        for (int k = 0; k < 4; ++k) {
            double a = pi / 6.0 - 2.0 * pi * k / 4.0 + pi / 4.0, h = 0.2 * sqrt(2.0);
            turned[k][0] = (float)(0.5 + h * cos(a));
            turned[k][1] = (float)(0.5 + h * sin(a));
        }
        add_quad(&m, &v, &t, big);
        add_quad(&m, &v, &t, (const float(*)[2])turned);
        sam_uv_report rep = check_ok(&m, r);
        assert_relative(rep.overlap_fraction, 0.16 / 0.81, 0.01, "turned-square fraction");
        assert_relative((double)rep.covered_texels, 0.81 * r * r, 0.01, "turned-square coverage");
        assert_int_equal(sam_uv_usable(&rep, NULL, 0), 0);
        uv_mesh_free(&m);
    }
}

static void test_uv_outside_the_unit_square(void **state)
{
    (void)state;
    uv_mesh m;
    uv_mesh_alloc(&m, 8, 4);
    uint32_t v = 0, t = 0;
    const float left[4][2] = { { 0.0f, 0.0f }, { 0.5f, 0.0f }, { 0.5f, 0.5f }, { 0.0f, 0.5f } };
    const float right[4][2] = { { 0.5f, 0.5f }, { 1.0f, 0.5f }, { 1.0f, 1.0f }, { 0.5f, 1.0f } };
    add_quad(&m, &v, &t, left);
    add_quad(&m, &v, &t, right);
    m.uvs[2 * 5] = 1.2f; /* vertex 5 is used by triangle 2 only */
    sam_uv_report rep = check_ok(&m, 100);
    assert_int_equal(rep.outside_triangles, 1);
    assert_int_equal(rep.first_outside_triangle, 2);
    assert_int_equal(rep.overlap_texels, 0);
    char reason[256];
    assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 0);
    assert_string_equal(reason, "1 triangle (triangle 2) has UVs outside [0,1]");

    /* Several outside, one of them absurdly far (not rasterised). */
    m.uvs[2 * 0] = -0.5f;
    m.uvs[2 * 6 + 1] = 1e30f;
    rep = check_ok(&m, 100);
    assert_int_equal(rep.outside_triangles, 4);
    assert_int_equal(rep.first_outside_triangle, 0);
    assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 0);
    assert_non_null(strstr(reason, "4 triangles have UVs outside [0,1] (the first is triangle 0)"));
    uv_mesh_free(&m);

    /* The part of an outside triangle on the grid is still rasterised:
     * the square [-0.5, 0.5]^2 covers 50 x 50 centres of 100 x 100. */
    uv_mesh_alloc(&m, 4, 2);
    v = t = 0;
    const float straddle[4][2] = { { -0.5f, -0.5f }, { 0.5f, -0.5f }, { 0.5f, 0.5f }, { -0.5f, 0.5f } };
    add_quad(&m, &v, &t, straddle);
    rep = check_ok(&m, 100);
    assert_int_equal(rep.covered_texels, 2500);
    assert_int_equal(rep.outside_triangles, 2);
    uv_mesh_free(&m);
}

/* The fitted atlas: a layout in the unit square stays as it is; one past
 * it (slightly, tiled, or wrapping around a seam) moves in whole, with one
 * scale, and charts that did not overlap still do not. */
static void test_fit_atlas_moves_layouts_past_the_square(void **state)
{
    (void)state;
    uv_mesh m;
    uv_mesh_alloc(&m, 9, 4);
    uint32_t v = 0, t = 0;
    const float a[4][2] = { { 0.0f, 0.0f }, { 0.5f, 0.0f }, { 0.5f, 0.5f }, { 0.0f, 0.5f } };
    const float b[4][2] = { { 0.5f, 0.5f }, { 1.0f, 0.5f }, { 1.0f, 1.0f }, { 0.5f, 1.0f } };
    add_quad(&m, &v, &t, a);
    add_quad(&m, &v, &t, b);
    m.uvs[2 * 8] = 7.0f; /* vertex 8: no triangle uses it */
    float out[18];
    sam_uv_atlas atlas;
    sam_error err;
    assert_int_equal(sam_uv_fit_atlas(m.uvs, m.vertex_count, m.triangles, m.triangle_count, &atlas, out, &err),
                     SAM_OK);
    assert_int_equal(atlas.moved, 0);
    assert_true(atlas.scale == 1.0f && atlas.offset[0] == 0.0f && atlas.offset[1] == 0.0f);
    assert_memory_equal(out, m.uvs, sizeof out);

    /* u from -0.05 to 0.99 (a real scan's): moved by 0.05, scaled 1 / 1.04. */
    for (uint32_t k = 0; k < 8; ++k)
        m.uvs[2 * k] = m.uvs[2 * k] * 1.04f - 0.05f;
    assert_int_equal(sam_uv_fit_atlas(m.uvs, m.vertex_count, m.triangles, m.triangle_count, &atlas, out, &err),
                     SAM_OK);
    assert_int_equal(atlas.moved, 1);
    assert_relative(atlas.scale, 1.0 / 1.04, 1e-6, "scale");
    assert_relative(atlas.lo[0], -0.05, 1e-6, "lowest u");
    for (uint32_t k = 0; k < 8; ++k) {
        assert_true(fabs(out[2 * k] - (m.uvs[2 * k] + 0.05) / 1.04) < 1e-6);
        assert_true(fabs(out[2 * k + 1] - m.uvs[2 * k + 1] / 1.04) < 1e-6);
    }
    assert_true(out[16] == 1.0f); /* the unused vertex, clamped */
    sam_uv_report rep = check_ok(&m, 100);
    assert_int_equal(sam_uv_usable(&rep, NULL, 0), 0);
    uv_mesh tmp = m;
    tmp.uvs = out;
    rep = check_ok(&tmp, 100);
    assert_int_equal(sam_uv_usable(&rep, NULL, 0), 1);

    /* Tiled four times (u, v from 0 to 4): scaled by a quarter. */
    for (uint32_t k = 0; k < 8; ++k) {
        const float *q = k < 4 ? a[k] : b[k - 4];
        m.uvs[2 * k] = 4.0f * q[0];
        m.uvs[2 * k + 1] = 4.0f * q[1];
    }
    assert_int_equal(sam_uv_fit_atlas(m.uvs, m.vertex_count, m.triangles, m.triangle_count, &atlas, out, &err),
                     SAM_OK);
    assert_true(atlas.moved && atlas.scale == 0.25f);
    for (uint32_t k = 0; k < 8; ++k)
        assert_true(out[2 * k] == (k < 4 ? a[k] : b[k - 4])[0]);

    /* Wrapping around a seam: chart b at u = 0.9..1.4 would land on chart a
     * (u = 0..0.5) if wrapped; moved whole, the two stay apart. */
    for (uint32_t k = 0; k < 8; ++k) {
        const float *q = k < 4 ? a[k] : b[k - 4];
        m.uvs[2 * k] = k < 4 ? q[0] : q[0] + 0.4f;
        m.uvs[2 * k + 1] = q[1];
    }
    assert_int_equal(sam_uv_fit_atlas(m.uvs, m.vertex_count, m.triangles, m.triangle_count, &atlas, out, &err),
                     SAM_OK);
    tmp.uvs = out;
    rep = check_ok(&tmp, 100);
    assert_int_equal(rep.overlap_texels, 0);
    assert_int_equal(sam_uv_usable(&rep, NULL, 0), 1);

    /* Errors, named as sam_uv_check names them. */
    m.uvs[2] = NAN;
    assert_int_equal(sam_uv_fit_atlas(m.uvs, m.vertex_count, m.triangles, m.triangle_count, &atlas, out, &err),
                     SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "sam_uv_fit_atlas: vertex 1 has a non-finite UV"));
    m.uvs[2] = 0.0f;
    m.triangles[4] = 9;
    assert_int_equal(sam_uv_fit_atlas(m.uvs, m.vertex_count, m.triangles, m.triangle_count, &atlas, out, &err),
                     SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "triangle 1 corner 1 has index 9 (vertex count 9)"));
    assert_int_equal(sam_uv_fit_atlas(m.uvs, m.vertex_count, m.triangles, m.triangle_count, NULL, out, &err),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_uv_fit_atlas(NULL, 0, NULL, 0, &atlas, NULL, &err), SAM_OK);
    assert_int_equal(atlas.moved, 0);
    uv_mesh_free(&m);
}

static void test_degenerate_triangles_cover_nothing(void **state)
{
    (void)state;
    uv_mesh m;
    uv_mesh_alloc(&m, 6, 4);
    const float uvs[12] = { 0.1f, 0.1f, 0.9f, 0.1f, 0.5f, 0.9f, /* a real triangle */
                            0.2f, 0.2f, 0.4f, 0.4f, 0.8f, 0.8f /* collinear */ };
    const uint32_t tris[12] = { 0, 1, 2, 3, 4, 5, 1, 1, 2, 4, 4, 4 };
    memcpy(m.uvs, uvs, sizeof uvs);
    memcpy(m.triangles, tris, sizeof tris);
    sam_uv_report with = check_ok(&m, 256);
    assert_int_equal(with.degenerate_triangles, 3);
    assert_int_equal(with.overlap_texels, 0);
    m.triangle_count = 1;
    sam_uv_report without = check_ok(&m, 256);
    assert_int_equal(without.degenerate_triangles, 0);
    assert_int_equal(with.covered_texels, without.covered_texels);
    assert_int_equal(sam_uv_usable(&with, NULL, 0), 1);

    /* Only degenerate triangles: nothing covered, unusable. */
    memmove(m.triangles, m.triangles + 3, 9 * sizeof *m.triangles);
    m.triangle_count = 3;
    sam_uv_report none = check_ok(&m, 256);
    assert_int_equal(none.covered_texels, 0);
    assert_true(none.overlap_fraction == 0.0f);
    char reason[256];
    assert_int_equal(sam_uv_usable(&none, reason, sizeof reason), 0);
    assert_non_null(strstr(reason, "cover no texel centre of the 256x256 grid"));
    uv_mesh_free(&m);

    /* No triangles at all is not an error, just unusable. */
    sam_uv_report empty = check_ok(&(uv_mesh){ 0 }, 16);
    assert_int_equal(empty.covered_texels, 0);
    assert_int_equal(sam_uv_usable(&empty, NULL, 0), 0);
}

static void expect_failure(const float *uvs, uint32_t vertex_count, const uint32_t *triangles,
                           uint32_t triangle_count, uint32_t resolution, sam_status status,
                           const char *needle)
{
    sam_uv_report rep;
    memset(&rep, 0x5a, sizeof rep);
    sam_error err;
    sam_error_clear(&err);
    assert_int_equal(sam_uv_check(uvs, vertex_count, triangles, triangle_count, resolution, &rep, &err),
                     status);
    assert_int_equal(err.status, status);
    if (!strstr(err.message, needle))
        fail_msg("message \"%s\" lacks \"%s\"", err.message, needle);
    assert_int_equal(rep.covered_texels, 0);
    assert_int_equal(rep.resolution, 0);
    /* A NULL error is allowed; the status is the same. */
    assert_int_equal(sam_uv_check(uvs, vertex_count, triangles, triangle_count, resolution, &rep, NULL),
                     status);
}

static void test_bad_arguments_are_named(void **state)
{
    (void)state;
    float uvs[8] = { 0.0f, 0.0f, 1.0f, 0.0f, 1.0f, 1.0f, 0.0f, 1.0f };
    const uint32_t tris[6] = { 0, 1, 2, 0, 2, 7 };
    expect_failure(uvs, 4, tris, 2, 64, SAM_ERR_FORMAT, "triangle 1 corner 2 has index 7 (vertex count 4)");

    const uint32_t good[6] = { 0, 1, 2, 0, 2, 3 };
    uvs[5] = NAN;
    expect_failure(uvs, 4, good, 2, 64, SAM_ERR_FORMAT, "vertex 2 has a non-finite UV");
    uvs[5] = 1.0f;
    uvs[6] = -INFINITY;
    expect_failure(uvs, 4, good, 2, 64, SAM_ERR_FORMAT, "vertex 3 has a non-finite UV (-inf, 1)");
    uvs[6] = 0.0f;

    expect_failure(uvs, 4, good, 2, 0, SAM_ERR_INVALID_ARGUMENT, "resolution 0 is outside 1..8192");
    expect_failure(uvs, 4, good, 2, 8193, SAM_ERR_INVALID_ARGUMENT, "resolution 8193");
    expect_failure(NULL, 4, good, 2, 64, SAM_ERR_INVALID_ARGUMENT, "NULL uvs for 4 vertices");
    expect_failure(uvs, 4, NULL, 2, 64, SAM_ERR_INVALID_ARGUMENT, "NULL triangles for 2 triangles");
    assert_int_equal(sam_uv_check(uvs, 4, good, 2, 64, NULL, NULL), SAM_ERR_INVALID_ARGUMENT);

    /* NULL arrays with zero counts are fine. */
    sam_uv_report rep;
    assert_int_equal(sam_uv_check(NULL, 0, NULL, 0, 64, &rep, NULL), SAM_OK);
    assert_int_equal(rep.resolution, 64);
}

static void test_usable_reason_buffer(void **state)
{
    (void)state;
    sam_uv_report rep = { .resolution = 1024, .covered_texels = 1000, .overlap_texels = 125,
                          .overlap_fraction = 0.125f, .outside_triangles = 37, .first_outside_triangle = 5 };
    char reason[512];
    assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 0);
    assert_string_equal(reason, "37 triangles have UVs outside [0,1] (the first is triangle 5); 12.5% of the "
                                "covered atlas texels are covered by more than one triangle (mirrored or "
                                "stacked UV islands)");
    char small[8];
    memset(small, 'x', sizeof small);
    assert_int_equal(sam_uv_usable(&rep, small, sizeof small), 0);
    assert_int_equal(strlen(small), sizeof small - 1);
    assert_int_equal(sam_uv_usable(&rep, NULL, 0), 0);
    char one = 'x';
    assert_int_equal(sam_uv_usable(&rep, &one, 1), 0);
    assert_int_equal(one, '\0');

    /* Overlap at the tolerance passes, above it fails; NaN fails. */
    rep.outside_triangles = 0;
    rep.first_outside_triangle = UINT32_MAX;
    rep.overlap_fraction = SAM_UV_MAX_OVERLAP;
    assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 1);
    assert_string_equal(reason, "");
    rep.overlap_fraction = 2.0f * SAM_UV_MAX_OVERLAP;
    assert_int_equal(sam_uv_usable(&rep, reason, sizeof reason), 0);
    assert_non_null(strstr(reason, "0.2% of the covered"));
    rep.overlap_fraction = NAN;
    assert_int_equal(sam_uv_usable(&rep, NULL, 0), 0);
    assert_int_equal(sam_uv_usable(NULL, reason, sizeof reason), 0);
    assert_string_equal(reason, "no UV report");
}

/* The largest grid: [0.25, 0.75]^2 has exactly 4096^2 centres of 8192^2. */
static void test_max_resolution(void **state)
{
    (void)state;
    uv_mesh m;
    uv_mesh_alloc(&m, 4, 2);
    uint32_t v = 0, t = 0;
    const float sq[4][2] = { { 0.25f, 0.25f }, { 0.75f, 0.25f }, { 0.75f, 0.75f }, { 0.25f, 0.75f } };
    add_quad(&m, &v, &t, sq);
    double t0 = sam_seconds();
    sam_uv_report rep = check_ok(&m, SAM_UV_MAX_RESOLUTION);
    double t1 = sam_seconds();
    assert_int_equal(rep.covered_texels, 4096ull * 4096ull);
    assert_int_equal(rep.overlap_texels, 0);
    print_message("2 triangles at %ux%u: %.1f ms\n", SAM_UV_MAX_RESOLUTION, SAM_UV_MAX_RESOLUTION,
                  1e3 * (t1 - t0));
    uv_mesh_free(&m);
}

/* Built-in shape `name` at resolution 48, its other parameters the defaults. */
static void built_in_shape(const char *name, sam_shape_mesh *s)
{
    sam_shape_params p;
    sam_error err;
    assert_int_equal(sam_shape_default_params(name, &p, &err), SAM_OK);
    p.resolution = 48;
    if (sam_shape_generate(name, &p, s, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

/* sam_shape promises charts that never share texture space. */
static void test_built_in_shapes_are_usable(void **state)
{
    (void)state;
    size_t count;
    const char *const *names = sam_shape_names(&count);
    for (size_t k = 0; k < count; ++k) {
        sam_shape_mesh s;
        built_in_shape(names[k], &s);
        uv_mesh m = { s.vertex_count, s.triangle_count, s.uvs, s.triangles };
        sam_uv_report rep = check_ok(&m, 1024);
        char reason[256];
        int usable = sam_uv_usable(&rep, reason, sizeof reason);
        print_message("%-6s %7u triangles: covered %.1f%%, %llu overlapping texels%s%s\n", names[k],
                      s.triangle_count, 100.0 * (double)rep.covered_texels / (1024.0 * 1024.0),
                      (unsigned long long)rep.overlap_texels, usable ? "" : ": ", reason);
        assert_int_equal(rep.overlap_texels, 0);
        assert_int_equal(usable, 1);
        sam_shape_mesh_destroy(&s);
    }
}

/* Crossings of a unit square of two triangles, (0,1,2) and (0,2,3), whose
 * diagonal's ends are `copies` vertices: 4 (one chart) or 6 (the second
 * triangle's diagonal ends are copies with other UVs: a seam). */
static void square(int copies, float *pos, float *uv, uint32_t *tri)
{
    static const float p[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {1, 1, 0}};
    static const float u[6][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}, {0.9f, 0.9f}};
    memcpy(pos, p, sizeof p);
    memcpy(uv, u, sizeof u);
    const uint32_t t[6] = {0, 1, 2, copies == 6 ? 4 : 0, copies == 6 ? 5 : 2, 3};
    memcpy(tri, t, sizeof t);
}

static void test_crossings_of_a_square(void **state)
{
    (void)state;
    for (int copies = 4; copies <= 6; copies += 2) {
        float pos[18], uv[12];
        uint32_t tri[6], across[6], chart[2];
        sam_error err;
        square(copies, pos, uv, tri);
        assert_int_equal(sam_uv_crossings(pos, uv, (uint32_t)copies, tri, 2, across, chart, &err), SAM_OK);
        /* Triangle 0's edge 2 (corner 2 to 0) is the diagonal, triangle 1's
         * edge 0 (corner 0 to 2) the same; the rest is boundary. */
        const uint32_t expect[6] = {SAM_UV_NO_CROSSING, SAM_UV_NO_CROSSING, 4 * 1 + 0,
                                    4 * 0 + 2,          SAM_UV_NO_CROSSING, SAM_UV_NO_CROSSING};
        assert_memory_equal(across, expect, sizeof expect);
        assert_int_equal(chart[0], 0);
        assert_int_equal(chart[1], copies == 6 ? 1 : 0);
    }
}

/* A fin: three triangles on one edge. Which would the light go on into?
 * None: the edge gets no crossing, the others stay boundary. */
static void test_crossings_skip_non_manifold_edges(void **state)
{
    (void)state;
    const float pos[5][3] = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}};
    const float uv[5][2] = {{0, 0}, {0, 1}, {1, 0}, {0.5f, 0.5f}, {0.2f, 0.7f}};
    const uint32_t tri[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    uint32_t across[9], chart[3];
    sam_error err;
    assert_int_equal(sam_uv_crossings(&pos[0][0], &uv[0][0], 5, tri, 3, across, chart, &err), SAM_OK);
    for (int k = 0; k < 9; ++k)
        assert_int_equal(across[k], SAM_UV_NO_CROSSING);
    assert_int_equal(chart[0], 0);
    assert_int_equal(chart[1], 1);
    assert_int_equal(chart[2], 2);
    const uint32_t bad[3] = {0, 1, 5};
    assert_int_equal(sam_uv_crossings(&pos[0][0], &uv[0][0], 5, bad, 1, across, chart, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "triangle 0 corner 2 has index 5 (vertex count 5)"));
    assert_int_equal(sam_uv_crossings(NULL, &uv[0][0], 5, tri, 3, across, chart, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_uv_crossings(NULL, NULL, 0, NULL, 0, NULL, NULL, &err), SAM_OK);
}

/* Every edge of the closed built-in shapes has a crossing; crossings pair
 * up both ways and join the same two positions; seams part charts, which
 * the shapes have several of. */
static void test_built_in_shapes_cross_every_edge(void **state)
{
    (void)state;
    size_t count;
    const char *const *names = sam_shape_names(&count);
    for (size_t k = 0; k < count; ++k) {
        sam_shape_mesh s;
        sam_error err;
        built_in_shape(names[k], &s);
        uint32_t *across = malloc(3 * (size_t)s.triangle_count * sizeof *across);
        uint32_t *chart = malloc((size_t)s.triangle_count * sizeof *chart);
        assert_non_null(across);
        assert_non_null(chart);
        assert_int_equal(sam_uv_crossings(s.positions, s.uvs, s.vertex_count, s.triangles, s.triangle_count, across,
                                          chart, &err),
                         SAM_OK);
        uint32_t charts = 0, seams = 0;
        for (uint32_t t = 0; t < s.triangle_count; ++t) {
            assert_true(chart[t] <= charts);
            charts += chart[t] == charts;
            for (uint32_t e = 0; e < 3; ++e) {
                const uint32_t f = across[3 * t + e];
                assert_int_not_equal(f, SAM_UV_NO_CROSSING);
                assert_int_equal(across[3 * (size_t)(f >> 2) + (f & 3)], 4 * t + e);
                const float *a = s.positions + 3 * (size_t)s.triangles[3 * t + e];
                const float *b = s.positions + 3 * (size_t)s.triangles[3 * t + (e + 1) % 3];
                const uint32_t *g = s.triangles + 3 * (size_t)(f >> 2);
                assert_memory_equal(a, s.positions + 3 * (size_t)g[((f & 3) + 1) % 3], 3 * sizeof(float));
                assert_memory_equal(b, s.positions + 3 * (size_t)g[f & 3], 3 * sizeof(float));
                seams += chart[f >> 2] != chart[t];
            }
        }
        print_message("%-10s %6u triangles, %u charts, %u seam edges\n", names[k], s.triangle_count, charts, seams / 2);
        assert_true(charts > 1);
        assert_true(seams > 0);
        free(across);
        free(chart);
        sam_shape_mesh_destroy(&s);
    }
}

/* About a million triangles at 1024^2; the time is printed, not asserted
 * (sanitizer and debug builds are much slower). */
static void test_timing_million_triangles(void **state)
{
    (void)state;
    uv_mesh m;
    jittered_grid(&m, 708, 42, FLIP_NONE); /* 2 * 708^2 = 1,002,528 triangles */
    double best = INFINITY;
    sam_uv_report rep;
    for (int run = 0; run < 3; ++run) {
        double t0 = sam_seconds();
        rep = check_ok(&m, 1024);
        double dt = sam_seconds() - t0;
        best = dt < best ? dt : best;
    }
    assert_int_equal(rep.covered_texels, 1024u * 1024u);
    assert_int_equal(rep.overlap_texels, 0);
    print_message("%u triangles at 1024x1024: %.1f ms (best of 3)\n", m.triangle_count, 1e3 * best);
    uv_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_covers_every_texel_once),
        cmocka_unit_test(test_flipped_windings_change_nothing),
        cmocka_unit_test(test_jittered_grid_is_an_exact_cover),
        cmocka_unit_test(test_fan_around_a_texel_centre),
        cmocka_unit_test(test_mirrored_half_overlaps_everywhere),
        cmocka_unit_test(test_overlapping_squares_match_the_analytic_area),
        cmocka_unit_test(test_uv_outside_the_unit_square),
        cmocka_unit_test(test_fit_atlas_moves_layouts_past_the_square),
        cmocka_unit_test(test_degenerate_triangles_cover_nothing),
        cmocka_unit_test(test_bad_arguments_are_named),
        cmocka_unit_test(test_usable_reason_buffer),
        cmocka_unit_test(test_max_resolution),
        cmocka_unit_test(test_built_in_shapes_are_usable),
        cmocka_unit_test(test_crossings_of_a_square),
        cmocka_unit_test(test_crossings_skip_non_manifold_edges),
        cmocka_unit_test(test_built_in_shapes_cross_every_edge),
        cmocka_unit_test(test_timing_million_triangles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
