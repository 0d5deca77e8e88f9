/*
 * The comparison techniques' GL side: the uniforms of technique.glsl
 * (Jimenez et al.'s transmittance, the translucency override) and d'Eon et
 * al.'s modified translucent shadow maps (Sec. 5.2), rendered from the
 * shadow maps' own cameras so a TSM texel lines up with its shadow texel.
 */
#include <stdio.h>
#include <string.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_shadows.h"
#include "sam_runtime_surface.h"
#include "sam_runtime_technique.h"
#include "sam_runtime_thickness.h"

sam_status sam_runtime_technique_create(sam_runtime *rt, sam_error *err)
{
    GLuint sampler;
    glGenSamplers(1, &sampler);
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sampler, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(sampler, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    rt->technique.distance_sampler = sampler;
    return sam_gl_render_program("tsm.vert", "tsm.frag", NULL, &rt->technique.tsm_program, err);
}

/* The maps alone, kept with the program when the lights need more room. */
static void release_tsm_maps(sam_rt_technique *t)
{
    if (t->tsm_flat_tex)
        glDeleteTextures(1, &t->tsm_flat_tex);
    if (t->tsm_cube_tex)
        glDeleteTextures(1, &t->tsm_cube_tex);
    if (t->tsm_depth)
        glDeleteRenderbuffers(1, &t->tsm_depth);
    if (t->tsm_fbo)
        glDeleteFramebuffers(1, &t->tsm_fbo);
    t->tsm_flat_tex = t->tsm_cube_tex = t->tsm_depth = t->tsm_fbo = 0;
    t->tsm_flat_count = t->tsm_cube_count = 0;
}

void sam_runtime_technique_destroy(sam_runtime *rt)
{
    release_tsm_maps(&rt->technique);
    sam_runtime_delete_program(&rt->technique.tsm_program);
    if (rt->technique.distance_sampler)
        glDeleteSamplers(1, &rt->technique.distance_sampler);
    rt->technique.distance_sampler = 0;
}

int sam_runtime_technique_mode(const sam_render_view *view)
{
    if (view->translucency)
        return TECHNIQUE_OVERRIDE;
    switch (view->technique) {
    case SAM_TECHNIQUE_SAM:
        return TECHNIQUE_VERTEX;
    case SAM_TECHNIQUE_TRANSMITTANCE:
        return TECHNIQUE_TRANSMITTANCE;
    case SAM_TECHNIQUE_THICKNESS:
        return TECHNIQUE_THICKNESS;
    default:
        return TECHNIQUE_NONE;
    }
}

void sam_runtime_bind_technique(const sam_runtime *rt, GLuint p, int mode, GLuint override_tex)
{
    glUniform1i(glGetUniformLocation(p, "u_technique"), mode);
    glUniform1ui(glGetUniformLocation(p, "u_all_light_count"), rt->lights.count);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    float fit[SAM_PROFILE_FIT_GAUSSIANS][4];
    for (uint32_t i = 0; i < rt->fit.count; ++i) {
        memcpy(fit[i], rt->fit.weight[i], 3 * sizeof(float));
        fit[i][3] = rt->fit.variance[i];
    }
    glUniform1i(glGetUniformLocation(p, "u_fit_count"), (GLint)rt->fit.count);
    if (rt->fit.count)
        glUniform4fv(glGetUniformLocation(p, "u_fit"), (GLsizei)rt->fit.count, &fit[0][0]);
    /* The same depth textures as the shadow units, through a sampler that
     * does not compare: the stored distances themselves. */
    for (int i = 0; i < MAX_CUBE_SHADOWS + MAX_FLAT_SHADOWS; ++i) {
        int cube = i < MAX_CUBE_SHADOWS, k = cube ? i : i - MAX_CUBE_SHADOWS;
        GLuint unit = (GLuint)(cube ? UNIT_CUBE_DISTANCE + k : UNIT_FLAT_DISTANCE + k);
        char name[32];
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, cube ? rt->shadows.cube_tex[k] : rt->shadows.flat_tex[k]);
        glBindSampler(unit, rt->technique.distance_sampler);
        snprintf(name, sizeof name, cube ? "u_cube_distance[%d]" : "u_flat_distance[%d]", k);
        glUniform1i(glGetUniformLocation(p, name), (GLint)unit);
    }
    glUniform1f(glGetUniformLocation(p, "u_normal_offset"), 0.01f * rt->radius);
    glActiveTexture(GL_TEXTURE0 + UNIT_OVERRIDE);
    glBindTexture(GL_TEXTURE_2D, override_tex);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_override"), UNIT_OVERRIDE);
    if (mode == TECHNIQUE_THICKNESS)
        sam_runtime_bind_thickness(rt);
}

void sam_runtime_bind_tsm(const sam_runtime *rt, GLuint p)
{
    glActiveTexture(GL_TEXTURE0 + UNIT_TSM_FLAT);
    glBindTexture(GL_TEXTURE_2D_ARRAY, rt->technique.tsm_flat_tex);
    glActiveTexture(GL_TEXTURE0 + UNIT_TSM_CUBE);
    glBindTexture(GL_TEXTURE_2D_ARRAY, rt->technique.tsm_cube_tex);
    glActiveTexture(GL_TEXTURE0 + UNIT_LEVELS);
    glBindTexture(GL_TEXTURE_2D_ARRAY, rt->tsd.level_array);
    glActiveTexture(GL_TEXTURE0 + UNIT_STRETCH);
    glBindTexture(GL_TEXTURE_2D, rt->tsd.atlas_allocated ? rt->tsd.atlas_tex[ATLAS_STRETCH] : 0);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_tsm_flat"), UNIT_TSM_FLAT);
    glUniform1i(glGetUniformLocation(p, "u_tsm_cube"), UNIT_TSM_CUBE);
    glUniform1i(glGetUniformLocation(p, "u_levels"), UNIT_LEVELS);
    glUniform1i(glGetUniformLocation(p, "u_stretch"), UNIT_STRETCH);
    glUniform1f(glGetUniformLocation(p, "u_atlas_used"), (float)rt->tsd.atlas_used);
    sam_mat4 faces[6];
    for (int f = 0; f < 6; ++f)
        faces[f] = sam_runtime_cube_face((const float[3]){0, 0, 0}, 1.0f, f);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_cube_face"), 6, GL_FALSE, faces[0].m);
}

/* Nearest filtering: UVs of neighbouring texels may lie on other charts,
 * and their mean is nowhere on the surface. */
static GLuint tsm_texture(GLenum target, GLsizei side, GLsizei layers)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(target, tex);
    glTexStorage3D(target, 1, GL_RGBA32F, side, side, layers);
    sam_runtime_texture_sampling(target, GL_NEAREST);
    return tex;
}

/* Room for every shadow map the lights have now; grown, never shrunk. */
static sam_status ensure_tsm_maps(sam_runtime *rt, sam_error *err)
{
    if (rt->technique.tsm_fbo && rt->technique.tsm_flat_count >= rt->lights.flat_count && rt->technique.tsm_cube_count >= rt->lights.cube_count)
        return SAM_OK;
    release_tsm_maps(&rt->technique);
    while (glGetError() != GL_NO_ERROR) {
    }
    glGenFramebuffers(1, &rt->technique.tsm_fbo);
    glGenRenderbuffers(1, &rt->technique.tsm_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, rt->technique.tsm_depth);
    /* One depth buffer for both sizes: a framebuffer renders to the
     * intersection of its attachments. */
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, FLAT_SHADOW_SIZE, FLAT_SHADOW_SIZE);
    if (rt->lights.flat_count)
        rt->technique.tsm_flat_tex = tsm_texture(GL_TEXTURE_2D_ARRAY, FLAT_SHADOW_SIZE, (GLsizei)(2 * rt->lights.flat_count));
    if (rt->lights.cube_count)
        rt->technique.tsm_cube_tex = tsm_texture(GL_TEXTURE_2D_ARRAY, CUBE_SHADOW_SIZE, (GLsizei)(12 * rt->lights.cube_count));
    if (glGetError() != GL_NO_ERROR) {
        release_tsm_maps(&rt->technique);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                        "render: the GL could not allocate translucent shadow maps for %u lights with 2D shadow maps "
                        "and %u with cube maps",
                        rt->lights.flat_count, rt->lights.cube_count);
    }
    rt->technique.tsm_flat_count = rt->lights.flat_count;
    rt->technique.tsm_cube_count = rt->lights.cube_count;
    return SAM_OK;
}

/* One TSM image: layers `layer` and `layer + stride` of `tex` seen through
 * `view_proj`. */
static void draw_tsm(sam_runtime *rt, GLuint tex, GLint layer, GLint stride, GLsizei side, const sam_mat4 *view_proj,
                     uint32_t light)
{
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, tex, 0, layer);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, tex, 0, layer + stride);
    glViewport(0, 0, side, side);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    GLuint p = rt->technique.tsm_program;
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_proj"), 1, GL_FALSE, view_proj->m);
    glUniform1ui(glGetUniformLocation(p, "u_light"), light);
    glDrawElements(GL_TRIANGLES, (GLsizei)rt->triangle_count * 3, GL_UNSIGNED_INT, NULL);
}

sam_status sam_runtime_render_tsm(sam_runtime *rt, sam_error *err)
{
    sam_status st = ensure_tsm_maps(rt, err);
    if (st != SAM_OK)
        return st;
    glBindFramebuffer(GL_FRAMEBUFFER, rt->technique.tsm_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rt->technique.tsm_depth);
    static const GLenum two[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, two);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(rt->technique.tsm_program);
    sam_runtime_bind_uv_atlas(rt, rt->technique.tsm_program);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_LIGHTS, rt->buffer[SAM_B_LIGHTS]);
    glBindVertexArray(rt->vao);
    /* Area lights get no TSM, but keep their cube map's slot. */
    for (sam_runtime_shadow s = {0}; sam_runtime_next_shadow(rt, &s);) {
        if (s.cube) {
            if (rt->lights.lights[s.light].type == SAM_LIGHT_POINT)
                for (int f = 0; f < 6; ++f) {
                    sam_mat4 vp = sam_runtime_cube_face(rt->shadows.cube_origin[s.map], rt->shadows.cube_far[s.map], f);
                    draw_tsm(rt, rt->technique.tsm_cube_tex, (GLint)(12 * s.map) + f, 6, CUBE_SHADOW_SIZE, &vp, s.light);
                }
        } else {
            draw_tsm(rt, rt->technique.tsm_flat_tex, (GLint)(2 * s.map), 1, FLAT_SHADOW_SIZE, &rt->shadows.flat_matrix[s.map],
                     s.light);
        }
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    return SAM_OK;
}
