/* The translucency pass (sam_runtime_translucency.h). */
#include <math.h>
#include <stdio.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_nodes.h"
#include "sam_runtime_rest_k.h"
#include "sam_runtime_translucency.h"

/* The program of `mode` for `kind` (TRANSLUCENCY_*), compiled on first use. */
static sam_status program(sam_runtime *rt, sam_rest_k mode, int kind, GLuint *out, sam_error *err)
{
    static const char *const pose[TRANSLUCENCY_PROGRAMS] = {"", "#define SAM_POSED 1\n",
                                                            "#define SAM_POSED 1\n#define SAM_POSED_EQ15 1\n"};
    GLuint *p = &rt->translucency.program[mode][kind];
    if (!*p) {
        char defines[128];
        snprintf(defines, sizeof defines, "%s%s", mode == SAM_REST_K_CACHED ? "#define SAM_REST_K 1\n" : "",
                 pose[kind]);
        sam_status st = sam_gl_compute_program("translucency.comp", defines, p, err);
        if (st != SAM_OK)
            return st;
        sam_runtime_set_profile_uniforms(*p, &rt->profile);
    }
    *out = *p;
    return SAM_OK;
}

sam_status sam_runtime_translucency_create(sam_runtime *rt, sam_error *err)
{
    GLuint p;
    sam_status st = SAM_OK;
    for (int kind = 0; kind < TRANSLUCENCY_PROGRAMS && st == SAM_OK; ++kind)
        st = program(rt, sam_runtime_rest_k_mode(rt), kind, &p, err);
    return st;
}

void sam_runtime_translucency_destroy(sam_runtime *rt)
{
    for (int mode = 0; mode < 2; ++mode)
        for (int kind = 0; kind < TRANSLUCENCY_PROGRAMS; ++kind)
            sam_runtime_delete_program(&rt->translucency.program[mode][kind]);
}

float sam_runtime_smoothing_alpha(float dt)
{
    /* eq. 18: alpha = 1 - (1e-10)^dt = 1 - exp(dt ln 1e-10) */
    return (float)-expm1((double)dt * log(1e-10));
}

sam_status sam_runtime_set_posed_k(sam_runtime *rt, sam_posed_k mode, sam_error *err)
{
    if (mode != SAM_POSED_K_CARRIED && mode != SAM_POSED_K_EQ15)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: unknown posed-K mode %d (expected 0 or 1)",
                        (int)mode);
    rt->translucency.posed_k = mode;
    return SAM_OK;
}

sam_status sam_runtime_set_rest_k(sam_runtime *rt, sam_rest_k mode, sam_error *err)
{
    if (mode != SAM_REST_K_CACHED && mode != SAM_REST_K_EVALUATED)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: unknown rest-K mode %d (expected 0 or 1)", (int)mode);
    if (mode == sam_runtime_rest_k_mode(rt))
        return SAM_OK;
    GLuint p;
    sam_status st = SAM_OK;
    for (int kind = 0; kind < TRANSLUCENCY_PROGRAMS && st == SAM_OK; ++kind)
        st = program(rt, mode, kind, &p, err);
    if (st == SAM_OK && mode == SAM_REST_K_CACHED)
        st = sam_runtime_rest_k_fill(rt, err);
    if (st != SAM_OK)
        return st;
    if (mode == SAM_REST_K_EVALUATED)
        sam_runtime_rest_k_release(rt);
    return SAM_OK;
}

sam_rest_k sam_runtime_rest_k_mode(const sam_runtime *rt)
{
    return rt->rest_k.buffer ? SAM_REST_K_CACHED : SAM_REST_K_EVALUATED;
}

sam_status sam_runtime_translucency(sam_runtime *rt, uint32_t samples, float dt, int reset, sam_error *err)
{
    if (!(dt >= 0) || !isfinite(dt))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: frame time must be finite and >= 0, got %g", dt);
    sam_runtime_nodes_update(rt);
    const int kind = !rt->deform.posed                                 ? TRANSLUCENCY_REST
                     : rt->translucency.posed_k == SAM_POSED_K_CARRIED ? TRANSLUCENCY_CARRIED
                                                                       : TRANSLUCENCY_EQ15;
    GLuint p = rt->translucency.program[sam_runtime_rest_k_mode(rt)][kind]; /* compiled with its mode */
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_samples"), samples && samples < rt->stride ? samples : rt->stride);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1f(glGetUniformLocation(p, "u_alpha"), reset ? 1.0f : sam_runtime_smoothing_alpha(dt));
    sam_runtime_bind_buffers(rt);
    if (rt->rest_k.buffer)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_REST_K, rt->rest_k.buffer);
    /* A posed K is carried from the rest pose (shaders/fan_form_factor.glsl;
     * a node's from its rest centroid). */
    if (rt->deform.posed) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_REST_POSITIONS, rt->deform.rest_buffer[REST_POSITIONS]);
        /* A flat map has no nodes to read; its zeroed one keeps the block bound. */
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_REST_NODES,
                         rt->nodes.rest_nodes ? rt->nodes.rest_nodes : rt->buffer[SAM_B_NODES]);
    }
    sam_runtime_dispatch_per_vertex(rt, SAM_PASS_TRANSLUCENCY);
    return SAM_OK;
}
