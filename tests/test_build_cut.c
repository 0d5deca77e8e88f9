/*
 * The cut map (sam_build_cut.c): its nodes' K against the brute-force sum
 * over every fan behind the receiver, a uniformly lit slab against the
 * closed form, each row's K counting only the back side, determinism,
 * and the version-2 .sam it makes.
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

typedef struct cut_fixture {
    sam_mesh mesh;
    sam_profile profile;
    float mm_per_unit;
    float x_min; /* the smallest x of a vertex, mm */
    sam_build_context *ctx;
    sam_build_result r;
} cut_fixture;

/* `shape`: a sam_shape name, or a mesh file (a path: it holds a '/'). The
 * cut has `cut_budget` entries (0: the budget) and stores `budget`; `seed`
 * 0 is the default seed. */
static void build_cut_of(cut_fixture *f, const char *shape, int resolution, double size, double thickness,
                         const char *material, float mm_per_unit, uint32_t budget, uint32_t cut_budget, int threads,
                         uint64_t seed)
{
    sam_error err;
    if (strchr(shape, '/')) {
        if (sam_mesh_load(shape, &f->mesh, NULL, &err) != SAM_OK)
            fail_msg("%s", err.message);
    } else {
        sam_test_shape_mesh(shape, resolution, size, thickness, 0, &f->mesh);
    }
    f->mm_per_unit = mm_per_unit;
    f->x_min = INFINITY;
    for (uint32_t v = 0; v < f->mesh.vertex_count; ++v)
        f->x_min = fminf(f->x_min, f->mesh.positions[3 * (size_t)v] * mm_per_unit);
    assert_int_equal(sam_profile_preset(material, &f->profile, NULL), SAM_OK);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.samples_per_vertex = budget;
    s.cut_budget = cut_budget;
    s.threads = threads;
    if (seed)
        s.seed = seed;
    if (sam_build_context_create(&f->mesh, &f->profile, mm_per_unit, &s, &f->ctx, &err) != SAM_OK ||
        sam_build_run(f->ctx, NULL, NULL, &f->r, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(f->r.node_count, f->mesh.topo_count - 1);
}

/* A cut of `budget` entries, all stored. */
static void build_cut(cut_fixture *f, const char *shape, int resolution, double size, double thickness,
                      const char *material, float mm_per_unit, uint32_t budget, int threads)
{
    build_cut_of(f, shape, resolution, size, thickness, material, mm_per_unit, budget, budget, threads, 0);
}

static void destroy_cut(cut_fixture *f)
{
    sam_build_result_destroy(&f->r);
    sam_build_context_destroy(f->ctx);
    sam_mesh_destroy(&f->mesh);
}

/* Mean-RGB K summed over vertex o's cut. */
static double cut_total(const sam_build_result *r, uint32_t o)
{
    return ((double)r->k_total[3 * (size_t)o] + r->k_total[3 * (size_t)o + 1] + r->k_total[3 * (size_t)o + 2]) / 3.0;
}

/* Whether any of topo vertex i's fan is behind receiver o, and its K
 * (mean RGB) into *k: the Monte Carlo form factor over the pairs of points
 * that pass eq. 13-14 one by one, as the cut map counts a fan. */
static int fan_k(const cut_fixture *f, uint32_t o, uint32_t i, double *k)
{
    *k = 0;
    if (sam_build_fan_back_side(f->ctx, o, i) == 0)
        return 0;
    float kv[3], e;
    sam_build_form_factor_pointwise(f->ctx, o, i, 64, 1, kv, &e);
    *k = (kv[0] + kv[1] + kv[2]) / 3.0;
    return 1;
}

/* Mean-RGB K summed over every fan behind receiver o, each by its own
 * Monte Carlo form factor. */
static double brute_back_side_k(const cut_fixture *f, uint32_t o)
{
    double k_sum = 0, k;
    for (uint32_t i = 0; i < f->mesh.topo_count; ++i)
        if (fan_k(f, o, i, &k))
            k_sum += k;
    return k_sum;
}

/* The cut carries the vertex's whole back-side transport: its K summed
 * matches the Monte Carlo K of every fan behind it, one by one. The rims'
 * fans (part behind, their vertex not) count too: on this ear they are 5%
 * of the light, which rows of vertices alone lost. */
static void test_total_matches_brute_force(void **state)
{
    (void)state;
    static const struct {
        const char *shape, *material;
        int resolution;
        float mm_per_unit;
    } cases[] = {{"ear", "marble", 24, 60.0f}, {"sphere", "skin", 16, 8.0f}, {"knot", "ketchup", 24, 40.0f}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        cut_fixture f;
        build_cut(&f, cases[c].shape, cases[c].resolution, 0, 0, cases[c].material, cases[c].mm_per_unit, 64, 0);
        const uint32_t n = f.mesh.topo_count;
        double all_cut = 0, all_brute = 0, worst = 0;
        uint32_t lit = 0, close = 0;
        for (uint32_t o = 0; o < n; ++o) {
            const double brute = brute_back_side_k(&f, o);
            double cut = cut_total(&f.r, o);
            all_cut += cut;
            all_brute += brute;
            if (brute <= 0)
                continue;
            lit++;
            double rel = fabs(cut - brute) / brute;
            worst = fmax(worst, rel);
            close += rel < 0.05;
        }
        printf("%s, %s: %u vertices, total K cut/brute %.4f, %u of %u within 5%%, worst %.3f\n", cases[c].shape,
               cases[c].material, n, all_cut / all_brute, close, lit, worst);
        assert_true(fabs(all_cut / all_brute - 1) < 0.02);
        assert_true(close >= 0.95 * lit);
        destroy_cut(&f);
    }
}

/* On a slab lit uniformly from below, T at the top is L_d times
 * 2 pi int_t^inf R_d(s) s ds (the bottom plane seen at height t). */
static void test_uniform_slab_closed_form(void **state)
{
    (void)state;
    static const struct {
        const char *material;
        double thickness, width;
        int resolution;
    } cases[] = {{"skin", 2.0, 40.0, 40}, {"marble", 2.5, 100.0, 40}, {"wholemilk", 4.0, 80.0, 40}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        cut_fixture f;
        build_cut(&f, "slab", cases[c].resolution, cases[c].width, cases[c].thickness, cases[c].material, 1.0f, 8, 0);
        double expected[3] = {0, 0, 0};
        const double ds = 1e-3, end = 400.0;
        for (double s = cases[c].thickness; s < end; s += ds) {
            float rd[3];
            sam_profile_eval(&f.profile, (float)(s + 0.5 * ds), rd);
            for (int ch = 0; ch < 3; ++ch)
                expected[ch] += 2 * PI * rd[ch] * (s + 0.5 * ds) * ds;
        }
        double want = (expected[0] + expected[1] + expected[2]) / 3, worst = 0, mean = 0;
        uint32_t centre = 0;
        for (uint32_t o = 0; o < f.mesh.topo_count; ++o) {
            const float *p = f.mesh.positions + 3 * f.mesh.topo_rep[o];
            /* Top-face vertices within a tenth of the width of the centre. */
            if (fabsf(p[1] - 0.5f * (float)cases[c].thickness) > 1e-4f || hypotf(p[0], p[2]) > 0.1f * cases[c].width)
                continue;
            centre++;
            worst = fmax(worst, fabs(cut_total(&f.r, o) / want - 1));
            mean += cut_total(&f.r, o) / want;
        }
        printf("slab %.1f mm of %s: closed form %.5f, %u centre vertices, mean ratio %.4f, worst relative error %.4f\n",
               cases[c].thickness, cases[c].material, want, centre, mean / centre, worst);
        assert_true(centre > 20);
        /* The mean holds to 0.1%; single vertices of marble's long reach
         * err by up to 3.5% where a budget of 8 nodes ends its cut. */
        assert_true(fabs(mean / centre - 1) < 0.01);
        assert_true(worst < 0.04);
        destroy_cut(&f);
    }
}

/* A sheet 0.5 mm thick and 40 mm wide in skin, with 1 mm between its
 * vertices: R_d falls steeply across each pair of fans, most of the light
 * comes from the few fans right below a vertex, and the maps of seeds 7
 * and 8 differ only by their Monte Carlo. Each channel's K at the inner
 * top vertices differs between them by at most 6% RMS (relative to its
 * mean): 0.5%, 2.0% and 4.1% (red, green, blue) with the pairs' lattice
 * and four times the pairs for steep pairs; builder 1.12, with 64
 * independent pairs for every pair, 1.7%, 7.9% and 15.1% (the same mean
 * K), and such sheets glowed mottled. */
static void test_thin_sheet_seed_noise(void **state)
{
    (void)state;
    cut_fixture f[2];
    for (int i = 0; i < 2; ++i)
        build_cut_of(&f[i], "slab", 40, 40.0, 0.5, "skin", 1.0f, SAM_BUILD_CUT_DEFAULT_SAMPLES,
                     SAM_BUILD_CUT_DEFAULT_BUDGET, 0, 7 + (uint64_t)i);
    double square[3] = {0, 0, 0}, mean[3] = {0, 0, 0};
    uint32_t count = 0;
    for (uint32_t o = 0; o < f[0].mesh.topo_count; ++o) {
        const float *p = f[0].mesh.positions + 3 * f[0].mesh.topo_rep[o];
        if (fabsf(p[1] - 0.25f) > 1e-4f || fabsf(p[0]) > 16.0f || fabsf(p[2]) > 16.0f)
            continue;
        count++;
        for (int c = 0; c < 3; ++c) {
            const double a = f[0].r.k_total[3 * (size_t)o + c], b = f[1].r.k_total[3 * (size_t)o + c];
            square[c] += (a - b) * (a - b);
            mean[c] += 0.5 * (a + b);
        }
    }
    assert_true(count > 500);
    for (int c = 0; c < 3; ++c) {
        const double noise = sqrt(square[c] / count) / (mean[c] / count);
        printf("thin sheet, channel %d: K %.4f, seeds 7 and 8 differ by %.2f%% RMS over %u vertices\n", c,
               mean[c] / count, 100 * noise, count);
        assert_true(noise < 0.06);
    }
    for (int i = 0; i < 2; ++i)
        destroy_cut(&f[i]);
}

/* Topo vertex t's position in mm. */
static void topo_mm(const cut_fixture *f, uint32_t t, float out[3])
{
    for (int c = 0; c < 3; ++c)
        out[c] = f->mesh.positions[3 * (size_t)f->mesh.topo_rep[t] + c] * f->mm_per_unit;
}

/* Adds topo vertex t's fan area and area-weighted position (mm) to moment[4]. */
static void add_moment(const cut_fixture *f, uint32_t t, double moment[4])
{
    float p[3];
    topo_mm(f, t, p);
    moment[0] += f->r.fan_area[t];
    for (int c = 0; c < 3; ++c)
        moment[1 + c] += (double)f->r.fan_area[t] * p[c];
}

/* Sums the Monte Carlo K of the members of `id` whose fan is behind o (mean RGB),
 * counts the members on either side, and adds every member's fan area and
 * area-weighted position (mm) to moment[4]. */
static double member_k(const cut_fixture *f, uint32_t o, uint32_t id, uint32_t *back, uint32_t *front,
                       double moment[4])
{
    const uint32_t n = f->mesh.topo_count;
    if (id < n) {
        add_moment(f, id, moment);
        double k;
        if (!fan_k(f, o, id, &k)) {
            ++*front;
            return 0;
        }
        ++*back;
        return k;
    }
    return member_k(f, o, f->r.node_children[2 * (size_t)(id - n)], back, front, moment) +
           member_k(f, o, f->r.node_children[2 * (size_t)(id - n) + 1], back, front, moment);
}

/* The K (mean RGB) a cut map stores for a sample of receiver o: eq. 15
 * undone, K = K' F' R_d(d), with the node's area and centroid from its
 * members' moment[4]. */
static double stored_k(const cut_fixture *f, uint32_t o, const float kprime[3], const double moment[4])
{
    float p[3], rd[3], d2 = 0;
    topo_mm(f, o, p);
    for (int c = 0; c < 3; ++c) {
        const float dc = (float)(moment[1 + c] / moment[0]) - p[c];
        d2 += dc * dc;
    }
    sam_profile_eval(&f->profile, sqrtf(d2), rd);
    double k = 0;
    for (int c = 0; c < 3; ++c)
        k += kprime[c] * moment[0] * rd[c] / 3.0;
    return k;
}

/* A row's K is its receiver's back-side fans' K and nothing else: on
 * scans with noisy normals a node can straddle the back side's edge, and
 * its front members must not count. Summed over the row, not per node: a
 * node partly behind hands its K to a smaller node around its back-side
 * members (sam_build_cut.c's focus), which then holds more than its own
 * members' K. */
static void test_node_k_counts_only_back_side_members(void **state)
{
    (void)state;
    static const char *const shapes[] = {"ear", "blobs", "torus", "knot"};
    for (size_t s = 0; s < sizeof shapes / sizeof *shapes; ++s) {
        cut_fixture f;
        build_cut(&f, shapes[s], 24, 0, 0, "marble", 40.0f, 8, 0);
        const uint32_t n = f.mesh.topo_count, b = f.r.samples_per_vertex;
        uint32_t nodes = 0, straddling = 0, back = 0, front = 0;
        double stored = 0, brute = 0;
        for (uint32_t o = 0; o < n; o += 7) {
            brute += brute_back_side_k(&f, o);
            for (uint32_t k = 0; k < b; ++k) {
                const size_t at = (size_t)o * b + k;
                const uint32_t id = f.r.sample[at];
                if (id == SAM_BUILD_NO_SAMPLE)
                    break;
                uint32_t nb = 0, nf = 0;
                double moment[4] = {0, 0, 0, 0};
                if (id < n)
                    add_moment(&f, id, moment);
                else
                    member_k(&f, o, id, &nb, &nf, moment);
                stored += stored_k(&f, o, f.r.kprime + 3 * at, moment);
                if (id < n)
                    continue;
                nodes++;
                straddling += nf > 0;
                back += nb;
                front += nf;
                assert_true(nb > 0);
            }
        }
        printf("%s: %u node samples (%u straddle the back side's edge) over %u back-side and %u other members; "
               "the rows' stored K / their back-side fans' K %.4f\n",
               shapes[s], nodes, straddling, back, front, stored / brute);
        assert_true(nodes > 0);
        assert_true(fabs(stored / brute - 1) < 0.03);
        destroy_cut(&f);
    }
}

/* L_d of topo vertex t under a directional light travelling along -z:
 * max(0, n.z), the light the runtime would give a back side facing it. */
static double one_sided_ld(const cut_fixture *f, uint32_t t)
{
    return fmax(0.0, f->mesh.topo_normals[3 * (size_t)t + 2]);
}

/* L_d of topo vertex t rising linearly along x: 1 + its x in mm from the
 * mesh's smallest. */
static double linear_ld(const cut_fixture *f, uint32_t t)
{
    float p[3];
    topo_mm(f, t, p);
    return 1.0 + (p[0] - f->x_min);
}

typedef double (*vertex_ld_fn)(const cut_fixture *f, uint32_t t);

static double runtime_ld(const cut_fixture *f, vertex_ld_fn ld_of, uint32_t id, float tau, double moment[4]);

/* A sample's L_d as the nodes' pass sums it, each vertex's from `ld_of`:
 * its members' area-weighted mean. Adds every member's fan area and
 * area-weighted position (mm) to moment[4], as member_k does. */
static double sample_ld(const cut_fixture *f, vertex_ld_fn ld_of, uint32_t id, double moment[4])
{
    if (id < f->mesh.topo_count) {
        add_moment(f, id, moment);
        return ld_of(f, id);
    }
    return runtime_ld(f, ld_of, id, 0.0f, moment);
}

/* A sample's L_d as translucency.comp reads it: for a node, its mean moved
 * by tau times its children's difference. Fills moment[4] as sample_ld. */
static double runtime_ld(const cut_fixture *f, vertex_ld_fn ld_of, uint32_t id, float tau, double moment[4])
{
    const uint32_t n = f->mesh.topo_count;
    if (id < n)
        return sample_ld(f, ld_of, id, moment);
    double m[2][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}}, ld[2];
    for (int c = 0; c < 2; ++c)
        ld[c] = sample_ld(f, ld_of, f->r.node_children[2 * (size_t)(id - n) + c], m[c]);
    for (int i = 0; i < 4; ++i)
        moment[i] += m[0][i] + m[1][i];
    const double area = m[0][0] + m[1][0];
    return area > 0 ? fmax((m[0][0] * ld[0] + m[1][0] * ld[1]) / area + tau * (ld[1] - ld[0]), 0.0) : 0.0;
}

/* The bundled ear (a shell with a scan's uneven normals) in skin, lit
 * from one side: the translucency the cut sums (eq. 12, samples at their
 * members' mean L_d) against every back-side fan's L_d K, one by one.
 * Around a receiver, boxes cannot tell its front from its back side, and a
 * node only partly behind it by its boxes lent its few back-side members
 * the L_d of all its members: 1.8% off here, 25% on the Chinese dragon
 * scan, before small such nodes were classified member by member (0.6%
 * and 15%; the rest is tau's first-order move, left out here). Since rims
 * count, 2.1%: the brute force reads a rim's light at its vertex, the cut
 * at the sample nearest it, a vertex behind the receiver; lit from one
 * side, their L_d differ most where the normal turns, at the rims. */
/* Σ|T of the cut − Σ_back L_d K| over every `step`-th receiver, and Σ of
 * the latter (mean RGB), with each vertex's L_d from `ld_of`. Counts the
 * receivers with light into *lit. */
static double ld_error(const cut_fixture *f, vertex_ld_fn ld_of, uint32_t step, double *total, uint32_t *lit)
{
    const uint32_t n = f->mesh.topo_count, b = f->r.samples_per_vertex;
    double err = 0;
    *total = 0;
    *lit = 0;
    for (uint32_t o = 0; o < n; o += step) {
        double brute = 0, cut = 0;
        for (uint32_t i = 0; i < n; ++i) {
            double k;
            if (fan_k(f, o, i, &k))
                brute += ld_of(f, i) * k;
        }
        for (uint32_t k = 0; k < b; ++k) {
            const size_t at = (size_t)o * b + k;
            if (f->r.sample[at] == SAM_BUILD_NO_SAMPLE)
                break;
            double moment[4] = {0, 0, 0, 0};
            const double ld = runtime_ld(f, ld_of, f->r.sample[at], f->r.tau[at], moment);
            cut += ld * stored_k(f, o, f->r.kprime + 3 * at, moment);
        }
        err += fabs(cut - brute);
        *total += brute;
        *lit += brute > 0;
    }
    return err;
}

static void test_one_sided_light_matches_brute_force(void **state)
{
    (void)state;
    cut_fixture f;
    build_cut(&f, SAM_SOURCE_DIR "/meshes/ear.obj", 0, 0, 0, "skin", 60.0f, 32, 0);
    double total;
    uint32_t lit;
    const double err = ld_error(&f, one_sided_ld, 3, &total, &lit);
    printf("ear.obj, skin, lit from one side: %u receivers lit, |T cut - T brute| / T brute %.4f\n", lit, err / total);
    assert_true(lit > 100);
    assert_true(err / total < 0.025);
    destroy_cut(&f);
}

/* L_d rising along a marble slab and a knot, whose rows are cuts through
 * the tree (N = 8), summed as the runtime sums it (node means moved by
 * tau) against every back-side fan's L_d K: 2.4% and 3.1% off (builder
 * 1.11, which gave a node partly behind the largest node wholly behind,
 * 2.9% and 8.5%; before rims counted, 2.4% and 7.5%), where the K alone
 * (L_d = 1) is 0.3% and 0.4% off. The rest is where a node reads L_d: its members' mean, while
 * its light comes mostly from its edge nearest the receiver, and where a
 * rim's light is read (the sample nearest it). Builder 1.5 read 2.7% and
 * 8.0% here; its
 * gain in pictures, where L_d changes faster than linearly (a shadow's
 * edge, the terminator around a tube), is in docs/builder.md. */
static void test_linear_light_is_read_where_it_comes_from(void **state)
{
    (void)state;
    static const struct {
        const char *shape;
        int resolution;
        double size, thickness;
        float mm_per_unit;
        double bound;
    } cases[] = {{"slab", 24, 2.0, 0.05, 50.0f, 0.03}, {"knot", 24, 0, 0, 40.0f, 0.05}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        cut_fixture f;
        build_cut(&f, cases[c].shape, cases[c].resolution, cases[c].size, cases[c].thickness, "marble",
                  cases[c].mm_per_unit, 8, 0);
        double total;
        uint32_t lit;
        const double err = ld_error(&f, linear_ld, 5, &total, &lit);
        printf("%s, marble, L_d linear in x: %u receivers lit, %.1f%% of the samples are nodes, "
               "|T cut - T brute| / T brute %.4f\n",
               cases[c].shape, lit,
               100.0 * sam_test_node_share(f.r.sample, f.mesh.topo_count, f.r.samples_per_vertex, f.mesh.topo_count),
               err / total);
        assert_true(lit > 20);
        assert_true(err / total < cases[c].bound);
        destroy_cut(&f);
    }
}

/* L_d of topo vertex t: 1 where its x is positive, 0 elsewhere (a
 * shadow's edge across the middle of the mesh). */
static double half_lit_ld(const cut_fixture *f, uint32_t t)
{
    return f->mesh.positions[3 * (size_t)f->mesh.topo_rep[t]] > 0.0f ? 1.0 : 0.0;
}

/* A shape lit on one half (half_lit_ld): the cut's T against the
 * brute-force sum over every back-side fan, at every step-th receiver,
 * more than min_lit of them lit, below `bound` of it. */
typedef struct half_lit_case {
    const char *shape;
    int resolution;
    const char *material;
    float mm_per_unit;
    uint32_t budget, step, min_lit;
    double bound;
} half_lit_case;

static void check_half_lit(const half_lit_case *cases, size_t count)
{
    for (size_t c = 0; c < count; ++c) {
        cut_fixture f;
        build_cut(&f, cases[c].shape, cases[c].resolution, 0, 0, cases[c].material, cases[c].mm_per_unit,
                  cases[c].budget, 0);
        double total;
        uint32_t lit;
        const double err = ld_error(&f, half_lit_ld, cases[c].step, &total, &lit);
        printf("%s, %u vertices, %s, %.0f mm/unit, lit where x > 0: %u receivers lit, "
               "|T cut - T brute| / T brute %.4f\n",
               cases[c].shape, f.mesh.topo_count, cases[c].material, cases[c].mm_per_unit, lit, err / total);
        assert_true(lit > cases[c].min_lit);
        assert_true(err / total < cases[c].bound);
        destroy_cut(&f);
    }
}

/* Six blobs in a 60 mm cube in skin (whose light reaches 10 mm), and in a
 * 300 mm cube in marble (50 mm), lit on one half of the scene. A node's
 * L_d is its members' mean, so a node holding surfaces that face alike on
 * several blobs lends a receiver in the shadow the light of a blob it
 * cannot reach. Built with normals weighed by the whole
 * scene's extent at every size, the cut's T was 12.5% and 7.0% off the
 * brute-force sum; with nodes in a cone of normals split by position while
 * wider than the reach, 2.0% and 1.1% (sam_build_tree.c). */
static void test_nodes_stay_within_reach(void **state)
{
    (void)state;
    static const half_lit_case cases[] = {{"blobs", 16, "skin", 60.0f, 16, 3, 50, 0.05},
                                          {"blobs", 12, "marble", 300.0f, 16, 3, 50, 0.035}};
    check_half_lit(cases, sizeof cases / sizeof *cases);
}

/* A torus and blobs in marble, small against its reach (50 mm), lit on one
 * half: a shadow's edge across them. Nodes partly behind a receiver split
 * by normal near the root and span the whole object, while their K comes
 * from back-side members a few millimetres away; a node too large to ask
 * member by member read its members' mean L_d, lit or dark from the other
 * side of the edge. Builder 1.7 erred by 16.0% and 19.0% of the brute-force
 * sum (8.6% and 13.3% of it under a 4 mm checkerboard of light, where 1.8
 * errs by 9.5% and 15.8%: L_d reads from a smaller node); going down
 * towards where the light comes from first (sam_build_cut.c's
 * concentrate), 6.9% and 10.2%. Builder 1.11 erred by 6.3% and
 * 13.2%: a node partly behind handed its K to the largest node wholly
 * behind on the way to its light, tens of mm across where the K came
 * from a few; narrowed to the K's spread (focus), 5.8% and 1.0%. */
static void test_large_nodes_read_light_near_the_receiver(void **state)
{
    (void)state;
    static const half_lit_case cases[] = {{"torus", 128, "marble", 30.0f, 32, 47, 100, 0.075},
                                          {"blobs", 40, "marble", 60.0f, 32, 25, 100, 0.03}};
    check_half_lit(cases, sizeof cases / sizeof *cases);
}

/* Every sample holds its K in K' (eq. 15): K' F' R_d(d) at the sample's
 * position, as the runtime evaluates it, sums to the cut's total for every
 * receiver. A node whose centroid lay so far out in R_d's tail that R_d
 * underflowed kept K' = 1 and lost its light: the head scan in skin lost 8%
 * of its node samples' K that way, the ear rims' most. Such a node now
 * hands its K to a descendant node (sam_build_cut.c's carrier). */
static void test_samples_hold_the_cut_total(void **state)
{
    (void)state;
    static const struct {
        const char *shape;
        float mm_per_unit;
        uint32_t budget;
    } cases[] = {{"ear", 60.0f, 8}, {"ear", 100.0f, 8}, {"ear", 200.0f, 4}, {"knot", 40.0f, 4}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        cut_fixture f;
        build_cut(&f, cases[c].shape, 24, 0, 0, "skin", cases[c].mm_per_unit, cases[c].budget, 0);
        const uint32_t n = f.mesh.topo_count, b = f.r.samples_per_vertex;
        double held = 0, total = 0, worst = 1;
        for (uint32_t o = 0; o < n; ++o) {
            double row = 0;
            for (uint32_t k = 0; k < b; ++k) {
                const size_t at = (size_t)o * b + k;
                if (f.r.sample[at] == SAM_BUILD_NO_SAMPLE)
                    break;
                double moment[4] = {0, 0, 0, 0};
                sample_ld(&f, one_sided_ld, f.r.sample[at], moment);
                row += stored_k(&f, o, f.r.kprime + 3 * at, moment);
            }
            const double want = cut_total(&f.r, o);
            held += row;
            total += want;
            if (want > 0)
                worst = fmin(worst, row / want);
        }
        printf("%s in skin at %.0f mm per unit, N = %u: samples hold %.6f of the cuts' K, the worst receiver %.4f\n",
               cases[c].shape, cases[c].mm_per_unit, cases[c].budget, held / total, worst);
        /* Builder 1.1: the ear at 60 and 100 mm held 0.969 and 0.993, its
         * worst receivers 0.55 and 0.72. */
        assert_true(total > 0);
        assert_true(held / total > 0.9995);
        assert_true(worst > 0.99);
        destroy_cut(&f);
    }
}

/* Where the budget's best vertices carry nearly all the light (skin on a
 * small ear), a row is those vertices: no tree node, each vertex once,
 * each with K, and together they carry the cut's whole total. Where they
 * do not (marble, whose light comes from far across a slab), the row is a
 * cut through the tree. Both stored whole, at the default budget. */
static void test_rows_list_vertices_where_they_hold_the_light(void **state)
{
    (void)state;
    cut_fixture f;
    build_cut(&f, "ear", 24, 0, 0, "skin", 60.0f, SAM_BUILD_CUT_DEFAULT_BUDGET, 0);
    const uint32_t n = f.mesh.topo_count, b = f.r.samples_per_vertex;
    assert_true(sam_test_node_share(f.r.sample, n, b, n) == 0.0);
    uint32_t rows = 0;
    for (uint32_t o = 0; o < n; ++o) {
        double held = 0;
        for (uint32_t k = 0; k < b && f.r.sample[(size_t)o * b + k] != SAM_BUILD_NO_SAMPLE; ++k) {
            const size_t at = (size_t)o * b + k;
            for (uint32_t j = 0; j < k; ++j)
                assert_int_not_equal(f.r.sample[(size_t)o * b + j], f.r.sample[at]);
            double moment[4] = {0, 0, 0, 0};
            sample_ld(&f, one_sided_ld, f.r.sample[at], moment);
            const double k_mean = stored_k(&f, o, f.r.kprime + 3 * at, moment);
            assert_true(k_mean > 0);
            held += k_mean;
        }
        const double want = cut_total(&f.r, o);
        rows += want > 0;
        assert_true(fabs(held - want) <= 1e-4 * want);
    }
    printf("skin ear: %u of %u rows hold light, every one of them vertices only\n", rows, n);
    assert_true(rows > n / 2);
    destroy_cut(&f);
    build_cut(&f, "slab", 40, 2.0, 0.05, "marble", 50.0f, SAM_BUILD_CUT_DEFAULT_BUDGET, 0);
    const double share = sam_test_node_share(f.r.sample, f.mesh.topo_count, f.r.samples_per_vertex, f.mesh.topo_count);
    printf("marble slab, 2.5 mm: %.1f%% of the samples are tree nodes\n", 100.0 * share);
    assert_true(share > 0.5);
    destroy_cut(&f);
}

/* Whether row o of r holds no tree node (the budget's best vertices). */
static int row_listed(const sam_build_result *r, uint32_t o)
{
    const uint32_t b = r->samples_per_vertex;
    return r->sample[(size_t)o * b] != SAM_BUILD_NO_SAMPLE &&
           sam_test_node_share(r->sample + (size_t)o * b, 1, b, r->topo_count) == 0.0;
}

/* A larger budget refines a row; it does not change how the row is held.
 * On a marble slab, where some rows are the budget's best vertices and the
 * rest cuts through the tree, every row of vertices alone with 64 slots is
 * one with 32 too, and keeps the 32 vertices it had there. Judged on all of
 * its slots, a budget of 64 turned cuts into vertices that carry a folded
 * tenth of the light they do not stand for. */
static void test_larger_budget_keeps_how_rows_are_held(void **state)
{
    (void)state;
    cut_fixture f32, f64;
    build_cut(&f32, "slab", 40, 2.0, 0.05, "marble", 50.0f, 32, 0);
    build_cut(&f64, "slab", 40, 2.0, 0.05, "marble", 50.0f, 64, 0);
    const uint32_t n = f32.mesh.topo_count;
    uint32_t listed32 = 0, listed64 = 0;
    for (uint32_t o = 0; o < n; ++o) {
        listed32 += (uint32_t)row_listed(&f32.r, o);
        if (!row_listed(&f64.r, o))
            continue;
        listed64++;
        assert_true(row_listed(&f32.r, o));
        const uint32_t *row32 = f32.r.sample + (size_t)o * 32, *row64 = f64.r.sample + (size_t)o * 64;
        for (uint32_t k = 0; k < 32 && row32[k] != SAM_BUILD_NO_SAMPLE; ++k) {
            uint32_t j = 0;
            while (j < 64 && row64[j] != row32[k])
                ++j;
            assert_true(j < 64);
        }
    }
    printf("marble slab: %u of %u rows are vertices alone at N = 32, %u at N = 64\n", listed32, n, listed64);
    assert_true(listed64 > 0 && listed32 < n / 2);
    destroy_cut(&f32);
    destroy_cut(&f64);
}

/* Row o's K and its K times L_d under `ld_of` over `count` slots of
 * `f`'s rows from slot `from` on, as the runtime reads them. */
static void row_light(const cut_fixture *f, uint32_t o, uint32_t count, vertex_ld_fn ld_of, double *k, double *kl)
{
    const uint32_t n = f->r.samples_per_vertex;
    *k = *kl = 0;
    for (uint32_t s = 0; s < count; ++s) {
        const size_t at = (size_t)o * n + s;
        if (f->r.sample[at] == SAM_BUILD_NO_SAMPLE)
            break;
        double moment[4] = {0, 0, 0, 0};
        const double ld = runtime_ld(f, ld_of, f->r.sample[at], f->r.tau[at], moment),
                     ks = stored_k(f, o, f->r.kprime + 3 * at, moment);
        *k += ks;
        *kl += ks * ld;
    }
}

/* A cut of `budget` entries stored as `keep` on the knot at 40 mm: the
 * rows carry the whole cut's K, and some hold a node that merged two
 * siblings. Returns the translucency's error under light `ld_fn` against
 * the whole cut's, as a share of it, and that of the first `keep` of the
 * whole cut scaled to its K (into *scaled). */
static double budget_case(const char *material, uint32_t budget, uint32_t keep, vertex_ld_fn ld_fn, double *scaled)
{
    cut_fixture whole, kept;
    build_cut(&whole, "knot", 24, 0, 0, material, 40.0f, budget, 0);
    build_cut_of(&kept, "knot", 24, 0, 0, material, 40.0f, keep, budget, 0, 0);
    const uint32_t n = whole.mesh.topo_count;
    assert_int_equal(kept.r.samples_per_vertex, keep);
    double held = 0, total = 0, worst = 0, err_kept = 0, err_scaled = 0, light = 0;
    uint32_t merged = 0;
    for (uint32_t o = 0; o < n; ++o) {
        const double want = cut_total(&whole.r, o);
        assert_true(fabs(cut_total(&kept.r, o) - want) <= 1e-6 * want);
        double k_whole, t_whole, k_kept, t_kept, k_first, t_first;
        row_light(&whole, o, budget, ld_fn, &k_whole, &t_whole);
        row_light(&kept, o, keep, ld_fn, &k_kept, &t_kept);
        row_light(&whole, o, keep, ld_fn, &k_first, &t_first);
        const double t_scaled = k_first > 0 ? t_first * k_whole / k_first : 0;
        err_kept += fabs(t_kept - t_whole);
        err_scaled += fabs(t_scaled - t_whole);
        light += t_whole;
        held += k_kept;
        total += k_whole;
        if (k_whole > 0)
            worst = fmax(worst, fabs(k_kept - k_whole) / k_whole);
        for (uint32_t s = 0; s < keep; ++s) {
            const uint32_t id = kept.r.sample[(size_t)o * keep + s];
            merged += id >= n && id != SAM_BUILD_NO_SAMPLE && id != whole.r.sample[(size_t)o * budget + s];
        }
    }
    printf("knot in %s, %u of a %u-entry cut: %.6f of the cut's K, the worst receiver off by %.2e; "
           "translucency under %s light off by %.4f of it (the first %u scaled: %.4f); %u slots hold a node "
           "the whole row does not hold there\n",
           material, keep, budget, held / total, worst, ld_fn == one_sided_ld ? "one-sided" : "linear",
           err_kept / light, keep, err_scaled / light, merged);
    assert_true(fabs(held / total - 1) < 1e-4);
    assert_true(worst < 1e-3);
    assert_true(merged > 0);
    destroy_cut(&whole);
    destroy_cut(&kept);
    *scaled = err_scaled / light;
    return err_kept / light;
}

/* In skin most of a row is vertices, and two that share a node merge
 * into it with the tau that reads their light as it was: the row of 4
 * reads light less wrong than the first 4 scaled, under either light
 * (0.0056 against 0.030 from one side, 0.0048 against 0.0082 linear).
 * In marble, whose rows are nodes, the fold does it: a dropped node goes
 * to the kept one that faces its way (0.088 against 0.112 from one side;
 * by position alone 0.183, worse than the scaling). */
static void test_budget_beyond_n_merges_and_folds(void **state)
{
    (void)state;
    double scaled;
    assert_true(budget_case("skin", 16, 4, one_sided_ld, &scaled) < scaled);
    assert_true(budget_case("skin", 16, 4, linear_ld, &scaled) < scaled);
    assert_true(budget_case("marble", 16, 4, one_sided_ld, &scaled) < scaled);
}

static void test_bit_identical_for_any_thread_count(void **state)
{
    (void)state;
    cut_fixture f[3];
    const int threads[3] = {1, 2, 5};
    /* 8 of a 32-entry cut: the fit (merges, folds) is per row too. */
    for (int t = 0; t < 3; ++t)
        build_cut_of(&f[t], "knot", 24, 0, 0, "marble", 40.0f, 8, 32, threads[t], 0);
    const size_t n = (size_t)f[0].r.topo_count * f[0].r.samples_per_vertex;
    for (int t = 1; t < 3; ++t) {
        assert_memory_equal(f[t].r.sample, f[0].r.sample, n * sizeof *f[0].r.sample);
        assert_memory_equal(f[t].r.tau, f[0].r.tau, n * sizeof *f[0].r.tau);
        assert_memory_equal(f[t].r.k_total, f[0].r.k_total, 3 * (size_t)f[0].r.topo_count * sizeof *f[0].r.k_total);
        assert_memory_equal(f[t].r.kprime, f[0].r.kprime, 3 * n * sizeof *f[0].r.kprime);
        assert_memory_equal(f[t].r.node_children, f[0].r.node_children,
                            2 * (size_t)f[0].r.node_count * sizeof *f[0].r.node_children);
    }
    for (int t = 0; t < 3; ++t)
        destroy_cut(&f[t]);
}

/* Another build of f's mesh and material with settings `s`, into *r. */
static void build_again(const cut_fixture *f, const sam_build_settings *s, sam_build_result *r)
{
    sam_build_context *ctx;
    sam_error err;
    if (sam_build_context_create(&f->mesh, &f->profile, f->mm_per_unit, s, &ctx, &err) != SAM_OK ||
        sam_build_run(ctx, NULL, NULL, r, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_build_context_destroy(ctx);
}

/* The flat-scaled baseline: each row of the flat map scaled, per channel,
 * to the total of the largest cut a row holds (64 entries). On a slab in
 * marble that cut runs to all 64 entries; asked for 128, it overran the
 * rows (sam_compare's sweep crashed building the armadillo's N = 3). */
static void test_flat_scaled_carries_the_largest_cut(void **state)
{
    (void)state;
    cut_fixture cut;
    build_cut(&cut, "slab", 16, 2.0, 0.05, "marble", 50.0f, SAMFILE_MAX_SAMPLES_PER_VERTEX, 0);
    uint32_t longest = 0;
    for (uint32_t o = 0; o < cut.r.topo_count; ++o) {
        uint32_t used = 0;
        while (used < cut.r.samples_per_vertex &&
               cut.r.sample[(size_t)o * cut.r.samples_per_vertex + used] != SAM_BUILD_NO_SAMPLE)
            used++;
        longest = used > longest ? used : longest;
    }
    printf("slab in marble: the longest of its 64-entry cuts holds %u\n", longest);
    assert_int_equal(longest, SAMFILE_MAX_SAMPLES_PER_VERTEX);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.map = SAM_BUILD_MAP_FLAT_SCALED;
    s.samples_per_vertex = 3;
    sam_build_result r;
    build_again(&cut, &s, &r);
    uint32_t scaled = 0;
    for (uint32_t o = 0; o < r.topo_count; ++o)
        for (int c = 0; c < 3; ++c) {
            double row = 0;
            for (uint32_t k = 0; k < r.samples_per_vertex; ++k)
                row += r.k[3 * ((size_t)o * r.samples_per_vertex + k) + c];
            const double want = cut.r.k_total[3 * (size_t)o + c];
            if (!(row > 0))
                continue;
            scaled++;
            assert_true(fabs(row - want) <= 1e-5 * want);
        }
    assert_true(scaled > r.topo_count);
    sam_build_result_destroy(&r);
    destroy_cut(&cut);
}

/* The fewest Monte Carlo pairs a build takes (4): a member's cheaper
 * estimate asked 8 pairs of the receiver's 4 points and read past them
 * (ASan: heap-buffer-overflow on the bundled slab). The cuts' total K
 * stays that of 64 pairs within the noise of 4. */
static void test_fewest_pairs_build(void **state)
{
    (void)state;
    cut_fixture cut;
    build_cut_of(&cut, SAM_SOURCE_DIR "/meshes/slab.obj", 0, 0, 0, "marble", 50.0f, 8, SAM_BUILD_CUT_DEFAULT_BUDGET, 0, 0);
    sam_build_settings s;
    sam_build_default_settings(&s);
    s.samples_per_vertex = 8;
    s.cut_budget = SAM_BUILD_CUT_DEFAULT_BUDGET;
    s.mc_samples = 4;
    sam_build_result r;
    build_again(&cut, &s, &r);
    double few = 0, many = 0;
    for (uint32_t o = 0; o < r.topo_count; ++o) {
        few += cut_total(&r, o);
        many += cut_total(&cut.r, o);
    }
    printf("slab in marble: the cuts' K with 4 pairs / with 64: %.4f\n", few / many);
    assert_true(many > 0 && fabs(few / many - 1.0) < 0.05);
    sam_build_result_destroy(&r);
    destroy_cut(&cut);
}

/* A cut map is a version-2 .sam whose tree reads back as built; a flat
 * map stays version 1. */
static void test_samfile_versions(void **state)
{
    (void)state;
    cut_fixture f;
    build_cut(&f, "ear", 24, 0, 0, "marble", 60.0f, 8, 0); /* half its samples nodes; a skin ear's rows are vertices */
    assert_true(sam_test_node_share(f.r.sample, f.mesh.topo_count, f.r.samples_per_vertex, f.mesh.topo_count) > 0.25);
    samfile_data d, back;
    sam_error err;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "cut_ear.sam");
    assert_int_equal(sam_build_to_samfile(f.ctx, &f.r, NULL, &d, &err), SAM_OK);
    assert_int_equal(d.node_count, f.r.node_count);
    if (samfile_write(path, &d, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(samfile_read(path, &back, &err), SAM_OK);
    assert_int_equal(back.node_count, d.node_count);
    assert_int_equal(back.level_count, d.level_count);
    assert_memory_equal(back.node_children, d.node_children, 2 * (size_t)d.node_count * sizeof(uint32_t));
    assert_memory_equal(back.sample_index, d.sample_index,
                        (size_t)d.vertex_count * d.samples_per_vertex * sizeof(uint32_t));
    FILE *fp = fopen(path, "rb");
    uint8_t header[8];
    assert_int_equal(fread(header, 1, 8, fp), 8);
    fclose(fp);
    assert_int_equal(header[4], 2);
    /* Without its tree the same file is no longer valid. */
    back.node_count = 0;
    assert_int_equal(samfile_validate(&back, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "out of range (vertex_count"));
    back.node_count = d.node_count;
    samfile_free(&back);
    samfile_free(&d);
    destroy_cut(&f);
}

/* The .sam's rows follow render vertices: on a mesh with UV seams every
 * render copy of a topo vertex carries its samples, renumbered; the
 * in-place assembly (sam_build_move_to_samfile) writes what the copying one
 * does. */
static void test_samfile_rows_follow_render_vertices(void **state)
{
    (void)state;
    cut_fixture f;
    build_cut(&f, "knot", 24, 0, 0, "marble", 40.0f, 8, 0);
    const sam_mesh *m = &f.mesh;
    assert_true(m->vertex_count > m->topo_count);
    samfile_data d, moved;
    sam_error err;
    assert_int_equal(sam_build_to_samfile(f.ctx, &f.r, NULL, &d, &err), SAM_OK);
    const uint32_t n = f.r.samples_per_vertex;
    for (uint32_t v = 0; v < m->vertex_count; ++v)
        for (uint32_t k = 0; k < n; ++k) {
            const size_t at = (size_t)v * n + k, from = (size_t)m->topo_of[v] * n + k;
            const uint32_t s = f.r.sample[from];
            const uint32_t want = s == SAM_BUILD_NO_SAMPLE ? SAMFILE_NO_SAMPLE
                                  : s < m->topo_count  ? m->topo_rep[s]
                                                       : m->vertex_count + (s - m->topo_count);
            assert_int_equal(d.sample_index[at], want);
            assert_memory_equal(d.sample_kprime + 3 * at, f.r.kprime + 3 * from, 3 * sizeof(float));
            assert_memory_equal(d.sample_tau + at, f.r.tau + from, sizeof(float));
        }
    assert_int_equal(sam_build_move_to_samfile(f.ctx, &f.r, NULL, &moved, &err), SAM_OK);
    assert_null(f.r.sample);
    assert_null(f.r.kprime);
    assert_null(f.r.tau);
    const size_t slots = (size_t)d.vertex_count * n;
    assert_memory_equal(moved.sample_index, d.sample_index, slots * sizeof(uint32_t));
    assert_memory_equal(moved.sample_kprime, d.sample_kprime, 3 * slots * sizeof(float));
    assert_memory_equal(moved.sample_tau, d.sample_tau, slots * sizeof(float));
    samfile_free(&moved);
    samfile_free(&d);
    destroy_cut(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_total_matches_brute_force),
        cmocka_unit_test(test_uniform_slab_closed_form),
        cmocka_unit_test(test_thin_sheet_seed_noise),
        cmocka_unit_test(test_node_k_counts_only_back_side_members),
        cmocka_unit_test(test_one_sided_light_matches_brute_force),
        cmocka_unit_test(test_linear_light_is_read_where_it_comes_from),
        cmocka_unit_test(test_nodes_stay_within_reach),
        cmocka_unit_test(test_large_nodes_read_light_near_the_receiver),
        cmocka_unit_test(test_samples_hold_the_cut_total),
        cmocka_unit_test(test_rows_list_vertices_where_they_hold_the_light),
        cmocka_unit_test(test_larger_budget_keeps_how_rows_are_held),
        cmocka_unit_test(test_budget_beyond_n_merges_and_folds),
        cmocka_unit_test(test_bit_identical_for_any_thread_count),
        cmocka_unit_test(test_flat_scaled_carries_the_largest_cut),
        cmocka_unit_test(test_fewest_pairs_build),
        cmocka_unit_test(test_samfile_rows_follow_render_vertices),
        cmocka_unit_test(test_samfile_versions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
