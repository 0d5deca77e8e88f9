/* Read-backs of the per-vertex buffers, for tests and tools (sam_runtime.h).
 * Each waits for the passes that wrote the buffer. */
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_gpu.h"

/* The xyz of buffer `buffer`'s vec4 per vertex. */
static sam_status read_buffer_vec4(const sam_runtime *rt, GLuint buffer, float *rgb, sam_error *err)
{
    float *v4 = malloc((size_t)rt->vertex_count * 4 * sizeof *v4);
    if (!v4)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)rt->vertex_count * 4 * sizeof(float), v4);
    for (uint32_t v = 0; v < rt->vertex_count; ++v)
        memcpy(rgb + 3 * (size_t)v, v4 + 4 * (size_t)v, 3 * sizeof(float));
    free(v4);
    return SAM_OK;
}

static sam_status read_vec4(sam_runtime *rt, int binding, float *rgb, sam_error *err)
{
    return read_buffer_vec4(rt, rt->buffer[binding], rgb, err);
}

sam_status sam_runtime_read_positions(sam_runtime *rt, float *xyz, sam_error *err)
{
    sam_status st = read_vec4(rt, SAM_B_POSITIONS, xyz, err);
    for (size_t v = 0; st == SAM_OK && v < rt->vertex_count; ++v)
        sam_runtime_from_frame(rt, xyz + 3 * v, xyz + 3 * v);
    return st;
}

sam_status sam_runtime_read_normals(sam_runtime *rt, float *xyz, sam_error *err)
{
    return read_vec4(rt, SAM_B_NORMALS, xyz, err);
}

/* One float per vertex from `binding`. */
static sam_status read_floats(sam_runtime *rt, int binding, float *out)
{
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[binding]);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)rt->vertex_count * sizeof(float), out);
    return SAM_OK;
}

sam_status sam_runtime_read_fan_areas(sam_runtime *rt, float *mm2, sam_error *err)
{
    (void)err;
    return read_floats(rt, SAM_B_FAN_AREAS, mm2);
}

sam_status sam_runtime_read_curvature(sam_runtime *rt, float *per_mm, sam_error *err)
{
    (void)err;
    return read_floats(rt, SAM_B_CURVATURE, per_mm);
}

sam_status sam_runtime_read_irradiance(sam_runtime *rt, float *rgb, sam_error *err)
{
    return read_vec4(rt, SAM_B_IRRADIANCE, rgb, err);
}

sam_status sam_runtime_read_translucency(sam_runtime *rt, float *rgb, sam_error *err)
{
    return read_vec4(rt, SAM_B_TRANSLUCENCY, rgb, err);
}

sam_status sam_runtime_read_thickness_translucency(sam_runtime *rt, float *rgb, sam_error *err)
{
    if (!rt->thickness.ready)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: no thickness was given, so there is no such T");
    return read_buffer_vec4(rt, rt->thickness.result, rgb, err);
}

sam_status sam_runtime_read_samples(sam_runtime *rt, uint32_t *index, float *kprime, sam_error *err)
{
    const size_t count = (size_t)rt->vertex_count * rt->stride;
    uint32_t *raw = malloc(count * 3 * sizeof *raw);
    if (!raw)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu samples", count);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[SAM_B_SAMPLES]);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(count * 3 * sizeof *raw), raw);
    /* The GPU's slot-major order (shaders/sample.glsl) back to the .sam's rows. */
    const size_t nv = rt->vertex_count, n = rt->stride;
    for (size_t v = 0; v < nv; ++v)
        for (size_t k = 0; k < n; ++k) {
            const size_t to = v * n + k, from = k * nv + v;
            index[to] = raw[3 * from];
            sam_runtime_unpack_k(raw + 3 * from + 1, kprime + 3 * to);
        }
    free(raw);
    return SAM_OK;
}
