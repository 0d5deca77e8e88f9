/* The translucency pass (sam_runtime_translucency.h). */
#include <math.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_nodes.h"
#include "sam_runtime_translucency.h"

sam_status sam_runtime_translucency_create(sam_runtime *rt, sam_error *err)
{
    sam_rt_translucency *t = &rt->translucency;
    sam_status st;
    if ((st = sam_gl_compute_program("translucency.comp", NULL, &t->rest_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("translucency.comp", "#define SAM_POSED 1\n", &t->posed_program, err)) !=
            SAM_OK ||
        (st = sam_gl_compute_program("translucency.comp", "#define SAM_POSED 1\n#define SAM_POSED_EQ15 1\n",
                                     &t->eq15_program, err)) != SAM_OK)
        return st;
    sam_runtime_set_profile_uniforms(t->rest_program, &rt->profile);
    sam_runtime_set_profile_uniforms(t->posed_program, &rt->profile);
    sam_runtime_set_profile_uniforms(t->eq15_program, &rt->profile);
    return SAM_OK;
}

void sam_runtime_translucency_destroy(sam_runtime *rt)
{
    sam_runtime_delete_program(&rt->translucency.rest_program);
    sam_runtime_delete_program(&rt->translucency.posed_program);
    sam_runtime_delete_program(&rt->translucency.eq15_program);
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

sam_status sam_runtime_translucency(sam_runtime *rt, uint32_t samples, float dt, int reset, sam_error *err)
{
    if (!(dt >= 0) || !isfinite(dt))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: frame time must be finite and >= 0, got %g", dt);
    sam_runtime_nodes_update(rt);
    int carried = rt->deform.posed && rt->translucency.posed_k == SAM_POSED_K_CARRIED;
    GLuint p = !rt->deform.posed ? rt->translucency.rest_program : carried ? rt->translucency.posed_program
                                                               : rt->translucency.eq15_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_stride"), rt->stride);
    glUniform1ui(glGetUniformLocation(p, "u_samples"), samples && samples < rt->stride ? samples : rt->stride);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1f(glGetUniformLocation(p, "u_alpha"), reset ? 1.0f : sam_runtime_smoothing_alpha(dt));
    sam_runtime_bind_buffers(rt);
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
