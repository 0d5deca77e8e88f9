/* Screen-space diffusion and pre-integrated tables (sam_runtime_diffusion.h). */
#include <math.h>
#include <stdlib.h>

#include "sam/sam_preint.h"
#include "sam_runtime_diffusion.h"
#include "sam_runtime_gpu.h"

sam_status sam_runtime_diffusion_create(sam_runtime *rt, sam_error *err)
{
    sam_status st;
    if ((st = sam_gl_compute_program("sss_prefilter.comp", NULL, &rt->diffusion.prefilter_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("sss_mips.comp", NULL, &rt->diffusion.mips_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("sss_blur.comp", NULL, &rt->diffusion.blur_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("sss_compose.comp", NULL, &rt->diffusion.compose_program, err)) != SAM_OK)
        return st;
    return SAM_OK;
}

void sam_runtime_diffusion_destroy(sam_runtime *rt)
{
    sam_runtime_delete_program(&rt->diffusion.prefilter_program);
    sam_runtime_delete_program(&rt->diffusion.mips_program);
    sam_runtime_delete_program(&rt->diffusion.blur_program);
    sam_runtime_delete_program(&rt->diffusion.compose_program);
}

sam_status sam_runtime_ensure_preintegrated(sam_runtime *rt, sam_error *err)
{
    if (rt->diffusion.preint_ready)
        return SAM_OK;
    float *table = malloc(PRE_SIZE * PRE_SIZE * 3 * sizeof *table);
    if (!table)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    sam_status st = sam_preint_diffuse_table(&rt->profile, PRE_SIZE, PRE_SIZE, PRE_MAX_CURVATURE, table, err);
    if (st == SAM_OK)
        st = sam_runtime_upload(rt, SAM_B_PRE_DIFFUSE, table, PRE_SIZE * PRE_SIZE * 3 * sizeof *table, err);
    if (st == SAM_OK)
        st = sam_preint_penumbra_table(&rt->profile, PRE_SIZE, PRE_SIZE, PRE_MAX_PENUMBRA_MM, table, err);
    if (st == SAM_OK)
        st = sam_runtime_upload(rt, SAM_B_PRE_PENUMBRA, table, PRE_SIZE * PRE_SIZE * 3 * sizeof *table, err);
    free(table);
    rt->diffusion.min_penumbra_mm = fminf(sam_profile_radius(&rt->profile, 0.01f), PRE_MAX_PENUMBRA_MM);
    rt->diffusion.preint_ready = st == SAM_OK;
    return st;
}

sam_status sam_runtime_ensure_kernel(sam_runtime *rt, sam_sss_kernel kind, uint32_t taps, sam_error *err)
{
    if (rt->diffusion.kernel.taps == taps && rt->diffusion.kernel_kind == kind)
        return SAM_OK;
    sam_status st = kind == SAM_SSS_KERNEL_EQ1        ? sam_profile_separable_kernel(&rt->profile, taps, &rt->diffusion.kernel, err)
                    : kind == SAM_SSS_KERNEL_MARGINAL ? sam_profile_separable_kernel_direct(&rt->profile, taps,
                                                                                            &rt->diffusion.kernel, err)
                                                      : sam_profile_separable_kernel_fit2d(&rt->profile, taps,
                                                                                           &rt->diffusion.kernel, err);
    rt->diffusion.kernel_kind = kind;
    if (st != SAM_OK)
        rt->diffusion.kernel.taps = 0;
    return st;
}

/* The share of the kernel's axis each tap stands for (mm): half the way
 * to each neighbour, the whole way to the one neighbour of an end tap. */
static void tap_shares(const sam_separable_kernel *kernel, float *share)
{
    const uint32_t n = kernel->taps;
    for (uint32_t k = 0; k < n; ++k) {
        const float *o = kernel->offset_mm;
        share[k] = k == 0 ? o[1] - o[0] : k == n - 1 ? o[n - 1] - o[n - 2] : 0.5f * (o[k + 1] - o[k - 1]);
    }
}

/* Levels 1 and on of the blur's light and depth mips from level 0, one
 * dispatch for both per level (shaders/sss_mips.comp); the two textures
 * are bound to texture units 0 and 1 on return. */
static void build_mips(sam_runtime *rt, const sam_render_view *view, const GLuint mips[2])
{
    for (int m = 0; m < 2; ++m) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)m);
        glBindTexture(GL_TEXTURE_2D, mips[m]);
    }
    GLuint p = rt->diffusion.mips_program;
    glUseProgram(p);
    glUniform1i(glGetUniformLocation(p, "u_light_mips"), 0);
    glUniform1i(glGetUniformLocation(p, "u_depth_mips"), 1);
    GLint above = glGetUniformLocation(p, "u_above");
    uint32_t w = view->width, h = view->height;
    for (GLint level = 1; w > 1 || h > 1; ++level) {
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
        glUniform1f(above, (float)(level - 1));
        glBindImageTexture(SAM_IMAGE_TARGET, mips[0], level, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(SAM_IMAGE_DEPTH, mips[1], level, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glDispatchCompute((w + 7) / 8, (h + 7) / 8, 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    }
}

void sam_runtime_screen_space_diffusion(sam_runtime *rt, const sam_render_view *view, const GLuint tex[5],
                                        const GLuint mips[2])
{
    GLuint gx = (view->width + 7) / 8, gy = (view->height + 7) / 8;
    GLuint b = rt->diffusion.blur_program;
    glUseProgram(b);
    const sam_separable_kernel *kernel = &rt->diffusion.kernel;
    float share[SAM_KERNEL_MAX_TAPS];
    tap_shares(kernel, share);
    glUniform1i(glGetUniformLocation(b, "u_taps"), (GLint)kernel->taps);
    glUniform1fv(glGetUniformLocation(b, "u_offset_mm"), (GLsizei)kernel->taps, kernel->offset_mm);
    glUniform1fv(glGetUniformLocation(b, "u_share_mm"), (GLsizei)kernel->taps, share);
    glUniform3fv(glGetUniformLocation(b, "u_weight"), (GLsizei)kernel->taps, &kernel->weight[0][0]);
    glUniform1f(glGetUniformLocation(b, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1f(glGetUniformLocation(b, "u_pixels_per_unit_at_depth_one"),
                (float)view->height / (2.0f * tanf(0.5f * view->fov_deg * 3.14159265f / 180.0f)));
    glUniform1f(glGetUniformLocation(b, "u_depth_jump"), kernel->width_mm / rt->mm_per_unit);
    glUniform1i(glGetUniformLocation(b, "u_light_mips"), 0);
    glUniform1i(glGetUniformLocation(b, "u_depth_mips"), 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    for (int pass = 0; pass < 2; ++pass) {
        const GLuint source = pass == 0 ? tex[0] : tex[3];
        glUseProgram(rt->diffusion.prefilter_program);
        glBindImageTexture(SAM_IMAGE_SOURCE, source, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(SAM_IMAGE_TARGET, mips[0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(SAM_IMAGE_DEPTH, mips[1], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glDispatchCompute(gx, gy, 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
        build_mips(rt, view, mips);
        glUseProgram(b);
        glUniform2i(glGetUniformLocation(b, "u_direction"), pass == 0, pass == 1);
        glBindImageTexture(SAM_IMAGE_SOURCE, source, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(SAM_IMAGE_TARGET, pass == 0 ? tex[3] : tex[4], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(gx, gy, 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    for (int m = 1; m >= 0; --m) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)m);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    glUseProgram(rt->diffusion.compose_program);
    glBindImageTexture(SAM_IMAGE_BLURRED, tex[4], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(SAM_IMAGE_FACTOR, tex[1], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(SAM_IMAGE_SPECULAR, tex[2], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(SAM_IMAGE_COMPOSED, tex[3], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(gx, gy, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}
