/*
 * Keyframed poses on llvmpipe: the deform pass's positions against the CPU
 * lerp between the keys around a time (the rest pose as the key at 0), the
 * keys themselves at their times, the hold after the last key, deformers on
 * top, the rest pose restored bit for bit, and keyframe meshes of another
 * topology refused with the file named.
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
#include "sam/sam_deform.h"
#include "sam/sam_mesh.h"
#include "sam/sam_runtime_scene.h"
#include "sam/sam_shape.h"
#include "sam_test.h"

#define MM_PER_UNIT 30.0f
#define RESOLUTION 6

/* A small cube-sphere written as rest.obj, its .sam and a runtime, and two
 * poses of it (the same shape at other sizes: the same topology). */
typedef struct fixture {
    sam_mesh rest, key[2];
    samfile_data sam;
    sam_runtime *rt;
    float size; /* the rest mesh's diagonal, model units */
    float *pos, *fan;
    char path[4][512]; /* rest.obj, pose1.obj, pose2.obj, other.obj (another resolution) */
} fixture;

static void write_sphere(const char *path, int resolution, double size)
{
    sam_shape_params p;
    sam_shape_mesh s;
    sam_error err;
    if (sam_shape_default_params("sphere", &p, &err) != SAM_OK)
        fail_msg("%s", err.message);
    p.resolution = resolution;
    p.size = size;
    if (sam_shape_generate("sphere", &p, &s, &err) != SAM_OK || sam_shape_write_obj(path, &s, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_shape_mesh_destroy(&s);
}

static int fixture_setup(void **state)
{
    if (sam_test_gl_setup(state) != 0)
        return -1;
    static fixture f;
    const char *names[4] = {"kf_rest.obj", "kf_pose1.obj", "kf_pose2.obj", "kf_other.obj"};
    const double sizes[4] = {1.0, 1.3, 0.8, 1.0};
    for (int i = 0; i < 4; ++i) {
        sam_test_tmp_path(f.path[i], sizeof f.path[i], names[i]);
        write_sphere(f.path[i], i == 3 ? 2 * RESOLUTION : RESOLUTION, sizes[i]);
    }
    sam_error err;
    sam_profile profile;
    sam_build_settings set;
    sam_build_default_settings(&set);
    set.samples_per_vertex = 4;
    if (sam_mesh_load(f.path[0], &f.rest, NULL, &err) != SAM_OK ||
        sam_mesh_load(f.path[1], &f.key[0], NULL, &err) != SAM_OK ||
        sam_mesh_load(f.path[2], &f.key[1], NULL, &err) != SAM_OK ||
        sam_profile_preset("skin", &profile, &err) != SAM_OK ||
        sam_build_samfile(&f.rest, &profile, MM_PER_UNIT, &set, NULL, NULL, NULL, &f.sam, NULL, &err) != SAM_OK ||
        sam_runtime_create(&f.sam, &profile, MM_PER_UNIT, &f.rt, &err) != SAM_OK) {
        printf("setup: %s\n", err.message);
        return -1;
    }
    f.size = (float)sam_mesh_diagonal(&f.rest);
    f.pos = malloc(f.sam.vertex_count * 3 * sizeof *f.pos);
    f.fan = malloc(f.sam.vertex_count * sizeof *f.fan);
    *state = &f;
    return f.pos && f.fan ? 0 : -1;
}

static int fixture_teardown(void **state)
{
    fixture *f = *state;
    sam_runtime_destroy(f->rt);
    samfile_free(&f->sam);
    sam_mesh_destroy(&f->rest);
    sam_mesh_destroy(&f->key[0]);
    sam_mesh_destroy(&f->key[1]);
    free(f->pos);
    free(f->fan);
    return sam_test_gl_teardown(state);
}

static const float key_times[2] = {0.5f, 1.5f};

static void set_keys(fixture *f)
{
    sam_error err;
    const float *positions[2] = {f->key[0].positions, f->key[1].positions};
    if (sam_runtime_set_keyframes(f->rt, positions, key_times, 2, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

static void pose_at(fixture *f, float t)
{
    sam_error err;
    if (sam_runtime_deform(f->rt, t, &err) != SAM_OK || sam_runtime_read_positions(f->rt, f->pos, &err) != SAM_OK ||
        sam_runtime_read_fan_areas(f->rt, f->fan, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

/* The CPU reference: a + (b - a) w between the keys around t, in float. */
static void cpu_lerp(const fixture *f, float t, float *out)
{
    const float *keys[3] = {f->sam.positions, f->key[0].positions, f->key[1].positions};
    const float times[3] = {0.0f, key_times[0], key_times[1]};
    int i = t < times[1] ? 0 : 1;
    float w = (t - times[i]) / (times[i + 1] - times[i]);
    for (size_t k = 0; k < 3 * (size_t)f->sam.vertex_count; ++k)
        out[k] = keys[i][k] + (keys[i + 1][k] - keys[i][k]) * w;
}

static double max_difference(const float *a, const float *b, size_t n)
{
    double d = 0;
    for (size_t i = 0; i < n; ++i)
        d = fmax(d, fabs((double)a[i] - b[i]));
    return d;
}

static void test_between_keys_is_the_lerp(void **state)
{
    fixture *f = *state;
    const size_t n = 3 * (size_t)f->sam.vertex_count;
    float *ref = malloc(n * sizeof *ref);
    assert_non_null(ref);
    set_keys(f);
    const float times[] = {0.2f, 0.25f, 0.9f, 1.2f};
    for (size_t i = 0; i < sizeof times / sizeof times[0]; ++i) {
        pose_at(f, times[i]);
        cpu_lerp(f, times[i], ref);
        double e = max_difference(f->pos, ref, n) / f->size;
        printf("t = %.2f s: positions within %.2e of the size of the CPU lerp\n", times[i], e);
        assert_true(e < 1e-6);
        /* The lerp moved something, so the comparison has teeth. */
        assert_true(max_difference(f->pos, f->sam.positions, n) > 1e-3 * f->size);
    }
    free(ref);
}

static void test_at_a_key_is_the_key(void **state)
{
    fixture *f = *state;
    const uint32_t nv = f->sam.vertex_count;
    set_keys(f);
    for (int k = 0; k < 2; ++k) {
        pose_at(f, key_times[k]);
        assert_memory_equal(f->pos, f->key[k].positions, nv * 3 * sizeof(float));
        /* A uniform scale by s scales every fan area by s^2: the fan pass ran on the pose. */
        const float s = k == 0 ? 1.3f : 0.8f;
        for (uint32_t v = 0; v < nv; ++v)
            assert_true(fabsf(f->fan[v] - s * s * f->sam.fan_area[v]) <= 1e-4f * f->sam.fan_area[v]);
    }
    pose_at(f, 10.0f); /* after the last key the pose holds */
    assert_memory_equal(f->pos, f->key[1].positions, nv * 3 * sizeof(float));
    pose_at(f, 0.0f); /* the rest pose, restored bit for bit */
    assert_memory_equal(f->pos, f->sam.positions, nv * 3 * sizeof(float));
    assert_memory_equal(f->fan, f->sam.fan_area, nv * sizeof(float));
    pose_at(f, 0.7f);
    assert_memory_not_equal(f->pos, f->sam.positions, nv * 3 * sizeof(float));
    sam_error err;
    assert_int_equal(sam_runtime_set_keyframes(f->rt, NULL, NULL, 0, &err), SAM_OK);
    pose_at(f, 0.7f); /* keyframes removed: the rest pose again */
    assert_memory_equal(f->pos, f->sam.positions, nv * 3 * sizeof(float));
    const float *positions[2] = {f->key[0].positions, f->key[1].positions};
    const float backwards[2] = {1.0f, 0.5f};
    assert_int_equal(sam_runtime_set_keyframes(f->rt, positions, backwards, 2, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "keyframe 1 at time 0.5"));
}

static void test_deformers_apply_on_top(void **state)
{
    fixture *f = *state;
    const size_t n = 3 * (size_t)f->sam.vertex_count;
    float *lerp = malloc(n * sizeof *lerp), *ref = malloc(n * sizeof *ref);
    assert_non_null(lerp);
    assert_non_null(ref);
    set_keys(f);
    sam_deformer d = {.type = SAM_DEFORM_TWIST, .axis = {0, 1, 0}, .angle_deg = 60.0f, .length = f->size};
    sam_error err;
    if (sam_runtime_set_deformers(f->rt, &d, 1, &err) != SAM_OK)
        fail_msg("%s", err.message);
    const float t = 0.9f;
    pose_at(f, t);
    cpu_lerp(f, t, lerp);
    sam_deform_step step;
    assert_int_equal(sam_deform_prepare(&d, 1, t, &step), 1);
    sam_deform_positions(&step, 1, lerp, ref, f->sam.vertex_count);
    double e = max_difference(f->pos, ref, n) / f->size;
    printf("keyframes and a twist: within %.2e of the size of the CPU reference\n", e);
    assert_true(e < 1e-6);
    assert_true(max_difference(f->pos, lerp, n) > 1e-3 * f->size);
    assert_int_equal(sam_runtime_set_deformers(f->rt, NULL, 0, &err), SAM_OK);
    free(lerp);
    free(ref);
}

/* Runs sam_runtime_scene_keyframes on a scene with one keyframe, `path`. */
static sam_status load_keyframe(fixture *f, const char *path, sam_error *err)
{
    sam_scene scene;
    sam_scene_init(&scene);
    scene.keyframes = calloc(1, sizeof *scene.keyframes);
    assert_non_null(scene.keyframes);
    scene.keyframes[0].mesh = strdup(path);
    scene.keyframes[0].time_s = 1.0f;
    scene.keyframe_count = 1;
    sam_status st = sam_runtime_scene_keyframes(f->rt, &scene, &f->sam, err);
    sam_scene_destroy(&scene);
    return st;
}

/* The rest mesh's OBJ with its first two faces swapped: the same vertices,
 * the triangles in another order. */
static void write_swapped_faces(const char *from, const char *to)
{
    uint8_t *text;
    size_t size;
    sam_error err;
    if (sam_read_file(from, &text, &size, &err) != SAM_OK)
        fail_msg("%s", err.message);
    char *s = (char *)text, *a = strstr(s, "\nf "), *b = a ? strstr(a + 1, "\nf ") : NULL,
         *c = b ? strchr(b + 1, '\n') : NULL;
    assert_non_null(c);
    /* s = head a b tail, written as head b a tail (each line with its leading newline). */
    FILE *fp = fopen(to, "wb");
    assert_non_null(fp);
    fwrite(s, 1, (size_t)(a - s), fp);
    fwrite(b, 1, (size_t)(c - b), fp);
    fwrite(a, 1, (size_t)(b - a), fp);
    fwrite(c, 1, size - (size_t)(c - s), fp);
    fclose(fp);
    free(text);
}

static void test_other_topology_is_refused(void **state)
{
    fixture *f = *state;
    sam_error err;
    assert_int_equal(load_keyframe(f, f->path[1], &err), SAM_OK);
    pose_at(f, 1.0f);
    assert_memory_equal(f->pos, f->key[0].positions, f->sam.vertex_count * 3 * sizeof(float));

    assert_int_equal(load_keyframe(f, f->path[3], &err), SAM_ERR_FORMAT);
    printf("%s\n", err.message);
    assert_non_null(strstr(err.message, "kf_other.obj: "));
    assert_non_null(strstr(err.message, " vertices, the rest mesh has "));

    char swapped[512];
    sam_test_tmp_path(swapped, sizeof swapped, "kf_swapped.obj");
    write_swapped_faces(f->path[0], swapped);
    assert_int_equal(load_keyframe(f, swapped, &err), SAM_ERR_FORMAT);
    printf("%s\n", err.message);
    assert_non_null(strstr(err.message, "kf_swapped.obj: triangle "));
    assert_non_null(strstr(err.message, "the rest mesh's is ("));
    /* The refused file left the earlier keyframe in place. */
    pose_at(f, 1.0f);
    assert_memory_equal(f->pos, f->key[0].positions, f->sam.vertex_count * 3 * sizeof(float));
    assert_int_equal(sam_runtime_set_keyframes(f->rt, NULL, NULL, 0, &err), SAM_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_between_keys_is_the_lerp),
        cmocka_unit_test(test_at_a_key_is_the_key),
        cmocka_unit_test(test_deformers_apply_on_top),
        cmocka_unit_test(test_other_topology_is_refused),
    };
    return cmocka_run_group_tests(tests, fixture_setup, fixture_teardown);
}
