/*
 * sam_build against closed forms, a numerical quadrature and the O(m^2)
 * brute-force reference, on procedural meshes.
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

#include "sam/sam_build.h"
#include "sam_test.h"

#define PI 3.14159265358979323846

/* Two flat hexagonal fans of radius `r` in planes z = 0 (normal +z... as a
 * closed-ish pair: each fan is a 6-triangle disk), centres `d` apart on z. */
static void two_fans(float r, float d, sam_mesh *mesh)
{
    float pos[14 * 3];
    uint32_t tri[12 * 3];
    for (int f = 0; f < 2; ++f) {
        float z = f ? d : 0.0f;
        float *c = pos + 3 * 7 * f;
        c[0] = 0, c[1] = 0, c[2] = z;
        for (int k = 0; k < 6; ++k) {
            c[3 + 3 * k] = r * (float)cos(k * PI / 3);
            c[3 + 3 * k + 1] = r * (float)sin(k * PI / 3);
            c[3 + 3 * k + 2] = z;
        }
        for (int k = 0; k < 6; ++k) {
            uint32_t a = 7 * f + 1 + k, b = 7 * f + 1 + (k + 1) % 6, o = 7 * f;
            /* the lower fan faces -z (towards nothing), the upper +z... both
             * wound so the pair faces away from each other */
            uint32_t t[3] = {o, f ? a : b, f ? b : a};
            memcpy(tri + 3 * (6 * f + k), t, sizeof t);
        }
    }
    sam_mesh_input in = {.name = "fans", .vertex_count = 14, .positions = pos, .triangle_count = 12,
                         .triangles = tri};
    assert_int_equal(sam_mesh_create(&in, mesh, NULL, NULL), SAM_OK);
}

static sam_build_context *context(const sam_mesh *mesh, const sam_profile *profile, float mm_per_unit,
                                  const sam_build_settings *s)
{
    sam_build_context *ctx;
    sam_error err;
    if (sam_build_context_create(mesh, profile, mm_per_unit, s, &ctx, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return ctx;
}

/* A flat-map context on `mesh` at 1 mm per unit in the material preset
 * `preset`, whose profile goes into *profile (it must outlive the context). */
static sam_build_context *flat_context(const sam_mesh *mesh, const char *preset, sam_profile *profile)
{
    assert_int_equal(sam_profile_preset(preset, profile, NULL), SAM_OK);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    return context(mesh, profile, 1.0f, &s);
}

static float mean3(const float *k)
{
    return (k[0] + k[1] + k[2]) / 3.0f;
}

/* Small fans far apart: K -> F'_i R_d(d), so K' -> 1. */
static void test_far_small_fans(void **state)
{
    (void)state;
    sam_mesh mesh;
    two_fans(0.02f, 3.0f, &mesh);
    sam_profile marble;
    sam_build_context *ctx = flat_context(&mesh, "marble", &marble);
    uint32_t o = mesh.topo_of[0], i = mesh.topo_of[7];
    float k[3], e, rd[3];
    sam_build_form_factor(ctx, o, i, 256, 7, k, &e);
    sam_profile_eval(&marble, 3.0f, rd);
    float area = sam_build_fan_area(ctx, i);
    /* Fan area: a hexagon of radius r has area 3 sqrt(3)/2 r^2, the reduced
     * fan a third of it. */
    assert_float_equal(area, 3 * sqrt(3.0) / 2 * 0.02 * 0.02 / 3, 1e-9);
    for (int c = 0; c < 3; ++c)
        assert_float_equal(k[c] / (area * rd[c]), 1.0, 1e-3);
    assert_true(sam_build_is_back_side(ctx, o, i));
    assert_true(sam_build_is_back_side(ctx, i, o));
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* A constant profile (one Gaussian far wider than the fans) gives K = F'_i
 * times that constant, exactly, whatever the samples, where F'_i is behind
 * o's fan; and 0 from o's own side (no point of it is behind another). */
static void test_constant_profile(void **state)
{
    (void)state;
    sam_mesh mesh;
    two_fans(0.5f, 1.0f, &mesh);
    float variance = 1e8f, weight[1][3] = {{1.0f, 0.5f, 0.25f}};
    sam_profile flat;
    assert_int_equal(sam_profile_gaussian_sum(1, &variance, weight, &flat, NULL), SAM_OK);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    sam_build_context *ctx = context(&mesh, &flat, 1.0f, &s);
    float rd0[3];
    sam_profile_eval(&flat, 0.0f, rd0);
    int behind = 0, beside = 0;
    for (uint32_t i = 0; i < mesh.topo_count; i += 3) {
        float k[3], e;
        sam_build_form_factor(ctx, mesh.topo_of[0], i, 16, 3, k, &e);
        const int back = sam_build_is_back_side(ctx, mesh.topo_of[0], i);
        behind += back;
        beside += !back;
        for (int c = 0; c < 3; ++c) {
            if (back)
                assert_float_equal(k[c] / (sam_build_fan_area(ctx, i) * rd0[c]), 1.0, 1e-5);
            else
                assert_true(k[c] == 0.0f);
        }
        assert_true(e <= 1e-6f * mean3(k));
    }
    assert_true(behind > 0 && beside > 0);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* Midpoint quadrature of topo vertex t's reduced fan: each of its
 * half-quads (vertex, edge midpoint, centroid) split into QUAD_L^2
 * sub-triangles, one point at each centroid. Returns the point count. */
enum { QUAD_L = 12, QUAD_MAX = 12 * QUAD_L * QUAD_L };
static int fan_quadrature_points(const sam_mesh *mesh, uint32_t t, float (*qp)[3], float *qw)
{
    int nq = 0;
    const float *v = mesh->positions + 3 * mesh->topo_rep[t];
    for (uint32_t k = mesh->ring_offsets[t] + 1; k < mesh->ring_offsets[t + 1]; ++k) {
        const float *a = mesh->positions + 3 * mesh->topo_rep[mesh->ring[k - 1]];
        const float *b = mesh->positions + 3 * mesh->topo_rep[mesh->ring[k]];
        for (int half = 0; half < 2; ++half) {
            float p0[3], p1[3], p2[3];
            for (int c = 0; c < 3; ++c) {
                p0[c] = v[c];
                p1[c] = 0.5f * (v[c] + (half ? b[c] : a[c]));
                p2[c] = (v[c] + a[c] + b[c]) / 3.0f;
            }
            double e1[3], e2[3];
            for (int c = 0; c < 3; ++c)
                e1[c] = p1[c] - p0[c], e2[c] = p2[c] - p0[c];
            double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                   cz = e1[0] * e2[1] - e1[1] * e2[0];
            double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz) / (QUAD_L * QUAD_L);
            /* Sub-triangles of a regular L x L subdivision, by barycentric centroids. */
            for (int i = 0; i < QUAD_L; ++i)
                for (int j = 0; j < QUAD_L - i; ++j)
                    for (int up = 0; up < 2 && (up == 0 || i + j + 1 < QUAD_L); ++up) {
                        double u = up ? (i + 2.0 / 3) / QUAD_L : (i + 1.0 / 3) / QUAD_L;
                        double w = up ? (j + 2.0 / 3) / QUAD_L : (j + 1.0 / 3) / QUAD_L;
                        for (int c = 0; c < 3; ++c)
                            qp[nq][c] = (float)(p0[c] + u * e1[c] + w * e2[c]);
                        qw[nq++] = (float)area;
                    }
        }
    }
    return nq;
}

/* K_oi by the quadrature of both fans (mm per unit 1) over the pairs whose
 * point on F'_i has z above `z_behind` (-INFINITY: every pair), in k, and
 * F'_o in *area_o. */
static void quadrature_k(const sam_mesh *mesh, const sam_profile *p, uint32_t o, uint32_t i, float z_behind,
                         double k[3], double *area_o)
{
    static float qo[QUAD_MAX][3], wo[QUAD_MAX], qi[QUAD_MAX][3], wi[QUAD_MAX];
    const int no = fan_quadrature_points(mesh, o, qo, wo), ni = fan_quadrature_points(mesh, i, qi, wi);
    k[0] = k[1] = k[2] = *area_o = 0;
    for (int a = 0; a < no; ++a) {
        *area_o += wo[a];
        for (int b = 0; b < ni; ++b) {
            if (!(qi[b][2] > z_behind))
                continue;
            float dx = qo[a][0] - qi[b][0], dy = qo[a][1] - qi[b][1], dz = qo[a][2] - qi[b][2], rd[3];
            sam_profile_eval(p, sqrtf(dx * dx + dy * dy + dz * dz), rd);
            for (int c = 0; c < 3; ++c)
                k[c] += (double)wo[a] * wi[b] * rd[c];
        }
    }
    for (int c = 0; c < 3; ++c)
        k[c] /= *area_o;
}

/* quadrature_k against sam_build_form_factor with 20000 pairs: within 4
 * standard errors and 1% (the quadrature's own error is well under 1% at
 * QUAD_L = 12). Returns the quadrature's mean-RGB K. */
static double check_against_quadrature(const sam_build_context *ctx, const sam_mesh *mesh, const sam_profile *p,
                                       uint32_t o, uint32_t i, float z_behind)
{
    double quad[3], area_o;
    quadrature_k(mesh, p, o, i, z_behind, quad, &area_o);
    assert_float_equal(area_o, sam_build_fan_area(ctx, o), 1e-6);
    float k[3], e;
    sam_build_form_factor(ctx, o, i, 20000, 11, k, &e);
    for (int c = 0; c < 3; ++c)
        if (fabs(k[c] - quad[c]) > 4 * e + 0.01 * quad[c])
            fail_msg("channel %d: Monte Carlo %g +- %g, quadrature %g", c, k[c], e, quad[c]);
    return (quad[0] + quad[1] + quad[2]) / 3;
}

/* Two fans 0.2 mm apart, facing away from each other, under the skin sum
 * of Gaussians (which falls steeply across them) against a midpoint
 * quadrature of the double integral over both reduced fans: every point of
 * the one is behind every point of the other. A fan against itself gives
 * 0 (no point of it is behind another). */
static void test_near_form_factor_against_quadrature(void **state)
{
    (void)state;
    sam_mesh mesh;
    two_fans(0.3f, 0.2f, &mesh);
    sam_profile skin;
    sam_build_context *ctx = flat_context(&mesh, "skin", &skin);
    uint32_t o = mesh.topo_of[0];
    float k[3], e;
    sam_build_form_factor(ctx, o, o, 64, 11, k, &e);
    assert_true(k[0] == 0.0f && k[1] == 0.0f && k[2] == 0.0f);
    check_against_quadrature(ctx, &mesh, &skin, o, mesh.topo_of[7], -INFINITY);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* The pairs' Kronecker sequence on the pair of fans above, close against
 * skin's reach: a steep pair, so the 64 pairs asked are 256. Over 48
 * seeds K's mean is the quadrature's in every channel (unbiased), and the
 * mean-RGB K's spread from seed to seed is well under the standard error
 * that as many independent pairs have (which the form factor reports, from
 * its pairs' variance): independent pairs put the ratio near 1 (1.23 with
 * 64 of them, builder 1.12's streams). */
static void test_lattice_pairs_unbiased_and_less_noisy(void **state)
{
    (void)state;
    sam_mesh mesh;
    two_fans(0.3f, 0.2f, &mesh);
    sam_profile skin;
    sam_build_context *ctx = flat_context(&mesh, "skin", &skin);
    const uint32_t o = mesh.topo_of[0], i = mesh.topo_of[7];
    double quad[3], area_o;
    quadrature_k(&mesh, &skin, o, i, -INFINITY, quad, &area_o);
    const double quad_mean = (quad[0] + quad[1] + quad[2]) / 3;
    enum { SEEDS = 48 };
    double mean[3] = {0, 0, 0}, square[3] = {0, 0, 0}, square_mean = 0, independent = 0;
    for (uint64_t seed = 1; seed <= SEEDS; ++seed) {
        float k[3], e;
        sam_build_form_factor(ctx, o, i, 64, seed, k, &e);
        for (int c = 0; c < 3; ++c) {
            mean[c] += k[c] / SEEDS;
            square[c] += (k[c] - quad[c]) * (k[c] - quad[c]) / SEEDS;
        }
        const double off = (k[0] + k[1] + k[2]) / 3 - quad_mean;
        square_mean += off * off / SEEDS;
        independent += (double)e / SEEDS;
    }
    for (int c = 0; c < 3; ++c) {
        const double rms = sqrt(square[c]);
        print_message("channel %d: K %.5g over %d seeds (quadrature %.5g), seed-to-seed RMS %.2f%%\n", c, mean[c],
                      SEEDS, quad[c], 100 * rms / quad[c]);
        if (fabs(mean[c] - quad[c]) > 3 * rms / sqrt(SEEDS) + 0.01 * quad[c])
            fail_msg("channel %d: mean K %g over %d seeds, quadrature %g", c, mean[c], SEEDS, quad[c]);
    }
    const double ratio = sqrt(square_mean) / independent;
    print_message("mean RGB: seed-to-seed RMS %.2f%%, independent pairs' standard error %.2f%% (ratio %.2f)\n",
                  100 * sqrt(square_mean) / quad_mean, 100 * independent / quad_mean, ratio);
    if (!(ratio < 0.7))
        fail_msg("seed-to-seed RMS %g is %.2f of as many independent pairs' standard error %g", sqrt(square_mean),
                 ratio, independent);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* A fold, as on a scan's rim: a flat fan facing -z at z = 0 and, 0.15 mm
 * to its side, a fan tilted 70 degrees whose centre is 0.02 mm behind the
 * first's tangent plane. The two centres pass eq. 13-14, but half of the
 * second fan is in front of the plane; K counts only the part behind (z >
 * 0), as the ground truth does point by point, and that part sends much
 * less light than the whole fan would. */
static void test_fold_form_factor_against_quadrature(void **state)
{
    (void)state;
    const float r = 0.3f, tilt = 70.0f * (float)PI / 180.0f;
    const float centre[2][3] = {{0, 0, 0}, {0.15f, 0, 0.02f}};
    /* In-plane axes of each fan; fan 1's normal is (sin tilt, 0, cos tilt). */
    const float axis_u[2][3] = {{1, 0, 0}, {cosf(tilt), 0, -sinf(tilt)}}, axis_v[3] = {0, 1, 0};
    float pos[14 * 3];
    uint32_t tri[12 * 3];
    for (int f = 0; f < 2; ++f) {
        float *c = pos + 3 * 7 * f;
        memcpy(c, centre[f], sizeof centre[f]);
        for (int k = 0; k < 6; ++k)
            for (int d = 0; d < 3; ++d)
                c[3 + 3 * k + d] = centre[f][d] + r * ((float)cos(k * PI / 3) * axis_u[f][d] +
                                                       (float)sin(k * PI / 3) * axis_v[d]);
        for (int k = 0; k < 6; ++k) {
            uint32_t a = 7 * f + 1 + k, b = 7 * f + 1 + (k + 1) % 6, o = 7 * f;
            uint32_t t[3] = {o, f ? a : b, f ? b : a}; /* fan 0 faces -z, fan 1 along its normal */
            memcpy(tri + 3 * (6 * f + k), t, sizeof t);
        }
    }
    sam_mesh_input in = {.name = "fold", .vertex_count = 14, .positions = pos, .triangle_count = 12,
                         .triangles = tri};
    sam_mesh mesh;
    assert_int_equal(sam_mesh_create(&in, &mesh, NULL, NULL), SAM_OK);
    sam_profile skin;
    sam_build_context *ctx = flat_context(&mesh, "skin", &skin);
    const uint32_t o = mesh.topo_of[0], i = mesh.topo_of[7];
    assert_true(sam_build_is_back_side(ctx, o, i));
    const double behind = check_against_quadrature(ctx, &mesh, &skin, o, i, 0.0f);
    /* The whole fan, as the vertex test alone counted it, by the same quadrature. */
    double all[3], area_o;
    quadrature_k(&mesh, &skin, o, i, -INFINITY, all, &area_o);
    const double whole = (all[0] + all[1] + all[2]) / 3;
    printf("fold: K of the part behind %.4g, of the whole fan %.4g (%.2f)\n", behind, whole, behind / whole);
    assert_true(behind < 0.7 * whole);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* The topo vertex nearest (x, y, z). */
static uint32_t nearest_topo(const sam_mesh *mesh, float x, float y, float z)
{
    uint32_t best = 0;
    float best_d = INFINITY;
    for (uint32_t t = 0; t < mesh->topo_count; ++t) {
        const float *p = mesh->positions + 3 * (size_t)mesh->topo_rep[t];
        const float d = (p[0] - x) * (p[0] - x) + (p[1] - y) * (p[1] - y) + (p[2] - z) * (p[2] - z);
        if (d < best_d)
            best = t, best_d = d;
    }
    return best;
}

/* eq. 14 asked of point pairs (sam_build_form_factor_pointwise) on a 2.5 mm
 * marble slab, receiver on top 5 mm from an edge: a fan under it, whose
 * points all face away, gets the plain K exactly (the same points); a fan
 * beside it on top gets none; the fan of a vertex on the bottom edge,
 * whose normal is the mean of the bottom's and the side's, loses the
 * part of the side that faces up. */
static void test_pointwise_form_factor(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("slab", 24, 50.0, 2.5, 0, &mesh);
    sam_profile marble;
    sam_build_context *ctx = flat_context(&mesh, "marble", &marble);
    const uint32_t o = nearest_topo(&mesh, 20.0f, 1.25f, 0.0f), below = nearest_topo(&mesh, 20.0f, -1.25f, 0.0f);
    const uint32_t beside = nearest_topo(&mesh, 18.0f, 1.25f, 0.0f), edge = nearest_topo(&mesh, 25.0f, -1.25f, 0.0f);
    float plain[3], point[3], e;
    assert_true(sam_build_is_back_side(ctx, o, below));
    sam_build_form_factor(ctx, o, below, 256, 5, plain, &e);
    sam_build_form_factor_pointwise(ctx, o, below, 256, 5, point, &e);
    assert_true(mean3(plain) > 0.0f);
    assert_memory_equal(plain, point, sizeof plain);
    sam_build_form_factor_pointwise(ctx, o, beside, 256, 5, point, &e);
    assert_true(point[0] == 0.0f && point[1] == 0.0f && point[2] == 0.0f);
    sam_build_form_factor(ctx, o, edge, 256, 5, plain, &e);
    sam_build_form_factor_pointwise(ctx, o, edge, 256, 5, point, &e);
    printf("bottom edge: K %.4g plain, %.4g point by point\n", mean3(plain), mean3(point));
    assert_true(mean3(point) > 0.5f * mean3(plain) && mean3(point) < mean3(plain));
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* Eq. 13 (d) and 14 (c) at a point x with normal nx of any length, against
 * receiver vertex o's position po and unit normal no. */
static void fan_point_test(const float po[3], const float no[3], const float x[3], const float nx[3], double *d,
                           double *c)
{
    *d = 0, *c = 0;
    for (int k = 0; k < 3; ++k) {
        *d += ((double)x[k] - po[k]) * no[k];
        *c += (double)nx[k] * no[k];
    }
}

/* sam_build_fan_back_side against points drawn on the fans: where it says
 * all of a fan is behind the receiver, every point passes eq. 13-14 (the
 * normals interpolated there); where it says none is, no point does; and
 * all three answers occur. Drawn independently of the builder: each point
 * a random convex mix of one quad's corners (the vertex, two edge
 * midpoints, the triangle's centroid), its normal mixed alike. On the
 * bundled ear (a scan's uneven normals) and a 2.5 mm slab (rims). */
static void test_fan_back_side(void **state)
{
    (void)state;
    static const struct {
        const char *shape;
        float mm_per_unit;
    } cases[] = {{SAM_SOURCE_DIR "/meshes/ear.obj", 60.0f}, {"slab", 1.0f}};
    for (size_t s = 0; s < sizeof cases / sizeof *cases; ++s) {
        sam_mesh mesh;
        sam_error err;
        if (strchr(cases[s].shape, '/')) {
            if (sam_mesh_load(cases[s].shape, &mesh, NULL, &err) != SAM_OK)
                fail_msg("%s", err.message);
        } else {
            sam_test_shape_mesh(cases[s].shape, 24, 50.0, 2.5, 0, &mesh);
        }
        sam_profile marble;
        assert_int_equal(sam_profile_preset("marble", &marble, NULL), SAM_OK);
        sam_build_settings settings;
        sam_build_default_settings(&settings);
        sam_build_context *ctx = context(&mesh, &marble, cases[s].mm_per_unit, &settings);
        const uint32_t n = mesh.topo_count;
        uint32_t seen[3] = {0, 0, 0}, rng = 12345;
        for (uint32_t o = 0; o < n; o += 7) {
            float po[3];
            for (int k = 0; k < 3; ++k)
                po[k] = mesh.positions[3 * (size_t)mesh.topo_rep[o] + k] * cases[s].mm_per_unit;
            const float *no = mesh.topo_normals + 3 * (size_t)o;
            for (uint32_t i = 0; i < n; i += 3) {
                const int side = sam_build_fan_back_side(ctx, o, i);
                assert_true(side >= 0 && side <= 2);
                seen[side]++;
                if (i == o)
                    assert_int_equal(side, 0);
                if (side == 1 || i == o)
                    continue;
                float corner[4][3], normal[4][3];
                for (uint32_t r = mesh.ring_offsets[i] + 1; r < mesh.ring_offsets[i + 1]; ++r) {
                    const uint32_t t[3] = {i, mesh.ring[r - 1], mesh.ring[r]};
                    for (int k = 0; k < 3; ++k) {
                        float p[3], nn[3];
                        for (int v = 0; v < 3; ++v) {
                            p[v] = mesh.positions[3 * (size_t)mesh.topo_rep[t[v]] + k] * cases[s].mm_per_unit;
                            nn[v] = mesh.topo_normals[3 * (size_t)t[v] + k];
                        }
                        corner[0][k] = p[0], normal[0][k] = nn[0];
                        corner[1][k] = 0.5f * (p[0] + p[1]), normal[1][k] = 0.5f * (nn[0] + nn[1]);
                        corner[2][k] = (p[0] + p[1] + p[2]) / 3.0f, normal[2][k] = (nn[0] + nn[1] + nn[2]) / 3.0f;
                        corner[3][k] = 0.5f * (p[0] + p[2]), normal[3][k] = 0.5f * (nn[0] + nn[2]);
                    }
                    for (int q = 0; q < 8; ++q) {
                        float w[4], sum = 0, x[3] = {0, 0, 0}, nx[3] = {0, 0, 0};
                        for (int v = 0; v < 4; ++v) {
                            rng = rng * 1664525u + 1013904223u;
                            w[v] = (float)(rng >> 8) / 16777216.0f;
                            sum += w[v];
                        }
                        for (int v = 0; v < 4; ++v)
                            for (int k = 0; k < 3; ++k) {
                                x[k] += w[v] / sum * corner[v][k];
                                nx[k] += w[v] / sum * normal[v][k];
                            }
                        double d, c;
                        fan_point_test(po, no, x, nx, &d, &c);
                        /* A margin for float rounding at points on the planes. */
                        if (side == 2)
                            assert_true(d < 1e-4 && c < 1e-5);
                        else
                            assert_true(d > -1e-4 || c > -1e-5);
                    }
                }
            }
        }
        printf("%s: fans none / part / all behind: %u / %u / %u\n", cases[s].shape, seen[0], seen[1], seen[2]);
        assert_true(seen[0] > 0 && seen[1] > 0 && seen[2] > 0);
        sam_build_context_destroy(ctx);
        sam_mesh_destroy(&mesh);
    }
}

/* The fast builder against the brute-force reference: the chosen samples
 * capture >= 97% of the reference's top-N transport (median over vertices),
 * and the two builders' K for the same pairs agree within the Monte Carlo
 * error both report. Returns the median capture. */
static double compare_with_reference(const char *label, const sam_mesh *mesh, const sam_profile *profile,
                                     float mm_per_unit, uint32_t n)
{
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    s.samples_per_vertex = n;
    sam_build_context *ctx = context(mesh, profile, mm_per_unit, &s);
    sam_build_settings rs = s;
    rs.seed = 12345; /* independent Monte Carlo for the reference */
    sam_build_context *rctx = context(mesh, profile, mm_per_unit, &rs);
    sam_build_result fast, ref;
    sam_error err;
    assert_int_equal(sam_build_run(ctx, NULL, NULL, &fast, &err), SAM_OK);
    assert_int_equal(sam_build_reference(rctx, NULL, NULL, &ref, &err), SAM_OK);
    uint32_t nt = mesh->topo_count;
    double *capture = malloc(nt * sizeof *capture);
    uint32_t rows = 0, pairs = 0, agree = 0;
    for (uint32_t o = 0; o < nt; ++o) {
        double best = 0, got = 0;
        for (uint32_t k = 0; k < n; ++k) {
            size_t slot = (size_t)o * n + k;
            if (ref.sample[slot] != SAM_BUILD_NO_SAMPLE)
                best += mean3(ref.k + 3 * slot);
            uint32_t i = fast.sample[slot];
            if (i == SAM_BUILD_NO_SAMPLE)
                continue;
            /* The reference's estimate for the fast builder's pair. */
            float kr[3], er;
            sam_build_form_factor(rctx, o, i, rs.mc_samples, rs.seed, kr, &er);
            got += mean3(kr);
            float kf = mean3(fast.k + 3 * slot), ef = fast.k_error[slot];
            pairs++;
            agree += fabsf(kf - mean3(kr)) <= 3.0f * sqrtf(ef * ef + er * er) + 1e-6f * fabsf(kf);
        }
        /* Vertices whose reference transport is negligible say nothing. */
        if (best > 1e-7)
            capture[rows++] = got / best;
    }
    /* Median by partial selection sort (small arrays). */
    for (uint32_t a = 0; a <= rows / 2; ++a)
        for (uint32_t b = a + 1; b < rows; ++b)
            if (capture[b] < capture[a]) {
                double t = capture[a];
                capture[a] = capture[b];
                capture[b] = t;
            }
    double median = rows ? capture[rows / 2] : 1.0, p10 = rows ? capture[rows / 10] : 1.0;
    printf("%s: %u vertices, %u with back-side transport; capture median %.4f, 10th percentile %.4f; "
           "K agreement %.2f%% of %u pairs; fast %.3f s, reference %.3f s\n",
           label, nt, rows, median, p10, pairs ? 100.0 * agree / pairs : 100.0, pairs, fast.seconds, ref.seconds);
    assert_true(rows > nt / 10);
    assert_true(median >= 0.97);
    assert_true(agree >= 0.99 * pairs);
    free(capture);
    sam_build_result_destroy(&fast);
    sam_build_result_destroy(&ref);
    sam_build_context_destroy(ctx);
    sam_build_context_destroy(rctx);
    return median;
}

static void test_matches_reference_ear(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("ear", 40, 0, 0, 0, &mesh);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    compare_with_reference("ear, skin, N=3", &mesh, &skin, 60.0f, 3);
    sam_mesh_destroy(&mesh);
}

static void test_matches_reference_knot(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("knot", 96, 0, 0, 0, &mesh);
    sam_profile marble;
    assert_int_equal(sam_profile_preset("marble", &marble, NULL), SAM_OK);
    compare_with_reference("knot, marble, N=8", &mesh, &marble, 30.0f, 8);
    sam_mesh_destroy(&mesh);
}

/* Blobs: back-side vertices may sit in another component. */
static void test_matches_reference_blobs(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("blobs", 8, 0, 0, 8, &mesh);
    sam_profile potato;
    assert_int_equal(sam_profile_preset("potato", &potato, NULL), SAM_OK);
    float lo[3], hi[3];
    sam_mesh_bounds(&mesh, lo, hi);
    /* Millimetre-sized blobs with N large enough that a vertex's own blob
     * cannot fill its list: the far sides of the neighbouring blobs (which
     * face away from it, so they pass eq. 14) come next. */
    const uint32_t n = 48;
    float mm = 4.0f / (hi[0] - lo[0]);
    compare_with_reference("blobs, potato, N=48", &mesh, &potato, mm, n);
    /* Some samples land on another blob: components by flood fill over rings. */
    uint32_t *comp = malloc(mesh.topo_count * sizeof *comp), *stack = malloc(mesh.topo_count * sizeof *stack);
    for (uint32_t t = 0; t < mesh.topo_count; ++t)
        comp[t] = UINT32_MAX;
    uint32_t ncomp = 0;
    for (uint32_t t = 0; t < mesh.topo_count; ++t) {
        if (comp[t] != UINT32_MAX)
            continue;
        uint32_t top = 0;
        stack[top++] = t;
        comp[t] = ncomp;
        while (top) {
            uint32_t u = stack[--top];
            for (uint32_t k = mesh.ring_offsets[u]; k < mesh.ring_offsets[u + 1]; ++k)
                if (comp[mesh.ring[k]] == UINT32_MAX) {
                    comp[mesh.ring[k]] = ncomp;
                    stack[top++] = mesh.ring[k];
                }
        }
        ncomp++;
    }
    assert_int_equal(ncomp, 8);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    s.samples_per_vertex = n;
    sam_build_context *ctx = context(&mesh, &potato, mm, &s);
    sam_build_result r;
    assert_int_equal(sam_build_run(ctx, NULL, NULL, &r, NULL), SAM_OK);
    uint32_t across = 0;
    for (uint32_t o = 0; o < mesh.topo_count; ++o)
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t i = r.sample[o * n + k];
            across += i != SAM_BUILD_NO_SAMPLE && comp[i] != comp[o];
        }
    printf("blobs: %u samples on another blob\n", across);
    assert_true(across > 0);
    free(comp);
    free(stack);
    sam_build_result_destroy(&r);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* A thin slab: top vertices take their samples from the bottom face right
 * below them, never from their own side. */
static void test_thin_slab(void **state)
{
    (void)state;
    sam_mesh mesh;
    /* 20 x 20 mm, 1 mm thick, 0.5 mm spacing (mm_per_unit 1). */
    sam_test_shape_mesh("slab", 40, 20.0, 1.0, 0, &mesh);
    sam_profile skin;
    sam_build_context *ctx = flat_context(&mesh, "skin", &skin);
    sam_build_result r;
    assert_int_equal(sam_build_run(ctx, NULL, NULL, &r, NULL), SAM_OK);
    const float spacing = 0.5f, top = 0.5f;
    uint32_t interior = 0, below_first = 0;
    for (uint32_t o = 0; o < mesh.topo_count; ++o) {
        const float *p = mesh.positions + 3 * mesh.topo_rep[o];
        /* Top-face vertices away from the rim. */
        if (fabsf(p[1] - top) > 1e-5f || fabsf(p[0]) > 9.0f || fabsf(p[2]) > 9.0f)
            continue;
        interior++;
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t i = r.sample[o * 3 + k];
            assert_int_not_equal(i, SAM_BUILD_NO_SAMPLE);
            const float *q = mesh.positions + 3 * mesh.topo_rep[i];
            assert_float_equal(q[1], -top, 1e-5); /* on the bottom face */
            float h = hypotf(q[0] - p[0], q[2] - p[2]);
            /* within the fan directly below */
            assert_true(h <= 1.01f * spacing * sqrtf(2.0f));
            if (k == 0)
                below_first += h < 1e-5f;
        }
    }
    printf("slab: %u interior top vertices, %u have the vertex exactly below as best sample\n", interior,
           below_first);
    assert_true(interior > 1000);
    assert_true(below_first >= 0.9 * interior);
    sam_build_result_destroy(&r);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

/* A sphere far larger than the radius of influence: nothing on its back
 * side is within reach, so no vertex gets samples; a small one does. */
static void test_large_and_small_sphere(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("sphere", 32, 1.0, 0, 0, &mesh);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    for (int big = 1; big >= 0; --big) {
        float diameter_mm = big ? 1000.0f : 6.0f;
        sam_build_context *ctx = context(&mesh, &skin, diameter_mm, &s);
        sam_build_result r;
        assert_int_equal(sam_build_run(ctx, NULL, NULL, &r, NULL), SAM_OK);
        uint32_t with = 0;
        for (uint32_t o = 0; o < mesh.topo_count; ++o)
            with += r.sample[o * 3] != SAM_BUILD_NO_SAMPLE;
        if (big)
            assert_int_equal(with, 0);
        else
            assert_int_equal(with, mesh.topo_count);
        sam_build_result_destroy(&r);
        sam_build_context_destroy(ctx);
    }
    sam_mesh_destroy(&mesh);
}

/* The map of `mesh` in skin at `mm_per_unit` (flat, N = 3), and what
 * sam_build_explain_empty says of it into why[n]; returns its result. */
static int explain(const sam_mesh *mesh, float mm_per_unit, char *why, size_t n)
{
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    samfile_data map;
    sam_error err;
    if (sam_build_samfile(mesh, &skin, mm_per_unit, &s, NULL, NULL, NULL, &map, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    int said = sam_build_explain_empty(&map, mm_per_unit, sam_profile_radius(&skin, s.radius_tolerance), "m.obj",
                                       why, n);
    print_message("%s\n", why);
    samfile_free(&map);
    return said;
}

/* A map whose vertices mostly get no light says why: a sphere far larger
 * than the light crosses (closed: its size and scale are named), a single
 * sheet (open: it has no back side); a small sphere's map says nothing. */
static void test_explain_dark_maps(void **state)
{
    (void)state;
    char why[1024];
    sam_mesh sphere;
    sam_test_shape_mesh("sphere", 16, 1.0, 0, 0, &sphere);
    assert_int_equal(explain(&sphere, 1000.0f, why, sizeof why), 1);
    assert_non_null(strstr(why, "100% of the vertices"));
    assert_non_null(strstr(why, "closed"));
    assert_non_null(strstr(why, "1732 mm across")); /* the box's diagonal */
    assert_non_null(strstr(why, "units are not 1000 mm"));
    assert_null(strstr(why, "open"));
    assert_int_equal(explain(&sphere, 6.0f, why, sizeof why), 0);
    assert_string_equal(why, "");
    /* A short buffer still ends in a NUL. */
    char small[16];
    assert_int_equal(explain(&sphere, 1000.0f, small, sizeof small), 1);
    assert_int_equal(strlen(small), sizeof small - 1);
    sam_mesh_destroy(&sphere);

    /* A 10 x 10 mm sheet of 8 x 8 quads. */
    enum { Q = 8, V = (Q + 1) * (Q + 1) };
    float pos[3 * V];
    uint32_t tri[6 * Q * Q], t = 0;
    for (int j = 0; j <= Q; ++j)
        for (int i = 0; i <= Q; ++i) {
            float *p = pos + 3 * (j * (Q + 1) + i);
            p[0] = (float)i / Q, p[1] = (float)j / Q, p[2] = 0.0f;
        }
    for (uint32_t j = 0; j < Q; ++j)
        for (uint32_t i = 0; i < Q; ++i) {
            const uint32_t a = j * (Q + 1) + i, b = a + 1, c = a + Q + 1, d = c + 1;
            const uint32_t quad[6] = {a, b, d, a, d, c};
            memcpy(tri + t, quad, sizeof quad);
            t += 6;
        }
    sam_mesh_input in = {.name = "sheet", .vertex_count = V, .positions = pos, .triangle_count = 2 * Q * Q,
                         .triangles = tri};
    sam_mesh sheet;
    assert_int_equal(sam_mesh_create(&in, &sheet, NULL, NULL), SAM_OK);
    assert_int_equal(explain(&sheet, 10.0f, why, sizeof why), 1);
    assert_non_null(strstr(why, "m.obj is open (32 vertices on its boundary)"));
    assert_non_null(strstr(why, "single sheet"));
    sam_mesh_destroy(&sheet);
    assert_int_equal(sam_build_explain_empty(NULL, 1.0f, 1.0f, NULL, why, sizeof why), 0);
    assert_string_equal(why, "");
}

/* A map whose object is far smaller than the material spreads light says
 * so (a model in metres read as millimetres): its rows are full, so
 * sam_build_explain_empty is silent; at its own size it says nothing. */
static void test_explain_tiny_object(void **state)
{
    (void)state;
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    const float near_mm = sam_profile_radius(&skin, 0.99f);
    sam_mesh sphere;
    sam_test_shape_mesh("sphere", 12, 1.0, 0, 0, &sphere);
    char why[1024];
    for (int k = 0; k < 2; ++k) {
        const float mm_per_unit = k ? 6.0f : 0.001f;
        sam_build_settings s;
        sam_build_default_settings(&s);
        samfile_data map;
        sam_error err;
        if (sam_build_samfile(&sphere, &skin, mm_per_unit, &s, NULL, NULL, NULL, &map, NULL, &err) != SAM_OK)
            fail_msg("%s", err.message);
        assert_int_equal(sam_build_explain_empty(&map, mm_per_unit, sam_profile_radius(&skin, s.radius_tolerance),
                                                 "m.obj", why, sizeof why),
                         0);
        assert_int_equal(sam_build_explain_small(&map, mm_per_unit, near_mm, "m.obj", why, sizeof why), !k);
        print_message("%s\n", why);
        if (!k) {
            char size[64];
            snprintf(size, sizeof size, "m.obj is %.3g mm across", sam_mesh_diagonal(&sphere) * mm_per_unit);
            assert_non_null(strstr(why, size));
            assert_non_null(strstr(why, "units are not 0.001 mm"));
        } else {
            assert_string_equal(why, "");
        }
        samfile_free(&map);
    }
    sam_mesh_destroy(&sphere);
    assert_int_equal(sam_build_explain_small(NULL, 1.0f, 1.0f, NULL, why, sizeof why), 0);
}

/* The output does not depend on the thread count. */
static void test_bit_identical_for_any_thread_count(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("ear", 32, 0, 0, 0, &mesh);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    sam_build_result r[3];
    for (int t = 0; t < 3; ++t) {
        sam_build_settings s;
        sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
        s.threads = t + 1;
        sam_build_context *ctx = context(&mesh, &skin, 60.0f, &s);
        assert_int_equal(sam_build_run(ctx, NULL, NULL, &r[t], NULL), SAM_OK);
        sam_build_context_destroy(ctx);
    }
    size_t n = (size_t)mesh.topo_count * 3;
    for (int t = 1; t < 3; ++t) {
        assert_memory_equal(r[0].sample, r[t].sample, n * sizeof *r[0].sample);
        assert_memory_equal(r[0].k, r[t].k, 3 * n * sizeof *r[0].k);
        assert_memory_equal(r[0].kprime, r[t].kprime, 3 * n * sizeof *r[0].kprime);
        assert_memory_equal(r[0].k_error, r[t].k_error, n * sizeof *r[0].k_error);
    }
    for (int t = 0; t < 3; ++t)
        sam_build_result_destroy(&r[t]);
    sam_mesh_destroy(&mesh);
}

/* The .sam: render copies share their topo vertex's samples; K' recovers K
 * through eq. 15; rings are closed; INFO records what was done. */
static void test_samfile_output(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("ear", 32, 0, 0, 0, &mesh);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    sam_build_context *ctx = context(&mesh, &skin, 60.0f, &s);
    sam_build_result r;
    sam_error err;
    assert_int_equal(sam_build_run(ctx, NULL, NULL, &r, &err), SAM_OK);
    sam_build_source src = {"/some/dir/ear.obj", "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff"};
    samfile_data d;
    assert_int_equal(sam_build_to_samfile(ctx, &r, &src, &d, &err), SAM_OK);
    char path[512];
    sam_test_tmp_path(path, sizeof path, "build_ear.sam");
    if (samfile_write(path, &d, &err) != SAM_OK)
        fail_msg("%s", err.message);
    samfile_data back;
    assert_int_equal(samfile_read(path, &back, &err), SAM_OK);
    assert_int_equal(back.vertex_count, mesh.vertex_count);
    assert_non_null(back.uvs);
    for (uint32_t v = 0; v < back.vertex_count; ++v) {
        uint32_t t = mesh.topo_of[v], rep = mesh.topo_rep[t];
        assert_memory_equal(back.sample_index + 3 * v, back.sample_index + 3 * rep, 3 * sizeof(uint32_t));
        uint32_t b = back.adjacency_offsets[v], e = back.adjacency_offsets[v + 1];
        assert_int_equal(back.adjacency[b], back.adjacency[e - 1]); /* closed shell */
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t i = back.sample_index[3 * v + k];
            if (i == SAMFILE_NO_SAMPLE)
                continue;
            const float *pv = back.positions + 3 * v, *pi = back.positions + 3 * i;
            float dist = 60.0f * sqrtf((pi[0] - pv[0]) * (pi[0] - pv[0]) + (pi[1] - pv[1]) * (pi[1] - pv[1]) +
                                       (pi[2] - pv[2]) * (pi[2] - pv[2]));
            float rd[3];
            sam_profile_eval(&skin, dist, rd);
            for (int c = 0; c < 3; ++c) {
                float kk = back.sample_kprime[3 * (3 * v + k) + c] * back.fan_area[i] * rd[c];
                assert_float_equal(kk, r.k[3 * (3 * t + k) + c], 1e-4 * r.k[3 * (3 * t + k) + c] + 1e-12);
            }
        }
    }
    assert_non_null(strstr(back.info_json, "\"has_uvs\":true"));
    assert_non_null(strstr(back.info_json, "\"file\":\"ear.obj\""));
    assert_non_null(strstr(back.info_json, src.sha256));
    assert_non_null(strstr(back.info_json, "\"mc_samples\":64"));
    assert_non_null(strstr(back.info_json, "\"name\":\"skin\""));
    /* ...and samfile_info_read gives it back. */
    samfile_info info;
    assert_int_equal(samfile_info_read(&back, path, &info, &err), SAM_OK);
    assert_true(info.has_material);
    assert_string_equal(info.profile.name, "skin");
    assert_int_equal(info.profile.kind, skin.kind);
    assert_memory_equal(info.profile.variance, skin.variance, sizeof skin.variance);
    assert_memory_equal(info.profile.weight, skin.weight, sizeof skin.weight);
    assert_float_equal(info.mm_per_unit, 60.0f, 0.0f);
    assert_string_equal(info.source_file, "ear.obj");
    assert_string_equal(info.source_sha256, src.sha256);
    /* What INFO lacks stays empty; a material that does not parse is an error. */
    char bare[] = "{\"mm_per_unit\":2}", bad[] = "{\"material\":{\"preset\":\"jelly\"}}";
    samfile_data partial = {.info_json = bare};
    assert_int_equal(samfile_info_read(&partial, "bare.sam", &info, &err), SAM_OK);
    assert_false(info.has_material);
    assert_float_equal(info.mm_per_unit, 2.0f, 0.0f);
    assert_string_equal(info.source_sha256, "");
    partial.info_json = bad;
    assert_int_equal(samfile_info_read(&partial, "bad.sam", &info, &err), SAM_ERR_FORMAT);
    assert_false(info.has_material);
    assert_non_null(strstr(err.message, "bad.sam"));
    samfile_free(&back);
    samfile_free(&d);
    sam_build_result_destroy(&r);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

static int cancel_at_half(void *user, uint64_t done, uint64_t total)
{
    int *calls = user;
    ++*calls;
    return done * 2 >= total;
}

static void test_settings_and_cancel(void **state)
{
    (void)state;
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    sam_error err;
    assert_int_equal(sam_build_check_settings(&s, 0.0f, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "got 0"));
    assert_int_equal(sam_build_check_settings(&s, NAN, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_build_check_settings(&s, -2.0f, &err), SAM_ERR_INVALID_ARGUMENT);
    s.samples_per_vertex = 0; /* the map's default */
    assert_int_equal(sam_build_check_settings(&s, 1.0f, &err), SAM_OK);
    assert_int_equal(sam_build_samples(&s), SAM_BUILD_FLAT_DEFAULT_SAMPLES);
    s.samples_per_vertex = 65;
    assert_int_equal(sam_build_check_settings(&s, 1.0f, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "1..64 (0: default), got 65"));
    s.samples_per_vertex = 64;
    assert_int_equal(sam_build_check_settings(&s, 1.0f, &err), SAM_OK);
    /* A cut's budget: at least N, at most 64; by default at least 32. */
    s.samples_per_vertex = 16;
    s.cut_budget = 8;
    assert_int_equal(sam_build_check_settings(&s, 1.0f, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(
        strstr(err.message, "cut budget must be 0 (the larger of the samples per vertex and 32) or in 16..64"));
    s.cut_budget = 65;
    assert_int_equal(sam_build_check_settings(&s, 1.0f, &err), SAM_ERR_INVALID_ARGUMENT);
    s.cut_budget = 32;
    assert_int_equal(sam_build_check_settings(&s, 1.0f, &err), SAM_OK);
    assert_int_equal(sam_build_cut_budget(&s), 32);
    s.cut_budget = 0;
    assert_int_equal(sam_build_cut_budget(&s), 32);
    s.samples_per_vertex = 48;
    assert_int_equal(sam_build_cut_budget(&s), 48);
    s.samples_per_vertex = 16;
    s.samples_per_vertex = 64;
    s.candidates = 10;
    assert_int_equal(sam_build_check_settings(&s, 1.0f, &err), SAM_ERR_INVALID_ARGUMENT);

    sam_mesh mesh;
    sam_test_shape_mesh("ear", 32, 0, 0, 0, &mesh);
    sam_profile skin;
    assert_int_equal(sam_profile_preset("skin", &skin, NULL), SAM_OK);
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT;
    sam_build_context *ctx = context(&mesh, &skin, 60.0f, &s);
    sam_build_result r;
    int calls = 0;
    assert_int_equal(sam_build_run(ctx, cancel_at_half, &calls, &r, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "cancelled"));
    assert_true(calls >= 1); /* thread 0 reports; under load it may first report past half */
    assert_null(r.sample);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_far_small_fans),
        cmocka_unit_test(test_constant_profile),
        cmocka_unit_test(test_near_form_factor_against_quadrature),
        cmocka_unit_test(test_lattice_pairs_unbiased_and_less_noisy),
        cmocka_unit_test(test_fold_form_factor_against_quadrature),
        cmocka_unit_test(test_pointwise_form_factor),
        cmocka_unit_test(test_fan_back_side),
        cmocka_unit_test(test_matches_reference_ear),
        cmocka_unit_test(test_matches_reference_knot),
        cmocka_unit_test(test_matches_reference_blobs),
        cmocka_unit_test(test_thin_slab),
        cmocka_unit_test(test_large_and_small_sphere),
        cmocka_unit_test(test_explain_dark_maps),
        cmocka_unit_test(test_explain_tiny_object),
        cmocka_unit_test(test_bit_identical_for_any_thread_count),
        cmocka_unit_test(test_samfile_output),
        cmocka_unit_test(test_settings_and_cancel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
