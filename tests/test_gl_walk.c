/*
 * The runtime's sample walk (Sec. 3.4) on llvmpipe, on a thin slab: after a
 * bend the walked map is closer to a fresh build of the bent mesh than the
 * stale one (rest samples, posed K) by a bounded amount (a bend keeps each
 * vertex's opposite vertex on its normal, so the walk has nothing to gain
 * and its estimates cost a little); at rest the walk changes nothing; a
 * periodic animation does not drift; no sample adds light across the front;
 * the rest K computed once gives the T that evaluating it every frame does,
 * at rest and posed.
 */
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
#include "sam/sam_deform.h"
#include "sam/sam_mesh.h"
#include "sam/sam_runtime.h"
#include "sam_test.h"

#define MM_PER_UNIT 50.0f /* the fixture: a 50 mm slab, 2 mm thick */

typedef struct fixture {
    sam_mesh mesh;
    samfile_data sam;
    sam_profile profile;
    sam_build_settings settings;
    sam_runtime *rt;
    float mm_per_unit;
    uint32_t nv, n;
    double node_share; /* of the map's samples, tree nodes */
    float *pos, *nrm, *ld, *t, *t_ref;
} fixture;

/* A shape's map in `material` of kind `map` (a flat one with 4 samples per
 * vertex, a cut one with its default budget) and enough Monte Carlo pairs
 * that two builds differ by less than a pose does, on the GPU, lit by one
 * directional light; 0 on success. */
static int fixture_init(fixture *f, const char *shape, int resolution, double size, double thickness,
                        float mm_per_unit, const char *material, sam_build_map map)
{
    sam_error err;
    memset(f, 0, sizeof *f);
    sam_test_shape_mesh(shape, resolution, size, thickness, 0, &f->mesh);
    f->mm_per_unit = mm_per_unit;
    if (sam_profile_preset(material, &f->profile, &err) != SAM_OK)
        return -1;
    sam_build_default_settings(&f->settings);
    f->settings.map = map;
    f->settings.samples_per_vertex = map == SAM_BUILD_MAP_FLAT ? 4 : 0;
    f->settings.mc_samples = 8192;
    if (sam_build_samfile(&f->mesh, &f->profile, mm_per_unit, &f->settings, NULL, NULL, NULL, &f->sam, NULL,
                          &err) != SAM_OK ||
        sam_runtime_create(&f->sam, &f->profile, mm_per_unit, &f->rt, &err) != SAM_OK) {
        printf("setup: %s\n", err.message);
        return -1;
    }
    f->nv = f->sam.vertex_count;
    f->n = f->sam.samples_per_vertex;
    f->node_share = sam_test_node_share(f->sam.sample_index, f->nv, f->n, f->nv);
    f->pos = malloc(f->nv * 3 * sizeof *f->pos);
    f->nrm = malloc(f->nv * 3 * sizeof *f->nrm);
    f->ld = malloc(f->nv * 3 * sizeof *f->ld);
    f->t = malloc(f->nv * 3 * sizeof *f->t);
    f->t_ref = malloc(f->nv * 3 * sizeof *f->t_ref);
    sam_light light = {.type = SAM_LIGHT_DIRECTIONAL, .color = {1, 1, 1}, .intensity = 1, .direction = {0.3f, -1, 0}};
    if (sam_runtime_set_lights(f->rt, &light, 1, &err) != SAM_OK)
        return -1;
    return f->pos && f->nrm && f->ld && f->t && f->t_ref ? 0 : -1;
}

static void fixture_free(fixture *f)
{
    sam_runtime_destroy(f->rt);
    samfile_free(&f->sam);
    sam_mesh_destroy(&f->mesh);
    free(f->pos);
    free(f->nrm);
    free(f->ld);
    free(f->t);
    free(f->t_ref);
}

static int fixture_setup(void **state)
{
    if (sam_test_gl_setup(state) != 0)
        return -1;
    static fixture f;
    if (fixture_init(&f, "slab", 20, 1.0, 0.04, MM_PER_UNIT, "skin", SAM_BUILD_MAP_FLAT) != 0)
        return -1;
    *state = &f;
    return 0;
}

static int fixture_teardown(void **state)
{
    fixture_free(*state);
    return sam_test_gl_teardown(state);
}

/* A bend of the slab (x along its width, y its thickness) about its middle,
 * by `angle_deg` over its width, periodic over `period_s` (0: static). */
static sam_deformer slab_bend(float angle_deg, float period_s)
{
    return (sam_deformer){.type = SAM_DEFORM_BEND, .axis = {1, 0, 0}, .direction = {0, 1, 0},
                          .length = 1.0f, .angle_deg = angle_deg, .period_s = period_s};
}

static void check(sam_status st, const sam_error *err)
{
    if (st != SAM_OK)
        fail_msg("%s", err->message);
}

/* Poses f->rt at time t, walking when `walk`. */
static void step(fixture *f, float t, int walk)
{
    sam_error err;
    check(sam_runtime_deform(f->rt, t, &err), &err);
    if (walk)
        check(sam_runtime_walk(f->rt, &err), &err);
}

/* Lights the current pose: L_d into f->ld, the unsmoothed T into f->t. */
static void light_pose(fixture *f)
{
    sam_error err;
    check(sam_runtime_irradiance(f->rt, &err), &err);
    check(sam_runtime_read_irradiance(f->rt, f->ld, &err), &err);
    check(sam_runtime_translucency(f->rt, 0, 0.0f, 1, &err), &err);
    check(sam_runtime_read_translucency(f->rt, f->t, &err), &err);
}

/* f->t_ref: T of a fresh build of the current pose (same triangles, the
 * posed normals), lit by f->ld. */
static void fresh_reference(fixture *f)
{
    sam_error err;
    check(sam_runtime_read_positions(f->rt, f->pos, &err), &err);
    check(sam_runtime_read_normals(f->rt, f->nrm, &err), &err);
    sam_mesh posed;
    sam_mesh_input in = {.name = "posed", .vertex_count = f->nv, .positions = f->pos, .normals = f->nrm,
                         .uvs = f->sam.uvs, .triangle_count = f->sam.triangle_count,
                         .triangles = f->sam.triangles};
    check(sam_mesh_create(&in, &posed, NULL, &err), &err);
    assert_int_equal(posed.vertex_count, f->nv);
    samfile_data sam;
    sam_runtime *rt;
    check(sam_build_samfile(&posed, &f->profile, f->mm_per_unit, &f->settings, NULL, NULL, NULL, &sam, NULL, &err),
          &err);
    check(sam_runtime_create(&sam, &f->profile, f->mm_per_unit, &rt, &err), &err);
    check(sam_runtime_set_irradiance(rt, f->ld, &err), &err);
    check(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), &err);
    check(sam_runtime_read_translucency(rt, f->t_ref, &err), &err);
    sam_runtime_destroy(rt);
    samfile_free(&sam);
    sam_mesh_destroy(&posed);
}

/* RMSE of t against f->t_ref, relative to the reference's RMS. */
static double relative_rmse_of(const fixture *f, const float *t)
{
    double se = 0, ss = 0;
    for (size_t i = 0; i < 3 * (size_t)f->nv; ++i) {
        se += ((double)t[i] - f->t_ref[i]) * ((double)t[i] - f->t_ref[i]);
        ss += (double)f->t_ref[i] * f->t_ref[i];
    }
    return sqrt(se / ss);
}

static double relative_rmse(const fixture *f)
{
    return relative_rmse_of(f, f->t);
}

/* T of the rest-pose map left as built (its samples and its rest K, in a
 * runtime never deformed), lit by f->ld: what a renderer without the
 * update would show. */
static void stale_map_translucency(const fixture *f, float *t)
{
    sam_error err;
    sam_runtime *rt;
    check(sam_runtime_create(&f->sam, &f->profile, f->mm_per_unit, &rt, &err), &err);
    check(sam_runtime_set_irradiance(rt, f->ld, &err), &err);
    check(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), &err);
    check(sam_runtime_read_translucency(rt, t, &err), &err);
    sam_runtime_destroy(rt);
}

/* Ramps deformer `d` up over `frames` frames (a quarter of the period it is
 * given), walking every frame when `walk`. */
static void ramp_deformer(fixture *f, sam_deformer d, int frames, int walk)
{
    sam_error err;
    d.period_s = 4.0f * (float)frames / 30.0f;
    check(sam_runtime_set_deformers(f->rt, &d, 1, &err), &err);
    step(f, 0.0f, 0); /* back to rest and the .sam's samples */
    for (int i = 1; i <= frames; ++i)
        step(f, (float)i / 30.0f, walk);
}

/* The same for a bend of the slab by `angle_deg`. */
static void ramp(fixture *f, float angle_deg, int frames, int walk)
{
    ramp_deformer(f, slab_bend(angle_deg, 0.0f), frames, walk);
}

/* T's relative RMSE against a fresh build of the pose `d` reaches, for the
 * stale rest-pose map, K updated on the rest samples, and K updated and
 * walked. */
static void update_errors(fixture *f, sam_deformer d, double *stale, double *posed, double *walked)
{
    ramp_deformer(f, d, 20, 0);
    light_pose(f);
    fresh_reference(f);
    *posed = relative_rmse(f);
    float *t_stale = malloc(f->nv * 3 * sizeof *t_stale);
    assert_non_null(t_stale);
    stale_map_translucency(f, t_stale);
    *stale = relative_rmse_of(f, t_stale);
    free(t_stale);
    ramp_deformer(f, d, 20, 1);
    light_pose(f);
    *walked = relative_rmse(f);
}

/* update_errors on a 60 mm ear-like shell in `material` twisted by 90
 * degrees, its map of kind `map`, its posed K by `mode`; the share of the
 * map's samples that are tree nodes into *node_share. */
static void ear_twist_errors(const char *material, sam_build_map map, sam_posed_k mode, double *stale, double *posed,
                             double *walked, double *node_share)
{
    fixture f;
    assert_int_equal(fixture_init(&f, "ear", 48, 1.0, 0.0333, 60.0f, material, map), 0);
    *node_share = f.node_share;
    sam_error err;
    assert_int_equal(sam_runtime_set_posed_k(f.rt, mode, &err), SAM_OK);
    sam_deformer twist = {.type = SAM_DEFORM_TWIST, .axis = {0, 1, 0}, .length = 1.0f, .angle_deg = 90.0f};
    update_errors(&f, twist, stale, posed, walked);
    fixture_free(&f);
}

/* The other two cases: a twisting ear-like shell and a waving thin sheet,
 * each against a fresh build of its pose. */
static void test_twisting_ear_and_waving_sheet(void **state)
{
    (void)state;
    fixture f;
    double stale, posed, walked;
    double node_share;
    ear_twist_errors("skin", SAM_BUILD_MAP_FLAT, SAM_POSED_K_CARRIED, &stale, &posed, &walked, &node_share);
    printf("ear twisted 90 deg: T relative RMSE against a fresh build: stale %.4f, updated K %.4f, walked %.4f\n",
           stale, posed, walked);
    /* Measured 0.2216 stale, 0.1530 updated, 0.0933 walked. */
    assert_true(walked < 0.75 * stale);
    assert_int_equal(fixture_init(&f, "slab", 24, 1.0, 0.04, MM_PER_UNIT, "skin", SAM_BUILD_MAP_FLAT), 0);
    sam_deformer wave = {.type = SAM_DEFORM_WAVE, .axis = {1, 0, 0}, .direction = {0, 1, 0}, .amplitude = 0.04f,
                         .wavelength = 0.8f};
    update_errors(&f, wave, &stale, &posed, &walked);
    printf("sheet waving (0.04 amplitude, 0.8 wavelength): stale %.4f, updated K %.4f, walked %.4f\n", stale, posed,
           walked);
    /* Measured 0.0774 stale, 0.0613 updated, 0.0404 walked. With K carried
     * by eq. 15's point estimate the update lost here (0.1095 updated,
     * 0.0980 walked): the wave shears the fans against each other
     * (shaders/fan_form_factor.glsl). */
    assert_true(posed < stale);
    assert_true(walked < 0.75 * stale);
    fixture_free(&f);
    /* The paper's eq. 15 on the same pose, still selectable. */
    double eq15_stale, eq15_posed, eq15_walked;
    assert_int_equal(fixture_init(&f, "slab", 24, 1.0, 0.04, MM_PER_UNIT, "skin", SAM_BUILD_MAP_FLAT), 0);
    sam_error err;
    assert_int_equal(sam_runtime_set_posed_k(f.rt, SAM_POSED_K_EQ15, &err), SAM_OK);
    assert_int_equal(sam_runtime_set_posed_k(f.rt, (sam_posed_k)7, &err), SAM_ERR_INVALID_ARGUMENT);
    update_errors(&f, wave, &eq15_stale, &eq15_posed, &eq15_walked);
    printf("the same wave with eq. 15's K: stale %.4f, updated K %.4f, walked %.4f\n", eq15_stale, eq15_posed,
           eq15_walked);
    assert_true(eq15_stale == stale);
    assert_true(eq15_posed > posed && eq15_walked > walked);
    fixture_free(&f);
}

/* A cut map (the default) under the same twist: its nodes' K follows the
 * pose without blowing up, and the update beats the stale map. In skin the
 * ear's rows are its best vertices (sam_build_cut.c's list_back_side), in
 * marble a third of its samples are tree nodes. */
static void test_cut_map_follows_a_twist(void **state)
{
    (void)state;
    static const char *const materials[] = {"skin", "marble"};
    for (int m = 0; m < 2; ++m) {
        double stale, posed, walked, node_share;
        ear_twist_errors(materials[m], SAM_BUILD_MAP_CUT, SAM_POSED_K_CARRIED, &stale, &posed, &walked, &node_share);
        printf("cut map in %s (%.1f%% of its samples tree nodes), ear twisted 90 deg: T relative RMSE against a "
               "fresh cut build: stale %.4f, updated K %.4f, walked %.4f\n",
               materials[m], 100.0 * node_share, stale, posed, walked);
        assert_true(posed < stale);
        assert_true(walked < stale);
    }
    /* Eq. 15's K takes the same bounded change for the nodes. */
    double eq15_stale, eq15_posed, eq15_walked, node_share;
    ear_twist_errors("marble", SAM_BUILD_MAP_CUT, SAM_POSED_K_EQ15, &eq15_stale, &eq15_posed, &eq15_walked,
                     &node_share);
    printf("the same in marble with eq. 15's K: stale %.4f, updated K %.4f, walked %.4f\n", eq15_stale, eq15_posed,
           eq15_walked);
    assert_true(node_share > 0.25);
    assert_true(eq15_walked < eq15_stale);
}

/* A cut map's rows partition the back side in reach: its nodes, their
 * carried K (handed down the tree where the light comes from) and its
 * vertices count every back-side vertex once, and a row with a spare slot
 * is one whose cut ended there. The walk fills no spare slot and replaces
 * only samples the pose took off the back side, so a pose a hair from
 * rest gives the rest's T (a torus in skin and an ear in marble, twisted
 * by 1e-4 degrees). Filling spare slots and swapping by estimate took
 * 34.5% of the torus's T away from the rest's (1.37 times the light) at
 * the first posed frame, with nothing moved. */
static void test_cut_map_is_continuous_at_rest(void **state)
{
    (void)state;
    static const struct {
        const char *shape, *material;
        int resolution;
        double thickness;
        float mm_per_unit;
    } cases[] = {{"torus", "skin", 24, 0.3, 40.0f}, {"ear", "marble", 48, 0.0333, 60.0f}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        fixture f;
        assert_int_equal(fixture_init(&f, cases[c].shape, cases[c].resolution, 1.0, cases[c].thickness,
                                      cases[c].mm_per_unit, cases[c].material, SAM_BUILD_MAP_CUT),
                         0);
        light_pose(&f);
        memcpy(f.t_ref, f.t, f.nv * 3 * sizeof *f.t);
        sam_error err;
        sam_deformer hair = {.type = SAM_DEFORM_TWIST, .axis = {0, 1, 0}, .length = 1.0f, .angle_deg = 1e-4f};
        check(sam_runtime_set_deformers(f.rt, &hair, 1, &err), &err);
        for (int i = 0; i < 3; ++i)
            step(&f, 0.0f, 1);
        light_pose(&f);
        const double change = relative_rmse(&f);
        printf("cut map of a %s in %s (%.1f%% of its samples tree nodes), twisted 1e-4 deg and walked 3 times: T "
               "relative RMS change %.2e\n",
               cases[c].shape, cases[c].material, 100.0 * f.node_share, change);
        assert_true(change < 1e-3);
        fixture_free(&f);
    }
}

static void test_walk_against_a_fresh_build(void **state)
{
    fixture *f = *state;
    const float angle = 240.0f;
    /* The floor: the .sam against a build of the same rest mesh with
     * another seed differ by the Monte Carlo noise of K alone. */
    ramp(f, angle, 20, 0);
    step(f, 0.0f, 0);
    light_pose(f);
    f->settings.seed = 2;
    fresh_reference(f);
    f->settings.seed = 1;
    double floor_rmse = relative_rmse(f);
    double stale, posed, walked;
    update_errors(f, slab_bend(angle, 0.0f), &stale, &posed, &walked);
    printf("slab bent %.0f deg: T relative RMSE against a fresh build: stale rest-pose map %.4f, updated K "
           "(rest samples) %.4f, updated K and walked %.4f; two rest builds (seeds 1, 2) differ by %.4f\n",
           angle, stale, posed, walked, floor_rmse);
    /* Measured with 8192 Monte Carlo pairs: stale 0.0658, posed K 0.0432,
     * walked 0.0432; two seeds of the rest build differ by 0.0338 (with
     * 4096 and builder 1.2: 0.0750, 0.0391, 0.0391, 0.0759; with 4096 and
     * builder 1.3, whose pairs count only behind the receiver's plane, the
     * builds' noise is less alike and the posed error 0.0580 reached the
     * stale map's 0.0743 times 0.78; with 16384: 0.0634, 0.0386, 0.0260). The
     * builds share seed 1, so their Monte Carlo noise is correlated and the
     * update's gain shows; a bend keeps each vertex's opposite vertex on
     * its normal, so the walk has little to find. */
    assert_true(walked < 0.75 * stale);
    assert_true(walked < posed * 1.2);
    assert_true(posed > 0.02); /* the pose did change K */
}

static void test_rest_walk_changes_nothing(void **state)
{
    fixture *f = *state;
    sam_error err;
    const size_t ns = (size_t)f->nv * f->n;
    uint32_t *idx = malloc(ns * sizeof *idx);
    float *kp = malloc(ns * 3 * sizeof *kp);
    assert_non_null(idx);
    assert_non_null(kp);
    /* Bent and walked first, so the samples have moved; at t = 0 the
     * periodic bend has strength 0. */
    ramp(f, 240.0f, 10, 1);
    check(sam_runtime_read_samples(f->rt, idx, kp, &err), &err);
    size_t moved = 0;
    for (size_t i = 0; i < ns; ++i)
        moved += idx[i] != f->sam.sample_index[i];
    step(f, 0.0f, 1);
    light_pose(f);
    memcpy(f->t_ref, f->t, f->nv * 3 * sizeof *f->t);
    check(sam_runtime_read_samples(f->rt, idx, kp, &err), &err);
    assert_memory_equal(idx, f->sam.sample_index, ns * sizeof *idx);
    /* The GPU holds K' packed (shaders/sample.glsl): each channel within
     * 2^-14 of itself. */
    size_t exact = 0;
    for (size_t i = 0; i < ns; ++i) {
        const float *want = f->sam.sample_kprime + 3 * i;
        for (int c = 0; c < 3; ++c) {
            assert_true(fabsf(kp[3 * i + c] - want[c]) <= 0x1p-14f * want[c]);
            exact += kp[3 * i + c] == want[c];
        }
    }
    float *kp_rest = malloc(ns * 3 * sizeof *kp_rest);
    assert_non_null(kp_rest);
    memcpy(kp_rest, kp, ns * 3 * sizeof *kp);
    for (int i = 0; i < 5; ++i)
        step(f, 0.0f, 1);
    light_pose(f);
    check(sam_runtime_read_samples(f->rt, idx, kp, &err), &err);
    assert_memory_equal(idx, f->sam.sample_index, ns * sizeof *idx);
    assert_memory_equal(kp, kp_rest, ns * 3 * sizeof *kp);
    assert_memory_equal(f->t, f->t_ref, f->nv * 3 * sizeof *f->t);
    printf("%zu of %zu samples moved during the bend; at rest samples, K' and T are bit-identical after 5 "
           "walks; %zu of %zu K' channels held exactly, the rest within 2^-14\n",
           moved, ns, exact, 3 * ns);
    assert_true(moved > 0);
    assert_true(exact < 3 * ns); /* packed, not copied */
    free(idx);
    free(kp);
    free(kp_rest);
}

static void test_periodic_animation_does_not_drift(void **state)
{
    fixture *f = *state;
    sam_error err;
    const int period = 100, periods = 3;
    sam_deformer d = slab_bend(240.0f, (float)period / 30.0f);
    check(sam_runtime_set_deformers(f->rt, &d, 1, &err), &err);
    step(f, 0.0f, 0);
    light_pose(f);
    memcpy(f->t_ref, f->t, f->nv * 3 * sizeof *f->t); /* the .sam's own T at rest */
    double error[3] = {0};
    for (int frame = 1; frame <= period * periods; ++frame) {
        step(f, (float)frame / 30.0f, 1);
        if (frame % period == 0) {
            light_pose(f);
            error[frame / period - 1] = relative_rmse(f);
        }
    }
    printf("T relative RMSE against the rest map at the returns to rest: %.2e, %.2e, %.2e\n", error[0], error[1],
           error[2]);
    assert_true(error[2] <= error[0] * 1.05 + 1e-6);
}

static int back_side(const float *pos, const float *nrm, uint32_t o, uint32_t i)
{
    double along = 0, facing = 0;
    for (int c = 0; c < 3; ++c) {
        along += ((double)pos[3 * i + c] - pos[3 * o + c]) * nrm[3 * o + c];
        facing += (double)nrm[3 * i + c] * nrm[3 * o + c];
    }
    return along < 0 && facing < 0;
}

/* The CPU counterpart of fan_integral in shaders/fan_form_factor.glsl: the
 * integral over t's reduced fan (the .sam's ring, at positions `pos`) of
 * R_d(|x - c|), c in mm, by one point per fan triangle; t's reduced fan
 * area in `area`. */
static void fan_integral(const fixture *f, const float *pos, uint32_t t, const double c[3], double sum[3],
                         double *area)
{
    const uint32_t *off = f->sam.adjacency_offsets, *ring = f->sam.adjacency;
    const float *v = pos + 3 * (size_t)t;
    sum[0] = sum[1] = sum[2] = *area = 0;
    for (uint32_t k = off[t] + 1; k < off[t + 1]; ++k) {
        const float *a = pos + 3 * (size_t)ring[k - 1], *b = pos + 3 * (size_t)ring[k];
        double e1[3], e2[3], d2 = 0;
        for (int i = 0; i < 3; ++i) {
            e1[i] = (double)a[i] - v[i];
            e2[i] = (double)b[i] - v[i];
            double x = f->mm_per_unit * (v[i] + 7.0 / 36.0 * (e1[i] + e2[i]));
            d2 += (x - c[i]) * (x - c[i]);
        }
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
        double w = sqrt(cx * cx + cy * cy + cz * cz) * f->mm_per_unit * f->mm_per_unit / 6.0;
        float rd[3];
        sam_profile_eval(&f->profile, (float)sqrt(d2), rd);
        for (int i = 0; i < 3; ++i)
            sum[i] += w * rd[i];
        *area += w;
    }
}

/* fan_quadrature of fan_form_factor.glsl: the mean of the two one-sided
 * rules for eq. 11 between the fans of o and i; i's fan area in `area_i`. */
static void fan_quadrature(const fixture *f, const float *pos, uint32_t o, uint32_t i, double q[3], double *area_i)
{
    double co[3], ci[3], from_i[3], from_o[3], area_o;
    for (int c = 0; c < 3; ++c) {
        co[c] = f->mm_per_unit * (double)pos[3 * o + c];
        ci[c] = f->mm_per_unit * (double)pos[3 * i + c];
    }
    fan_integral(f, pos, i, co, from_i, area_i);
    fan_integral(f, pos, o, ci, from_o, &area_o);
    for (int c = 0; c < 3; ++c)
        q[c] = 0.5 * (from_i[c] + (area_o > 0 ? from_o[c] * *area_i / area_o : 0.0));
}

/* The distance (mm) between vertices o and i at `pos`. */
static double distance_mm(const fixture *f, const float *pos, uint32_t o, uint32_t i)
{
    double d2 = 0;
    for (int c = 0; c < 3; ++c)
        d2 += ((double)pos[3 * i + c] - pos[3 * o + c]) * ((double)pos[3 * i + c] - pos[3 * o + c]);
    return sqrt(d2) * f->mm_per_unit;
}

/* K of sample i of vertex o in slot `slot` at the pose f->pos, its K'
 * holding at the rest pose (the .sam's positions), as the translucency
 * pass carries it: by the fans' quadrature in the first 3 slots, by eq.
 * 15 at the pose after them. */
static void posed_k(const fixture *f, uint32_t o, uint32_t i, uint32_t slot, const float *kprime, double k[3])
{
    double q_rest[3], q_pose[3], rest_area, area;
    float rd[3];
    fan_quadrature(f, f->pos, o, i, q_pose, &area);
    if (slot >= 3) {
        sam_profile_eval(&f->profile, (float)distance_mm(f, f->pos, o, i), rd);
        for (int c = 0; c < 3; ++c)
            k[c] = kprime[c] * area * rd[c];
        return;
    }
    sam_profile_eval(&f->profile, (float)distance_mm(f, f->sam.positions, o, i), rd);
    fan_quadrature(f, f->sam.positions, o, i, q_rest, &rest_area);
    for (int c = 0; c < 3; ++c)
        k[c] = q_rest[c] > 0 ? kprime[c] * rest_area * rd[c] * q_pose[c] / q_rest[c] : 0.0;
}

/* Checks that the GPU's T (L_d = 1) is the sum over the samples on the
 * back side at the pose, not over all; returns how many are off it. */
static size_t check_back_side_only(fixture *f, uint32_t *idx, float *kp)
{
    sam_error err;
    check(sam_runtime_read_positions(f->rt, f->pos, &err), &err);
    check(sam_runtime_read_normals(f->rt, f->nrm, &err), &err);
    check(sam_runtime_read_samples(f->rt, idx, kp, &err), &err);
    for (size_t i = 0; i < 3 * (size_t)f->nv; ++i)
        f->ld[i] = 1.0f;
    check(sam_runtime_set_irradiance(f->rt, f->ld, &err), &err);
    check(sam_runtime_translucency(f->rt, 0, 0.0f, 1, &err), &err);
    check(sam_runtime_read_translucency(f->rt, f->t, &err), &err);
    size_t off = 0;
    double worst_valid = 0, worst_all = 0;
    for (uint32_t v = 0; v < f->nv; ++v) {
        double valid[3] = {0}, all[3] = {0};
        for (uint32_t k = 0; k < f->n; ++k) {
            uint32_t b = idx[(size_t)v * f->n + k];
            if (b == SAMFILE_NO_SAMPLE)
                break;
            double kk[3];
            posed_k(f, v, b, k, kp + ((size_t)v * f->n + k) * 3, kk);
            int ok = back_side(f->pos, f->nrm, v, b);
            off += !ok;
            for (int c = 0; c < 3; ++c) {
                all[c] += kk[c];
                valid[c] += ok ? kk[c] : 0.0;
            }
        }
        for (int c = 0; c < 3; ++c) {
            double scale = fmax(valid[c], 1e-3);
            worst_valid = fmax(worst_valid, fabs(f->t[3 * v + c] - valid[c]) / scale);
            worst_all = fmax(worst_all, fabs(all[c] - valid[c]) / scale);
        }
    }
    printf("%zu samples off the back side; GPU T differs from the back-side-only sum by %.2e (relative), the "
           "all-samples sum by %.2e\n", off, worst_valid, worst_all);
    assert_true(worst_valid < 1e-3);
    if (off)
        assert_true(worst_all > 1e-2);
    return off;
}

static void test_no_sample_adds_light_through_the_front(void **state)
{
    fixture *f = *state;
    sam_error err;
    const size_t ns = (size_t)f->nv * f->n;
    uint32_t *idx = malloc(ns * sizeof *idx);
    float *kp = malloc(ns * 3 * sizeof *kp);
    assert_non_null(idx);
    assert_non_null(kp);
    /* A strong bend with a twist on top, in one jump: the rest samples are
     * pushed off the back side; then walks replace them. */
    sam_deformer d[2] = {slab_bend(330.0f, 0.0f),
                         {.type = SAM_DEFORM_TWIST, .axis = {1, 0, 0}, .length = 1.0f, .angle_deg = 200.0f}};
    check(sam_runtime_set_deformers(f->rt, d, 2, &err), &err);
    step(f, 0.0f, 0);
    printf("strong bend + twist, rest samples: ");
    size_t stale = check_back_side_only(f, idx, kp);
    for (int i = 0; i < 3; ++i)
        step(f, 0.0f, 1);
    printf("after 3 walks: ");
    size_t walked = check_back_side_only(f, idx, kp);
    assert_true(stale > 0); /* else this test shows nothing */
    assert_true(walked < stale);
    check(sam_runtime_set_deformers(f->rt, NULL, 0, &err), &err);
    free(idx);
    free(kp);
}

/* The largest difference of a and b (vertex_count x 3) relative to b's
 * largest value. */
static double max_relative_difference(const fixture *f, const float *a, const float *b)
{
    double diff = 0, scale = 0;
    for (size_t i = 0; i < (size_t)f->nv * 3; ++i) {
        diff = fmax(diff, fabs((double)a[i] - b[i]));
        scale = fmax(scale, fabs((double)b[i]));
    }
    return scale > 0 ? diff / scale : diff;
}

/* A cut map (vertex and node samples: marble) on the twisting ear: T with the rest
 * K cached equals T with it evaluated per frame up to K's packing, at
 * rest and on a walked pose (where a node's rest K comes from the cache);
 * a cache refilled while posed comes from the rest pose, bit for bit. */
static void test_cached_rest_k_matches_evaluated(void **state)
{
    (void)state;
    fixture f;
    assert_int_equal(fixture_init(&f, "ear", 48, 1.0, 0.0333, 60.0f, "marble", SAM_BUILD_MAP_CUT), 0);
    assert_true(f.node_share > 0.25);
    sam_error err;
    const size_t bytes = (size_t)f.nv * 3 * sizeof(float);
    float *cached = malloc(bytes), *first = malloc(bytes);
    assert_non_null(cached);
    assert_non_null(first);
    assert_int_equal(sam_runtime_rest_k_mode(f.rt), SAM_REST_K_CACHED);
    light_pose(&f);
    memcpy(first, f.t, bytes);
    check(sam_runtime_set_rest_k(f.rt, SAM_REST_K_EVALUATED, &err), &err);
    assert_int_equal(sam_runtime_rest_k_mode(f.rt), SAM_REST_K_EVALUATED);
    light_pose(&f);
    const double rest = max_relative_difference(&f, first, f.t);
    sam_deformer twist = {.type = SAM_DEFORM_TWIST, .axis = {0, 1, 0}, .length = 1.0f, .angle_deg = 90.0f};
    ramp_deformer(&f, twist, 10, 1);
    light_pose(&f);
    memcpy(cached, f.t, bytes);
    check(sam_runtime_set_rest_k(f.rt, SAM_REST_K_CACHED, &err), &err); /* filled while posed */
    light_pose(&f);
    const double posed = max_relative_difference(&f, f.t, cached);
    step(&f, 0.0f, 0); /* back to rest (the twist's strength is 0 at t = 0) */
    light_pose(&f);
    printf("cut map on the ear: T cached against evaluated rest K: largest difference %.2g of the largest T at "
           "rest, %.2g on a walked twist\n",
           rest, posed);
    /* The cache holds K packed (shaders/sample.glsl), each channel within
     * 2^-14 of itself; evaluated, K comes from the packed K'. */
    assert_true(rest < 2e-4);
    assert_true(posed < 2e-4);
    assert_true(memcmp(cached, first, bytes) != 0); /* the pose changed T */
    assert_memory_equal(f.t, first, bytes);
    assert_int_equal(sam_runtime_set_rest_k(f.rt, (sam_rest_k)5, &err), SAM_ERR_INVALID_ARGUMENT);
    free(cached);
    free(first);
    fixture_free(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_walk_against_a_fresh_build),
        cmocka_unit_test(test_twisting_ear_and_waving_sheet),
        cmocka_unit_test(test_cut_map_follows_a_twist),
        cmocka_unit_test(test_cut_map_is_continuous_at_rest),
        cmocka_unit_test(test_rest_walk_changes_nothing),
        cmocka_unit_test(test_periodic_animation_does_not_drift),
        cmocka_unit_test(test_no_sample_adds_light_through_the_front),
        cmocka_unit_test(test_cached_rest_k_matches_evaluated),
    };
    return cmocka_run_group_tests(tests, fixture_setup, fixture_teardown);
}
