/*
 * The runtime's deform pass on llvmpipe: deformed positions against
 * sam_deform_positions, normals against a mesh built from those positions,
 * fan areas against sam_mesh_fan_areas, seam copies kept identical, the
 * rest pose restored bit for bit, and the later passes reading the pose.
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

#define MM_PER_UNIT 60.0f

/* The ear shape, its .sam (render vertices in the mesh's order) and a runtime. */
typedef struct fixture {
    sam_mesh mesh;
    samfile_data sam;
    sam_runtime *rt;
    float lo[3], hi[3], size; /* bounds and diagonal, model units */
    float *pos, *nrm, *fan;   /* read-back space */
} fixture;

static int fixture_setup(void **state)
{
    if (sam_test_gl_setup(state) != 0)
        return -1;
    static fixture f;
    sam_error err;
    sam_profile profile;
    sam_test_shape_mesh("ear", 24, 0, 0, 0, &f.mesh);
    if (sam_profile_preset("skin", &profile, &err) != SAM_OK)
        return -1;
    sam_build_settings set;
    sam_build_default_settings(&set);
    set.samples_per_vertex = 4;
    if (sam_build_samfile(&f.mesh, &profile, MM_PER_UNIT, &set, NULL, NULL, NULL, &f.sam, NULL, &err) != SAM_OK ||
        sam_runtime_create(&f.sam, &profile, MM_PER_UNIT, &f.rt, &err) != SAM_OK) {
        printf("setup: %s\n", err.message);
        return -1;
    }
    printf("%.1f%% of the map's samples are tree nodes\n",
           100.0 * sam_test_node_share(f.sam.sample_index, f.sam.vertex_count, 4, f.sam.vertex_count));
    sam_mesh_bounds(&f.mesh, f.lo, f.hi);
    f.size = (float)sam_mesh_diagonal(&f.mesh);
    size_t nv = f.sam.vertex_count;
    f.pos = malloc(nv * 3 * sizeof *f.pos);
    f.nrm = malloc(nv * 3 * sizeof *f.nrm);
    f.fan = malloc(nv * sizeof *f.fan);
    *state = &f;
    return f.pos && f.nrm && f.fan ? 0 : -1;
}

static int fixture_teardown(void **state)
{
    fixture *f = *state;
    sam_runtime_destroy(f->rt);
    samfile_free(&f->sam);
    sam_mesh_destroy(&f->mesh);
    free(f->pos);
    free(f->nrm);
    free(f->fan);
    return sam_test_gl_teardown(state);
}

static void read_pose(fixture *f)
{
    sam_error err;
    assert_int_equal(sam_runtime_read_positions(f->rt, f->pos, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_normals(f->rt, f->nrm, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_fan_areas(f->rt, f->fan, &err), SAM_OK);
}

static void pose(fixture *f, const sam_deformer *d, size_t count, float t)
{
    sam_error err;
    if (sam_runtime_set_deformers(f->rt, d, count, &err) != SAM_OK || sam_runtime_deform(f->rt, t, &err) != SAM_OK)
        fail_msg("%s", err.message);
    read_pose(f);
}

/* One deformer of each type, sized to the object, periodic over 2 s. */
static sam_deformer example(const fixture *f, sam_deformer_type type)
{
    sam_deformer d = {.type = type, .period_s = 2.0f};
    for (int k = 0; k < 3; ++k)
        d.center[k] = 0.5f * (f->lo[k] + f->hi[k]);
    float along[3] = {0, 1, 0}, across[3] = {1, 0, 0};
    memcpy(d.axis, along, sizeof along);
    memcpy(d.direction, across, sizeof across);
    d.length = f->size;
    d.angle_deg = type == SAM_DEFORM_BEND ? 70.0f : 120.0f;
    d.amount = 0.3f;
    d.amplitude = 0.05f * f->size;
    d.wavelength = 0.5f * f->size;
    d.speed = 0.3f * f->size;
    return d;
}

static double angle_deg(const float *a, const float *b)
{
    double dot = 0, la = 0, lb = 0;
    for (int k = 0; k < 3; ++k) {
        dot += (double)a[k] * b[k];
        la += (double)a[k] * a[k];
        lb += (double)b[k] * b[k];
    }
    return acos(fmax(-1.0, fmin(1.0, dot / sqrt(la * lb)))) * 180.0 / 3.14159265358979323846;
}

static void test_pose_matches_cpu(void **state)
{
    fixture *f = *state;
    const uint32_t nv = f->sam.vertex_count;
    float *ref = malloc(nv * 3 * sizeof *ref), *ref_fan = malloc(f->mesh.topo_count * sizeof *ref_fan);
    assert_non_null(ref);
    assert_non_null(ref_fan);
    const float times[] = {0.3f, 0.5f, 1.7f};
    for (int type = SAM_DEFORM_BEND; type <= SAM_DEFORM_WAVE; ++type) {
        sam_deformer d = example(f, (sam_deformer_type)type);
        for (size_t ti = 0; ti < sizeof times / sizeof times[0]; ++ti) {
            pose(f, &d, 1, times[ti]);
            sam_deform_step step;
            assert_int_equal(sam_deform_prepare(&d, 1, times[ti], &step), 1);
            sam_deform_positions(&step, 1, f->sam.positions, ref, nv);
            double pos_err = 0, moved = 0;
            for (size_t i = 0; i < 3 * (size_t)nv; ++i) {
                pos_err = fmax(pos_err, fabs((double)f->pos[i] - ref[i]));
                moved = fmax(moved, fabs((double)ref[i] - f->sam.positions[i]));
            }
            pos_err /= f->size;
            moved /= f->size;
            /* Normals: the area-weighted normals of a mesh built from the pose
             * (its topo normals; UVs and normals keep the render vertices apart). */
            sam_mesh posed;
            sam_error err;
            sam_mesh_input in = {.name = "posed", .vertex_count = nv, .positions = ref,
                                 .normals = f->sam.normals, .uvs = f->sam.uvs,
                                 .triangle_count = f->sam.triangle_count, .triangles = f->sam.triangles};
            if (sam_mesh_create(&in, &posed, NULL, &err) != SAM_OK)
                fail_msg("%s", err.message);
            assert_int_equal(posed.vertex_count, nv);
            double worst_angle = 0, fan_err = 0;
            sam_mesh_fan_areas(&f->mesh, ref, MM_PER_UNIT, ref_fan);
            for (uint32_t v = 0; v < nv; ++v) {
                worst_angle = fmax(worst_angle, angle_deg(f->nrm + 3 * v, posed.topo_normals + 3 * posed.topo_of[v]));
                double want = ref_fan[f->mesh.topo_of[v]];
                fan_err = fmax(fan_err, fabs(f->fan[v] - want) / want);
            }
            sam_mesh_destroy(&posed);
            printf("%-6s t=%.1f: moved %.3f of the size; position error %.2e of the size, normal %.2e deg, "
                   "fan area %.2e relative\n",
                   sam_deformer_type_name((sam_deformer_type)type), times[ti], moved, pos_err, worst_angle,
                   fan_err);
            assert_true(moved > 0.01);
            assert_true(pos_err < 1e-5);
            assert_true(worst_angle < 0.1);
            assert_true(fan_err < 1e-5);
        }
    }
    free(ref);
    free(ref_fan);
}

static void test_seam_copies_stay_identical(void **state)
{
    fixture *f = *state;
    sam_deformer d[2] = {example(f, SAM_DEFORM_TWIST), example(f, SAM_DEFORM_BEND)};
    pose(f, d, 2, 0.4f);
    uint32_t copies = 0;
    for (uint32_t v = 0; v < f->sam.vertex_count; ++v) {
        uint32_t rep = f->mesh.topo_rep[f->mesh.topo_of[v]];
        if (rep == v)
            continue;
        copies++;
        assert_memory_equal(f->pos + 3 * v, f->pos + 3 * rep, 3 * sizeof(float));
        assert_memory_equal(f->nrm + 3 * v, f->nrm + 3 * rep, 3 * sizeof(float));
        assert_memory_equal(f->fan + v, f->fan + rep, sizeof(float));
    }
    printf("%u seam copies of %u vertices match their vertex bit for bit\n", copies, f->sam.vertex_count);
    assert_true(copies > 0);
}

static void test_rest_pose_is_bit_identical(void **state)
{
    fixture *f = *state;
    const size_t nv = f->sam.vertex_count;
    pose(f, NULL, 0, 0.0f); /* whatever an earlier test left: no deformers restores the rest pose */
    assert_memory_equal(f->pos, f->sam.positions, nv * 3 * sizeof(float));
    assert_memory_equal(f->nrm, f->sam.normals, nv * 3 * sizeof(float));
    assert_memory_equal(f->fan, f->sam.fan_area, nv * sizeof(float));
    sam_deformer d[4];
    for (int type = 0; type < 4; ++type)
        d[type] = example(f, (sam_deformer_type)type);
    /* At t = 0 every periodic deformer has strength 0, after a pose too. */
    pose(f, d, 4, 0.5f);
    assert_memory_not_equal(f->pos, f->sam.positions, nv * 3 * sizeof(float));
    pose(f, d, 4, 0.0f);
    assert_memory_equal(f->pos, f->sam.positions, nv * 3 * sizeof(float));
    assert_memory_equal(f->nrm, f->sam.normals, nv * 3 * sizeof(float));
    assert_memory_equal(f->fan, f->sam.fan_area, nv * sizeof(float));
    pose(f, d, 4, 2.0f); /* a whole period: sin(2 pi) is not exactly 0 */
    double drift = 0;
    for (size_t i = 0; i < 3 * nv; ++i)
        drift = fmax(drift, fabs(f->pos[i] - f->sam.positions[i]));
    printf("rest pose restored bit for bit; after one period positions differ by %.2e of the size\n",
           drift / f->size);
    assert_true(drift / f->size < 1e-6);
    sam_error err;
    assert_int_equal(sam_runtime_deform(f->rt, NAN, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "nan"));
    assert_int_equal(sam_runtime_set_deformers(f->rt, d, SAM_DEFORM_MAX + 1, &err), SAM_ERR_INVALID_ARGUMENT);
}

/* The bounds follow the pose: the box around the posed positions, exactly,
 * and the rest pose's bounds bit for bit at rest. */
static void test_bounds_follow_the_pose(void **state)
{
    fixture *f = *state;
    float rest_centre[3], rest_radius, centre[3], radius;
    sam_runtime_bounds(f->rt, rest_centre, &rest_radius);
    sam_deformer d = example(f, SAM_DEFORM_BEND);
    d.angle_deg = 200.0f;
    pose(f, &d, 1, 0.5f);
    sam_runtime_bounds(f->rt, centre, &radius);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < f->sam.vertex_count; ++v)
        for (int c = 0; c < 3; ++c) {
            lo[c] = fminf(lo[c], f->pos[3 * v + c]);
            hi[c] = fmaxf(hi[c], f->pos[3 * v + c]);
        }
    double r2 = 0, moved = 0;
    for (int c = 0; c < 3; ++c) {
        assert_true(centre[c] == 0.5f * (lo[c] + hi[c]));
        r2 += 0.25 * ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
        moved += fabs((double)centre[c] - rest_centre[c]);
    }
    assert_true(radius == (float)sqrt(r2));
    printf("bent 200 deg: bounding sphere centre moved %.3f, radius %.3f -> %.3f (model units)\n", moved, rest_radius,
           radius);
    assert_true(moved + fabs((double)radius - rest_radius) > 0.02 * rest_radius); /* the pose changed them */
    sam_deformer still = d;
    still.angle_deg = 0.0f;
    pose(f, &still, 1, 0.5f);
    sam_runtime_bounds(f->rt, centre, &radius);
    assert_memory_equal(centre, rest_centre, sizeof centre);
    assert_true(radius == rest_radius);
}

/* Pre-integrated shading's curvature follows the pose: the GPU's equals
 * sam_mesh_ring_curvature of the read-back pose, and the rest values come
 * back bit for bit. */
static void test_curvature_follows_the_pose(void **state)
{
    fixture *f = *state;
    size_t nv = f->sam.vertex_count;
    float *rest = malloc(nv * sizeof *rest), *gpu = malloc(nv * sizeof *gpu), *cpu = malloc(nv * sizeof *cpu);
    assert_true(rest && gpu && cpu);
    sam_error err;
    assert_int_equal(sam_runtime_read_curvature(f->rt, rest, &err), SAM_OK);
    sam_deformer d = example(f, SAM_DEFORM_TWIST);
    pose(f, &d, 1, 0.5f);
    assert_int_equal(sam_runtime_read_curvature(f->rt, gpu, &err), SAM_OK);
    sam_mesh_ring_curvature((uint32_t)nv, f->pos, NULL, f->nrm, f->sam.adjacency_offsets, f->sam.adjacency, cpu);
    double worst = 0, scale = 0, changed = 0;
    for (size_t v = 0; v < nv; ++v) {
        cpu[v] /= MM_PER_UNIT;
        scale = fmax(scale, fabs(cpu[v]));
        worst = fmax(worst, fabs((double)gpu[v] - cpu[v]));
        changed = fmax(changed, fabs((double)gpu[v] - rest[v]));
    }
    printf("twisted: curvature on the GPU within %.2e of the CPU's (largest |H| %.3f /mm); it changed by up to %.3f /mm\n",
           worst, scale, changed);
    assert_true(worst <= 1e-3 * scale);
    assert_true(changed > 0.05 * scale);
    sam_deformer still = d;
    still.angle_deg = 0.0f;
    pose(f, &still, 1, 0.5f);
    assert_int_equal(sam_runtime_read_curvature(f->rt, gpu, &err), SAM_OK);
    assert_memory_equal(gpu, rest, nv * sizeof *rest);
    free(rest);
    free(gpu);
    free(cpu);
}

static double max_relative_change(const float *a, const float *b, size_t n)
{
    double peak = 0, diff = 0;
    for (size_t i = 0; i < n; ++i) {
        peak = fmax(peak, fabs(a[i]));
        diff = fmax(diff, fabs(a[i] - b[i]));
    }
    return peak > 0 ? diff / peak : 0.0;
}

static void test_later_passes_follow_the_pose(void **state)
{
    fixture *f = *state;
    const size_t nv = f->sam.vertex_count;
    float *rest = malloc(nv * 3 * sizeof *rest), *posed = malloc(nv * 3 * sizeof *posed),
          *ones = malloc(nv * 3 * sizeof *ones);
    assert_non_null(rest);
    assert_non_null(posed);
    assert_non_null(ones);
    sam_error err;
    sam_deformer bend = example(f, SAM_DEFORM_BEND);
    bend.period_s = 0;
    /* Translucency: eq. 15's distances and F'_b come from the pose. */
    for (size_t i = 0; i < 3 * nv; ++i)
        ones[i] = 1.0f;
    pose(f, NULL, 0, 0.0f);
    assert_int_equal(sam_runtime_set_irradiance(f->rt, ones, &err), SAM_OK);
    assert_int_equal(sam_runtime_translucency(f->rt, 0, 0.0f, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_translucency(f->rt, rest, &err), SAM_OK);
    pose(f, &bend, 1, 0.0f);
    assert_int_equal(sam_runtime_translucency(f->rt, 0, 0.0f, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_translucency(f->rt, posed, &err), SAM_OK);
    double t_change = max_relative_change(rest, posed, 3 * nv);
    /* L_d: the light's cosine at the new normals and positions. */
    sam_light light = {.type = SAM_LIGHT_DIRECTIONAL, .color = {1, 1, 1}, .intensity = 1, .direction = {0, 0, -1}};
    assert_int_equal(sam_runtime_set_lights(f->rt, &light, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_irradiance(f->rt, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_irradiance(f->rt, posed, &err), SAM_OK);
    pose(f, NULL, 0, 0.0f);
    assert_int_equal(sam_runtime_irradiance(f->rt, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_irradiance(f->rt, rest, &err), SAM_OK);
    double l_change = max_relative_change(rest, posed, 3 * nv);
    printf("a %.0f degree bend changes T by up to %.3f and L_d by up to %.3f of their peaks\n", bend.angle_deg,
           t_change, l_change);
    assert_true(t_change > 1e-3);
    assert_true(l_change > 1e-2);
    assert_int_equal(sam_runtime_set_lights(f->rt, NULL, 0, &err), SAM_OK);
    free(rest);
    free(posed);
    free(ones);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pose_matches_cpu),
        cmocka_unit_test(test_seam_copies_stay_identical),
        cmocka_unit_test(test_rest_pose_is_bit_identical),
        cmocka_unit_test(test_later_passes_follow_the_pose),
        cmocka_unit_test(test_bounds_follow_the_pose),
        cmocka_unit_test(test_curvature_follows_the_pose),
    };
    return cmocka_run_group_tests(tests, fixture_setup, fixture_teardown);
}
