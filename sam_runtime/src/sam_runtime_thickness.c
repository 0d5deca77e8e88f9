/* The local-thickness technique (sam_runtime_thickness.h): Barre-Brisebois
 * and Bouchard's GDC 2011 translucency with the material's own slab
 * transmission in place of the talk's hand-set power and scale. */
#include <math.h>
#include <stdlib.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_surface.h"
#include "sam_runtime_thickness.h"

sam_status sam_runtime_thickness_create(sam_runtime *rt, sam_error *err)
{
    glGenBuffers(1, &rt->thickness.transmission);
    glGenBuffers(1, &rt->thickness.result);
    return sam_gl_compute_program("thickness.comp", NULL, &rt->thickness.program, err);
}

void sam_runtime_thickness_destroy(sam_runtime *rt)
{
    sam_runtime_delete_program(&rt->thickness.program);
    glDeleteBuffers(1, &rt->thickness.transmission);
    glDeleteBuffers(1, &rt->thickness.result);
    rt->thickness.transmission = rt->thickness.result = 0;
    rt->thickness.ready = 0;
}

sam_status sam_runtime_set_thickness(sam_runtime *rt, const float *mm, uint32_t count, sam_error *err)
{
    if (!mm && !count) {
        rt->thickness.ready = 0;
        return SAM_OK;
    }
    if (!mm || count != rt->vertex_count)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %u thickness values%s for %u vertices", count,
                        mm ? "" : " (and no array)", rt->vertex_count);
    for (uint32_t v = 0; v < count; ++v)
        if (!(mm[v] >= 0) || !isfinite(mm[v]))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "runtime: vertex %u's thickness %g mm is not a finite value >= 0", v, (double)mm[v]);
    /* G(t) is fixed per vertex: computed once here, exactly, rather than
     * looked up from a table every frame. w keeps the thickness. */
    float *g = malloc((size_t)count * 4 * sizeof *g);
    if (!g)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %u thickness values", count);
    for (uint32_t v = 0; v < count; ++v) {
        sam_profile_slab_transmission(&rt->profile, mm[v], g + 4 * (size_t)v);
        g[4 * (size_t)v + 3] = mm[v];
    }
    rt->thickness.ready = 0;
    while (glGetError() != GL_NO_ERROR) {
    }
    GLsizeiptr bytes = (GLsizeiptr)count * 4 * (GLsizeiptr)sizeof(float);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->thickness.transmission);
    glBufferData(GL_SHADER_STORAGE_BUFFER, bytes, g, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->thickness.result);
    glBufferData(GL_SHADER_STORAGE_BUFFER, bytes, NULL, GL_DYNAMIC_DRAW);
    free(g);
    if (glGetError() != GL_NO_ERROR)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not store %u thickness values", count);
    rt->thickness.ready = 1;
    return SAM_OK;
}

sam_status sam_runtime_set_thickness_distortion(sam_runtime *rt, float distortion, sam_error *err)
{
    if (!(distortion >= 0 && distortion <= 1))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: thickness distortion must be in [0, 1], got %g",
                        (double)distortion);
    rt->thickness.distortion = distortion;
    return SAM_OK;
}

sam_status sam_runtime_thickness_pass(sam_runtime *rt, sam_error *err)
{
    if (!rt->thickness.ready)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "render: the thickness technique needs each vertex's thickness "
                        "(sam_runtime_set_thickness), and none was given");
    GLuint p = rt->thickness.program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_light_count"), rt->lights.count);
    glUniform1f(glGetUniformLocation(p, "u_distortion"), rt->thickness.distortion);
    sam_runtime_set_surface_uniforms(rt, p);
    sam_runtime_bind_buffers(rt);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_TRANSMISSION, rt->thickness.transmission);
    sam_runtime_bind_thickness(rt);
    sam_runtime_dispatch_per_vertex(rt, SAM_PASS_TRANSLUCENCY);
    return SAM_OK;
}

void sam_runtime_bind_thickness(const sam_runtime *rt)
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_TRANSLUCENCY, rt->thickness.result);
}
