/*
 * The runtime inside an engine, on llvmpipe: the engine's own interleaved
 * vertex buffer (in the asset's order, with a vertex no triangle uses and
 * one duplicated) poses the runtime, and the translucency comes back in
 * the engine's order. At rest and under a bend the result equals the
 * runtime's own deform pass on the same pose; bad buffers get one clear
 * message.
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
#include "sam/sam_runtime.h"
#include "sam/sam_shape.h"
#include "sam_test.h"

#define MM_PER_UNIT 60.0f
/* The engine's vertex record: position, normal, UV (8 floats), after a
 * 16-byte header in the same buffer. */
#define RECORD 8
#define HEADER_FLOATS 4

typedef struct fixture {
    uint32_t engine_count;      /* the asset's vertices: the shape's, an unused one first, a duplicate last */
    float *engine_pos;          /* 3 * engine_count, rest */
    sam_mesh mesh;              /* built from the asset's arrays */
    samfile_data sam;
    sam_profile profile;
    sam_runtime *rt, *own;      /* posed by the engine's buffer; posed by the runtime's own deformers */
    GLuint buffer;              /* the engine's vertex buffer */
    float lo[3], hi[3], size;
} fixture;

static int fixture_setup(void **state)
{
    if (sam_test_gl_setup(state) != 0)
        return -1;
    static fixture f;
    sam_error err;
    sam_shape_params params;
    sam_shape_mesh s;
    if (sam_shape_default_params("ear", &params, &err) != SAM_OK || sam_shape_generate("ear", &params, &s, &err))
        return -1;
    /* Engine vertex 0 is used by nothing; the last repeats shape vertex 5
     * and replaces it in the first triangle that uses it. */
    f.engine_count = s.vertex_count + 2;
    f.engine_pos = malloc(3 * (size_t)f.engine_count * sizeof *f.engine_pos);
    uint32_t *tri = malloc(3 * (size_t)s.triangle_count * sizeof *tri);
    if (!f.engine_pos || !tri)
        return -1;
    float far[3] = {100, 100, 100};
    memcpy(f.engine_pos, far, sizeof far);
    memcpy(f.engine_pos + 3, s.positions, 3 * (size_t)s.vertex_count * sizeof(float));
    memcpy(f.engine_pos + 3 * (size_t)(f.engine_count - 1), s.positions + 15, 3 * sizeof(float));
    int replaced = 0;
    for (size_t i = 0; i < 3 * (size_t)s.triangle_count; ++i) {
        tri[i] = s.triangles[i] + 1;
        if (!replaced && s.triangles[i] == 5) {
            tri[i] = f.engine_count - 1;
            replaced = 1;
        }
    }
    sam_mesh_input in = {.name = "asset", .vertex_count = f.engine_count, .positions = f.engine_pos,
                         .triangle_count = s.triangle_count, .triangles = tri};
    sam_build_settings set;
    sam_build_default_settings(&set);
    if (sam_mesh_create(&in, &f.mesh, NULL, &err) != SAM_OK || sam_profile_preset("skin", &f.profile, &err) ||
        sam_build_samfile(&f.mesh, &f.profile, MM_PER_UNIT, &set, NULL, NULL, NULL, &f.sam, NULL, &err) ||
        sam_runtime_create(&f.sam, &f.profile, MM_PER_UNIT, &f.rt, &err) ||
        sam_runtime_create(&f.sam, &f.profile, MM_PER_UNIT, &f.own, &err)) {
        printf("setup: %s\n", err.message);
        return -1;
    }
    free(tri);
    sam_shape_mesh_destroy(&s);
    printf("%.1f%% of the map's samples are tree nodes\n",
           100.0 * sam_test_node_share(f.sam.sample_index, f.sam.vertex_count, f.sam.samples_per_vertex, f.sam.vertex_count));
    sam_light light = {.type = SAM_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 3, .position = {0.2f, 0.1f, -1}};
    if (sam_runtime_set_lights(f.rt, &light, 1, &err) || sam_runtime_set_lights(f.own, &light, 1, &err))
        return -1;
    sam_mesh_bounds(&f.mesh, f.lo, f.hi);
    f.size = (float)sam_mesh_diagonal(&f.mesh);
    glGenBuffers(1, &f.buffer);
    glBindBuffer(GL_ARRAY_BUFFER, f.buffer);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((HEADER_FLOATS + RECORD * (size_t)f.engine_count) * sizeof(float)),
                 NULL, GL_DYNAMIC_DRAW);
    *state = &f;
    return 0;
}

static int fixture_teardown(void **state)
{
    fixture *f = *state;
    glDeleteBuffers(1, &f->buffer);
    sam_runtime_destroy(f->rt);
    sam_runtime_destroy(f->own);
    samfile_free(&f->sam);
    sam_mesh_destroy(&f->mesh);
    free(f->engine_pos);
    return sam_test_gl_teardown(state);
}

/* Writes positions (3 * engine_count) into the engine's buffer, normals
 * all `normal` (unnormalised on purpose). */
static void upload(const fixture *f, const float *pos, const float normal[3])
{
    const size_t n = (size_t)f->engine_count;
    float *data = calloc(HEADER_FLOATS + RECORD * n, sizeof *data);
    assert_non_null(data);
    for (size_t e = 0; e < n; ++e) {
        memcpy(data + HEADER_FLOATS + RECORD * e, pos + 3 * e, 3 * sizeof(float));
        memcpy(data + HEADER_FLOATS + RECORD * e + 3, normal, 3 * sizeof(float));
    }
    glBindBuffer(GL_ARRAY_BUFFER, f->buffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)((HEADER_FLOATS + RECORD * n) * sizeof(float)), data);
    free(data);
}

static sam_engine_pose engine_pose(const fixture *f, int normals)
{
    sam_engine_pose p = {.positions = f->buffer,
                         .position_offset = HEADER_FLOATS * 4,
                         .position_stride = RECORD * 4,
                         .normals = normals ? f->buffer : 0,
                         .normal_offset = (HEADER_FLOATS + 3) * 4,
                         .normal_stride = RECORD * 4,
                         .vertex_count = f->engine_count};
    return p;
}

/* T of every SAM vertex after walk, irradiance and translucency. */
static void frame(sam_runtime *rt, float *t)
{
    sam_error err;
    if (sam_runtime_walk(rt, &err) || sam_runtime_irradiance(rt, &err) ||
        sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 1, &err) || sam_runtime_read_translucency(rt, t, &err))
        fail_msg("%s", err.message);
}

/* The engine-order buffer: T of the vertex each engine vertex became. */
static void check_engine_order(const fixture *f, const float *t)
{
    GLuint buffer;
    sam_error err;
    assert_int_equal(sam_runtime_engine_translucency(f->rt, &buffer, &err), SAM_OK);
    assert_true(buffer != 0);
    float *got = malloc(4 * (size_t)f->engine_count * sizeof *got);
    assert_non_null(got);
    glBindBuffer(GL_COPY_READ_BUFFER, buffer);
    glGetBufferSubData(GL_COPY_READ_BUFFER, 0, (GLsizeiptr)(4 * (size_t)f->engine_count * sizeof(float)), got);
    uint32_t lit = 0;
    for (uint32_t e = 0; e < f->engine_count; ++e) {
        const uint32_t v = f->sam.source_vertex[e];
        for (int c = 0; c < 3; ++c) {
            const float want = v == SAMFILE_NO_SAMPLE ? 0.0f : t[3 * (size_t)v + c];
            assert_float_equal(got[4 * e + c], want, 0.0f);
        }
        lit += got[4 * e] > 0;
    }
    assert_true(lit > f->engine_count / 4);
    free(got);
}

static void test_orders_differ(void **state)
{
    fixture *f = *state;
    assert_int_equal(sam_runtime_engine_vertex_count(f->rt), f->engine_count);
    assert_int_equal(f->sam.source_vertex_count, f->engine_count);
    assert_int_equal(f->sam.source_vertex[0], SAMFILE_NO_SAMPLE);
    assert_int_equal(f->sam.source_vertex[f->engine_count - 1], f->sam.source_vertex[6]);
    const uint32_t merged = f->sam.vertex_source[f->sam.source_vertex[6]];
    assert_true(merged == 6 || merged == f->engine_count - 1);
    assert_true(f->sam.vertex_count < f->engine_count);
}

/* The engine's pose (bend at time t, or rest) against the runtime's own
 * deform pass on the same deformer: positions to float precision (the CPU
 * poses in double, the GPU in float), T within 1e-4 of its largest value. */
static void compare_at(fixture *f, float time_s)
{
    const sam_deformer bend = {.type = SAM_DEFORM_BEND, .axis = {0, 1, 0}, .direction = {1, 0, 0},
                               .center = {0.5f * (f->lo[0] + f->hi[0]), 0.5f * (f->lo[1] + f->hi[1]),
                                          0.5f * (f->lo[2] + f->hi[2])},
                               .length = f->size, .angle_deg = 70.0f, .period_s = 2.0f};
    sam_deform_step steps[SAM_DEFORM_MAX];
    sam_deform_prepare(&bend, 1, time_s, steps);
    float *posed = malloc(3 * (size_t)f->engine_count * sizeof *posed);
    const uint32_t nv = f->sam.vertex_count;
    float *pos = malloc(3 * (size_t)nv * sizeof *pos), *own_pos = malloc(3 * (size_t)nv * sizeof *own_pos);
    float *t = malloc(3 * (size_t)nv * sizeof *t), *own_t = malloc(3 * (size_t)nv * sizeof *own_t);
    assert_true(posed && pos && own_pos && t && own_t);
    sam_deform_positions(steps, 1, f->engine_pos, posed, f->engine_count);
    const float up[3] = {0, 0, 1};
    upload(f, posed, up);
    sam_error err;
    sam_engine_pose p = engine_pose(f, 0);
    if (sam_runtime_set_engine_pose(f->rt, &p, &err) || sam_runtime_pose_from_engine(f->rt, &err) ||
        sam_runtime_set_deformers(f->own, &bend, 1, &err) || sam_runtime_deform(f->own, time_s, &err))
        fail_msg("%s", err.message);
    assert_int_equal(sam_runtime_read_positions(f->rt, pos, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_positions(f->own, own_pos, &err), SAM_OK);
    for (size_t i = 0; i < 3 * (size_t)nv; ++i)
        assert_float_equal(pos[i], own_pos[i], 1e-5f * f->size);
    frame(f->rt, t);
    frame(f->own, own_t);
    float top = 0, worst = 0;
    for (size_t i = 0; i < 3 * (size_t)nv; ++i) {
        top = fmaxf(top, own_t[i]);
        worst = fmaxf(worst, fabsf(t[i] - own_t[i]));
    }
    printf("time %.2f s: largest T %.4g, largest difference to the runtime's own pose %.3g\n", time_s, top, worst);
    assert_true(top > 0);
    assert_true(worst <= 1e-4f * top);
    check_engine_order(f, t);
    free(posed);
    free(pos);
    free(own_pos);
    free(t);
    free(own_t);
}

static void test_engine_pose_matches_own_deform(void **state)
{
    fixture *f = *state;
    compare_at(f, 0.0f);
    compare_at(f, 0.5f);
    compare_at(f, 1.3f);
}

/* Normals from the engine replace the computed ones, made unit. */
static void test_engine_normals(void **state)
{
    fixture *f = *state;
    const float slanted[3] = {0, 3, 4};
    upload(f, f->engine_pos, slanted);
    sam_error err;
    sam_engine_pose p = engine_pose(f, 1);
    if (sam_runtime_set_engine_pose(f->rt, &p, &err) || sam_runtime_pose_from_engine(f->rt, &err))
        fail_msg("%s", err.message);
    float *n = malloc(3 * (size_t)f->sam.vertex_count * sizeof *n);
    assert_non_null(n);
    assert_int_equal(sam_runtime_read_normals(f->rt, n, &err), SAM_OK);
    for (uint32_t v = 0; v < f->sam.vertex_count; ++v) {
        assert_float_equal(n[3 * v], 0.0f, 1e-6f);
        assert_float_equal(n[3 * v + 1], 0.6f, 1e-6f);
        assert_float_equal(n[3 * v + 2], 0.8f, 1e-6f);
    }
    free(n);
}

static void expect_error(fixture *f, sam_engine_pose p, const char *needle)
{
    sam_error err;
    sam_status st = sam_runtime_set_engine_pose(f->rt, &p, &err);
    if (st != SAM_ERR_INVALID_ARGUMENT || !strstr(err.message, needle))
        fail_msg("expected \"%s\", got %s: \"%s\"", needle, sam_status_name(st), err.message);
}

static void test_bad_engine_buffers(void **state)
{
    fixture *f = *state;
    char want[160];
    sam_engine_pose p = engine_pose(f, 1);
    p.vertex_count = f->sam.vertex_count;
    snprintf(want, sizeof want, "engine pose: %u vertices, but the .sam was built from %u", f->sam.vertex_count,
             f->engine_count);
    expect_error(f, p, want);
    p = engine_pose(f, 0);
    p.position_stride = 8;
    expect_error(f, p, "positions offset 16 and stride 8 must be multiples of 4 bytes, the stride at least 12");
    p = engine_pose(f, 1);
    p.normal_offset = 30;
    expect_error(f, p, "normals offset 30 and stride 32");
    p = engine_pose(f, 0);
    p.position_stride = 64;
    snprintf(want, sizeof want, "the positions buffer holds %u bytes; %u vertices at offset 16 and stride 64",
             (unsigned)((HEADER_FLOATS + RECORD * (size_t)f->engine_count) * sizeof(float)), f->engine_count);
    expect_error(f, p, want);
    p = engine_pose(f, 0);
    p.positions = 987654;
    expect_error(f, p, "positions buffer 987654 is not a GL buffer object");
    p.positions = 0;
    expect_error(f, p, "no positions buffer");
    sam_error err;
    assert_int_equal(sam_runtime_set_engine_pose(f->rt, NULL, &err), SAM_OK);
    assert_int_equal(sam_runtime_pose_from_engine(f->rt, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "call sam_runtime_set_engine_pose first"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_orders_differ),
        cmocka_unit_test(test_engine_pose_matches_own_deform),
        cmocka_unit_test(test_engine_normals),
        cmocka_unit_test(test_bad_engine_buffers),
    };
    return cmocka_run_group_tests(tests, fixture_setup, fixture_teardown);
}
