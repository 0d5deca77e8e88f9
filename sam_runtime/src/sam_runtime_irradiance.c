/* The irradiance pass (sam_runtime_irradiance.h): each light's irradiance
 * through its shadow map times rho_dt, plus the environment's. */
#include <stdlib.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_irradiance.h"
#include "sam_runtime_shadows.h"
#include "sam_runtime_surface.h"

sam_status sam_runtime_irradiance_create(sam_runtime *rt, sam_error *err)
{
    return sam_gl_compute_program("irradiance.comp", NULL, &rt->irradiance.program, err);
}

void sam_runtime_irradiance_destroy(sam_runtime *rt)
{
    sam_runtime_delete_program(&rt->irradiance.program);
}

sam_status sam_runtime_irradiance(sam_runtime *rt, sam_error *err)
{
    (void)err;
    sam_runtime_render_shadows(rt);
    GLuint p = rt->irradiance.program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_light_count"), rt->lights.count);
    sam_runtime_set_surface_uniforms(rt, p);
    sam_runtime_bind_shadows(rt, p);
    sam_runtime_bind_buffers(rt);
    sam_runtime_dispatch_per_vertex(rt, SAM_PASS_IRRADIANCE);
    return SAM_OK;
}

sam_status sam_runtime_set_irradiance(sam_runtime *rt, const float *rgb, sam_error *err)
{
    float *v4 = sam_runtime_widen(rgb, rt->vertex_count, 0.0f);
    if (!v4)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[SAM_B_IRRADIANCE]);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)rt->vertex_count * 4 * sizeof(float), v4);
    free(v4);
    return SAM_OK;
}
