/* The rest-K pass (sam_runtime_rest_k.h). */
#include "sam_runtime_gpu.h"
#include "sam_runtime_nodes.h"
#include "sam_runtime_rest_k.h"

sam_status sam_runtime_rest_k_create(sam_runtime *rt, sam_error *err)
{
    sam_status st = sam_gl_compute_program("rest_k.comp", NULL, &rt->rest_k.program, err);
    if (st != SAM_OK)
        return st;
    sam_runtime_set_profile_uniforms(rt->rest_k.program, &rt->profile);
    sam_error ignored;
    (void)sam_runtime_rest_k_fill(rt, &ignored); /* failed: no buffer, so the evaluated mode */
    return SAM_OK;
}

void sam_runtime_rest_k_destroy(sam_runtime *rt)
{
    sam_runtime_delete_program(&rt->rest_k.program);
    sam_runtime_rest_k_release(rt);
}

void sam_runtime_rest_k_release(sam_runtime *rt)
{
    if (rt->rest_k.buffer)
        glDeleteBuffers(1, &rt->rest_k.buffer);
    rt->rest_k.buffer = 0;
}

sam_status sam_runtime_rest_k_fill(sam_runtime *rt, sam_error *err)
{
    const size_t bytes = (size_t)rt->vertex_count * rt->stride * 3 * sizeof(uint32_t);
    sam_status st = sam_runtime_check_block_size("the rest K of the samples", bytes, err);
    if (st != SAM_OK)
        return st;
    if (!rt->rest_k.buffer) {
        glGenBuffers(1, &rt->rest_k.buffer);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->rest_k.buffer);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(bytes ? bytes : 16), NULL, GL_STATIC_DRAW);
        if (glGetError() != GL_NO_ERROR) {
            sam_runtime_rest_k_release(rt);
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not allocate the rest K (%zu bytes)",
                            bytes);
        }
    }
    sam_runtime_bind_buffers(rt);
    const sam_rt_deform *d = &rt->deform;
    if (d->rest_buffer[REST_POSITIONS]) {
        /* Deformed once: the rest pose lives in the copies it kept. */
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_POSITIONS, d->rest_buffer[REST_POSITIONS]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_SAMPLES, d->rest_buffer[REST_SAMPLES]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_FAN_AREAS, d->rest_buffer[REST_FAN_AREAS]);
        if (rt->nodes.rest_nodes)
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_NODES, rt->nodes.rest_nodes);
    } else {
        sam_runtime_nodes_update(rt); /* the nodes' rest centroids and areas */
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_REST_K, rt->rest_k.buffer);
    GLuint p = rt->rest_k.program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_stride"), rt->stride);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    sam_runtime_bind_buffers(rt);
    return SAM_OK;
}
