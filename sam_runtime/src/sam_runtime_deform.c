/* Deformation and the sample walk (sam_runtime_deform.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_deform.h"
#include "sam_runtime_gpu.h"
#include "sam_runtime_nodes.h"

sam_status sam_runtime_deform_create(sam_runtime *rt, sam_error *err)
{
    sam_status st;
    if ((st = sam_gl_compute_program("deform.comp", NULL, &rt->deform.program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("deform_normals.comp", NULL, &rt->deform.normals_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("walk.comp", NULL, &rt->deform.walk_program, err)) != SAM_OK)
        return st;
    sam_runtime_set_profile_uniforms(rt->deform.walk_program, &rt->profile);
    return SAM_OK;
}

void sam_runtime_deform_destroy(sam_runtime *rt)
{
    sam_rt_deform *d = &rt->deform;
    sam_runtime_delete_program(&d->program);
    sam_runtime_delete_program(&d->normals_program);
    sam_runtime_delete_program(&d->walk_program);
    if (d->rest_buffer[0])
        glDeleteBuffers(REST_COUNT, d->rest_buffer);
    if (d->bounds_buffer)
        glDeleteBuffers(1, &d->bounds_buffer);
    if (d->keyframe_buffer)
        glDeleteBuffers(1, &d->keyframe_buffer);
    free(d->keyframe_times);
    memset(d, 0, sizeof *d);
}

/* The bytes of the buffers the rest pose keeps, in REST_* order. */
static void rest_sizes(const sam_runtime *rt, GLsizeiptr bytes[REST_COUNT])
{
    bytes[REST_POSITIONS] = bytes[REST_NORMALS] = (GLsizeiptr)rt->vertex_count * 4 * sizeof(float);
    bytes[REST_FAN_AREAS] = bytes[REST_CURVATURE] = (GLsizeiptr)rt->vertex_count * sizeof(float);
    bytes[REST_SAMPLES] = (GLsizeiptr)rt->vertex_count * rt->stride * 3 * sizeof(uint32_t);
}

/* Where each rest buffer's live copy is bound, in REST_* order. */
static const int rest_binding[REST_COUNT] = {SAM_B_POSITIONS, SAM_B_NORMALS, SAM_B_FAN_AREAS, SAM_B_SAMPLES,
                                             SAM_B_CURVATURE};

sam_status sam_runtime_deform_keep_rest(sam_runtime *rt, sam_error *err)
{
    if (rt->deform.rest_buffer[0])
        return SAM_OK;
    sam_status st = sam_runtime_nodes_keep_rest(rt, err);
    if (st != SAM_OK)
        return st;
    GLsizeiptr bytes[REST_COUNT];
    rest_sizes(rt, bytes);
    glGenBuffers(REST_COUNT, rt->deform.rest_buffer);
    for (int i = 0; i < REST_COUNT; ++i) {
        glBindBuffer(GL_COPY_WRITE_BUFFER, rt->deform.rest_buffer[i]);
        glBufferData(GL_COPY_WRITE_BUFFER, bytes[i], NULL, GL_STATIC_DRAW);
        glBindBuffer(GL_COPY_READ_BUFFER, rt->buffer[rest_binding[i]]);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, bytes[i]);
    }
    if (glGetError() != GL_NO_ERROR) {
        glDeleteBuffers(REST_COUNT, rt->deform.rest_buffer);
        memset(rt->deform.rest_buffer, 0, sizeof rt->deform.rest_buffer);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not keep the rest pose of %u vertices",
                        rt->vertex_count);
    }
    return SAM_OK;
}

sam_status sam_runtime_set_deformers(sam_runtime *rt, const sam_deformer *deformers, size_t count,
                                     sam_error *err)
{
    if (count > SAM_DEFORM_MAX || (count && !deformers))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu deformers%s (at most %d)", count,
                        count && !deformers ? " but none given" : "", SAM_DEFORM_MAX);
    sam_status st;
    if (count && (st = sam_runtime_deform_keep_rest(rt, err)) != SAM_OK)
        return st;
    if (count)
        memcpy(rt->deform.deformers, deformers, count * sizeof *deformers);
    rt->deform.deformer_count = count;
    return SAM_OK;
}

sam_status sam_runtime_set_keyframes(sam_runtime *rt, const float *const *positions, const float *times,
                                     size_t count, sam_error *err)
{
    if (count && (!positions || !times))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu keyframes but no %s given", count,
                        positions ? "times" : "positions");
    for (size_t i = 0; i < count; ++i) {
        if (!positions[i])
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: keyframe %zu has no positions", i);
        if (!(isfinite(times[i]) && times[i] > 0.0f && (i == 0 || times[i] > times[i - 1])))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "runtime: keyframe %zu at time %g: times must be finite, > 0 and increasing (previous %g)",
                            i, times[i], i ? times[i - 1] : 0.0f);
    }
    const size_t nv = rt->vertex_count;
    float *times_copy = count ? malloc(count * sizeof *times_copy) : NULL;
    float *vec4s = count ? malloc(count * nv * 4 * sizeof *vec4s) : NULL;
    if (count && (!times_copy || !vec4s)) {
        free(times_copy);
        free(vec4s);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu keyframes of %zu vertices", count,
                        nv);
    }
    sam_status st;
    if (count && (st = sam_runtime_deform_keep_rest(rt, err)) != SAM_OK) {
        free(times_copy);
        free(vec4s);
        return st;
    }
    for (size_t i = 0; i < count; ++i) {
        for (size_t v = 0; v < nv; ++v) {
            sam_runtime_to_frame(rt, positions[i] + 3 * v, vec4s + (i * nv + v) * 4);
            vec4s[(i * nv + v) * 4 + 3] = 1.0f;
        }
    }
    if (count)
        memcpy(times_copy, times, count * sizeof *times_copy);
    if (rt->deform.keyframe_buffer)
        glDeleteBuffers(1, &rt->deform.keyframe_buffer);
    rt->deform.keyframe_buffer = 0;
    free(rt->deform.keyframe_times);
    rt->deform.keyframe_times = times_copy;
    rt->deform.keyframe_count = 0;
    if (count) {
        glGenBuffers(1, &rt->deform.keyframe_buffer);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->deform.keyframe_buffer);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(count * nv * 4 * sizeof *vec4s), vec4s, GL_STATIC_DRAW);
        free(vec4s);
        if (glGetError() != GL_NO_ERROR) {
            glDeleteBuffers(1, &rt->deform.keyframe_buffer);
            rt->deform.keyframe_buffer = 0;
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not keep %zu keyframes of %zu vertices",
                            count, nv);
        }
    }
    rt->deform.keyframe_count = count;
    return SAM_OK;
}

/* The keyframe pose at `time_s` as two keys and a weight: positions =
 * key a + (key b - key a) * w, key -1 being the rest pose at time 0.
 * Returns 0 when that is the rest pose itself. */
static int keyframe_pose(const sam_runtime *rt, float time_s, GLint *a, GLint *b, float *w)
{
    *a = *b = -1;
    *w = 0.0f;
    if (!rt->deform.keyframe_count || time_s <= 0.0f)
        return 0;
    const float *t = rt->deform.keyframe_times;
    size_t n = rt->deform.keyframe_count;
    if (time_s >= t[n - 1]) {
        *a = *b = (GLint)(n - 1); /* after the last key the pose holds */
        return 1;
    }
    size_t i = 0;
    while (time_s >= t[i])
        ++i; /* t[i - 1] <= time_s < t[i], t[-1] = 0 */
    float t0 = i ? t[i - 1] : 0.0f;
    *a = (GLint)i - 1;
    *b = (GLint)i;
    *w = (time_s - t0) / (t[i] - t0);
    return 1;
}

sam_status sam_runtime_deform(sam_runtime *rt, float time_s, sam_error *err)
{
    if (!isfinite(time_s))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: deform time must be finite, got %g", time_s);
    if (!rt->deform.rest_buffer[0])
        return SAM_OK; /* never deformed: the buffers hold the rest pose */
    sam_deform_step steps[SAM_DEFORM_MAX];
    GLint key_a, key_b;
    float key_w;
    int keyed = keyframe_pose(rt, time_s, &key_a, &key_b, &key_w);
    sam_runtime_begin_timer(rt, SAM_PASS_DEFORM);
    if (!sam_deform_prepare(rt->deform.deformers, rt->deform.deformer_count, time_s, steps) && !keyed) {
        /* A copy, not the passes, so the rest pose comes back bit for bit. */
        GLsizeiptr bytes[REST_COUNT];
        rest_sizes(rt, bytes);
        for (int i = 0; i < REST_COUNT; ++i) {
            glBindBuffer(GL_COPY_READ_BUFFER, rt->deform.rest_buffer[i]);
            glBindBuffer(GL_COPY_WRITE_BUFFER, rt->buffer[rest_binding[i]]);
            glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, bytes[i]);
        }
        rt->deform.posed = 0;
    } else {
        rt->deform.posed = 1;
        GLint type[SAM_DEFORM_MAX];
        float axis[SAM_DEFORM_MAX][3], direction[SAM_DEFORM_MAX][3], center[SAM_DEFORM_MAX][3],
            param[SAM_DEFORM_MAX][3];
        GLint used = 0;
        for (size_t i = 0; i < rt->deform.deformer_count; ++i) {
            if (steps[i].identity)
                continue;
            type[used] = (GLint)steps[i].type;
            memcpy(axis[used], steps[i].axis, sizeof axis[used]);
            memcpy(direction[used], steps[i].direction, sizeof direction[used]);
            sam_runtime_to_frame(rt, steps[i].center, center[used]);
            memcpy(param[used], steps[i].param, sizeof param[used]);
            used++;
        }
        GLuint p = rt->deform.program;
        glUseProgram(p);
        glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
        glUniform1i(glGetUniformLocation(p, "u_step_count"), used);
        glUniform1iv(glGetUniformLocation(p, "u_type"), used, type);
        glUniform3fv(glGetUniformLocation(p, "u_axis"), used, &axis[0][0]);
        glUniform3fv(glGetUniformLocation(p, "u_direction"), used, &direction[0][0]);
        glUniform3fv(glGetUniformLocation(p, "u_center"), used, &center[0][0]);
        glUniform3fv(glGetUniformLocation(p, "u_param"), used, &param[0][0]);
        glUniform1i(glGetUniformLocation(p, "u_key_a"), key_a);
        glUniform1i(glGetUniformLocation(p, "u_key_b"), key_b);
        glUniform1f(glGetUniformLocation(p, "u_key_w"), key_w);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_POSITIONS, rt->buffer[SAM_B_POSITIONS]);
        /* Without keyframes the shader never reads binding 1; the rest
         * positions stand in so that every declared block is bound. */
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_KEY_POSITIONS,
                         rt->deform.keyframe_buffer ? rt->deform.keyframe_buffer : rt->deform.rest_buffer[REST_POSITIONS]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_DEFORM_REST, rt->deform.rest_buffer[REST_POSITIONS]);
        glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
        sam_runtime_deform_finish(rt);
    }
    sam_runtime_end_timer(rt, SAM_PASS_DEFORM);
    if (rt->deform.posed) {
        sam_runtime_deform_read_box(rt);
    } else {
        /* Positions and normals are vertex attributes of the draws as well. */
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                        GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
        sam_runtime_set_box(rt, rt->rest_box_lo, rt->rest_box_hi);
    }
    return SAM_OK;
}

void sam_runtime_deform_finish(sam_runtime *rt)
{
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_NORMALS, rt->buffer[SAM_B_NORMALS]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_SAMPLES, rt->buffer[SAM_B_SAMPLES]);
    GLuint p = rt->deform.normals_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1f(glGetUniformLocation(p, "u_mm2_per_unit2"), rt->mm_per_unit * rt->mm_per_unit);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1i(glGetUniformLocation(p, "u_stage"), 0);
    sam_runtime_bind_buffers(rt);
    static const GLuint empty_box[6] = {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu, 0, 0, 0};
    if (!rt->deform.bounds_buffer) {
        glGenBuffers(1, &rt->deform.bounds_buffer);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->deform.bounds_buffer);
        glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof empty_box, NULL, GL_DYNAMIC_READ);
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->deform.bounds_buffer);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof empty_box, empty_box);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_BOUNDS, rt->deform.bounds_buffer);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    /* Boundary vertices take their curvature from interior neighbours. */
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUniform1i(glGetUniformLocation(p, "u_stage"), 1);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
}

void sam_runtime_deform_read_box(sam_runtime *rt)
{
    /* Positions and normals are vertex attributes of the draws as well. */
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
    /* The shadow maps' and the camera's ranges need the pose's bounds on the
     * CPU this frame: the one read-back of the update (24 bytes; it waits
     * for the deform passes). */
    GLuint key[6];
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->deform.bounds_buffer);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof key, key);
    float lo[3], hi[3];
    for (int c = 0; c < 3; ++c) {
        uint32_t a = key[c] & 0x80000000u ? key[c] & 0x7FFFFFFFu : ~key[c];
        uint32_t b = key[3 + c] & 0x80000000u ? key[3 + c] & 0x7FFFFFFFu : ~key[3 + c];
        memcpy(&lo[c], &a, sizeof a);
        memcpy(&hi[c], &b, sizeof b);
    }
    sam_runtime_set_box(rt, lo, hi);
}

sam_status sam_runtime_walk(sam_runtime *rt, sam_error *err)
{
    (void)err;
    if (!rt->deform.posed)
        return SAM_OK; /* the builder's samples are exact at rest; the walk's estimates could only move them */
    GLuint p = rt->deform.walk_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_stride"), rt->stride);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1ui(glGetUniformLocation(p, "u_cut_map"), rt->nodes.node_count > 0);
    sam_runtime_bind_buffers(rt);
    sam_runtime_dispatch_per_vertex(rt, SAM_PASS_WALK);
    return SAM_OK;
}
