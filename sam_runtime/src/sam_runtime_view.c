/* The view (sam_runtime_view.h): sam_runtime_render and its texture,
 * sam_runtime_gbuffer and the view's camera. */
#include <math.h>
#include <string.h>

#include "sam_runtime_diffusion.h"
#include "sam_runtime_gpu.h"
#include "sam_runtime_shadows.h"
#include "sam_runtime_surface.h"
#include "sam_runtime_technique.h"
#include "sam_runtime_thickness.h"
#include "sam_runtime_tsd.h"
#include "sam_runtime_view.h"

sam_status sam_runtime_view_create(sam_runtime *rt, sam_error *err)
{
    return sam_gl_render_program("shade.vert", "shade.frag", NULL, &rt->view.shade_program, err);
}

static void release_view_targets(sam_runtime *rt)
{
    if (rt->view.fbo) {
        glDeleteFramebuffers(1, &rt->view.fbo);
        glDeleteTextures(5, rt->view.tex);
        glDeleteTextures(2, rt->view.sss_mips);
        glDeleteRenderbuffers(1, &rt->view.depth);
    }
    rt->view.fbo = rt->view.depth = 0;
    memset(rt->view.tex, 0, sizeof rt->view.tex);
    memset(rt->view.sss_mips, 0, sizeof rt->view.sss_mips);
    rt->view.width = rt->view.height = 0;
}

void sam_runtime_view_destroy(sam_runtime *rt)
{
    release_view_targets(rt);
    sam_runtime_delete_program(&rt->view.shade_program);
}

/* The view-sized targets of sam_runtime_render, kept between renders of
 * one size: 0 colour (or entering light + depth), 1 factor, 2 specular,
 * 3 and 4 the blur's ping-pong and the composed result; depth; and the
 * blur's two mipmapped textures (sam_runtime_screen_space_diffusion). */
static sam_status ensure_view_targets(sam_runtime *rt, uint32_t width, uint32_t height, sam_error *err)
{
    if (rt->view.fbo && rt->view.width == width && rt->view.height == height)
        return SAM_OK;
    release_view_targets(rt);
    glGenFramebuffers(1, &rt->view.fbo);
    glGenTextures(5, rt->view.tex);
    glGenRenderbuffers(1, &rt->view.depth);
    for (int i = 0; i < 5; ++i) {
        glBindTexture(GL_TEXTURE_2D, rt->view.tex[i]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, (GLsizei)width, (GLsizei)height);
    }
    GLsizei levels = 1;
    while ((width > height ? width : height) >> levels)
        ++levels;
    glGenTextures(2, rt->view.sss_mips);
    for (int i = 0; i < 2; ++i) {
        glBindTexture(GL_TEXTURE_2D, rt->view.sss_mips[i]);
        glTexStorage2D(GL_TEXTURE_2D, levels, i == 0 ? GL_RGBA32F : GL_R32F, (GLsizei)width, (GLsizei)height);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindRenderbuffer(GL_RENDERBUFFER, rt->view.depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, (GLsizei)width, (GLsizei)height);
    glBindFramebuffer(GL_FRAMEBUFFER, rt->view.fbo);
    for (int i = 0; i < 3; ++i)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, rt->view.tex[i], 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rt->view.depth);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        release_view_targets(rt);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "render: framebuffer incomplete (0x%04x) at %ux%u", status, width,
                        height);
    }
    rt->view.width = width;
    rt->view.height = height;
    return SAM_OK;
}

static sam_status check_view(const sam_runtime *rt, const sam_render_view *view, sam_error *err)
{
    const sam_diffusion_options *o = &view->options;
    if (!view->width || !view->height || view->width > 16384 || view->height > 16384 ||
        !(view->fov_deg > 0 && view->fov_deg < 180))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: size %ux%u or field of view %g out of range",
                        view->width, view->height, view->fov_deg);
    if (view->diffusion < 0 || view->diffusion > 3)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: diffusion %d is not 0..3", view->diffusion);
    if (o->sss_samples && (o->sss_samples < 9 || o->sss_samples > 33 || o->sss_samples % 2 == 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: %u screen-space samples; need an odd count in 9..33",
                        o->sss_samples);
    if ((unsigned)o->sss_kernel > SAM_SSS_KERNEL_EQ1)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: unknown screen-space kernel %d", (int)o->sss_kernel);
    if (!(o->texels_per_pixel >= 0 && o->texels_per_pixel <= 16))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: %g texels per pixel outside (0, 16]",
                        o->texels_per_pixel);
    if ((unsigned)view->technique > SAM_TECHNIQUE_THICKNESS)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: unknown technique %d", (int)view->technique);
    int tsm = view->technique == SAM_TECHNIQUE_TSM && !view->translucency;
    if (tsm && view->diffusion != 3)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "render: the tsm technique needs texture-space diffusion (diffusion 3) and usable UVs; "
                        "got diffusion %d",
                        view->diffusion);
    if (view->diffusion == 3 && !rt->tsd.uv_usable)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "render: texture-space diffusion%s cannot run: %s",
                        tsm ? " (which tsm needs)" : "", rt->tsd.uv_reason);
    const sam_image *t = view->translucency;
    if (t && t->channels != 3 && t->channels != 4)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: translucency override with %u channels; need 3 or 4",
                        t->channels);
    if (t && view->diffusion == 3 && o->depth_sized)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "render: a translucency override needs a fixed atlas; turn depth_sized off");
    uint32_t want_w = view->diffusion == 3 ? sam_runtime_atlas_size(view) : view->width,
             want_h = view->diffusion == 3 ? want_w : view->height;
    if (t && (t->width != want_w || t->height != want_h))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: translucency override is %ux%u; the %s is %ux%u",
                        t->width, t->height, view->diffusion == 3 ? "atlas" : "view", want_w, want_h);
    return SAM_OK;
}

/* `view` with its camera in the GPU's frame (sam_runtime_internal.h). */
static sam_render_view in_frame(const sam_runtime *rt, const sam_render_view *view)
{
    sam_render_view framed = *view;
    sam_runtime_to_frame(rt, view->eye, framed.eye);
    sam_runtime_to_frame(rt, view->target, framed.target);
    return framed;
}

/* The camera of `view` (in the frame): near and far from the object's
 * bounds where 0. */
static void view_matrices(const sam_runtime *rt, const sam_render_view *view, sam_mat4 *proj, sam_mat4 *view_proj)
{
    float dist = sqrtf((view->eye[0] - rt->centre[0]) * (view->eye[0] - rt->centre[0]) +
                       (view->eye[1] - rt->centre[1]) * (view->eye[1] - rt->centre[1]) +
                       (view->eye[2] - rt->centre[2]) * (view->eye[2] - rt->centre[2]));
    float far_plane = view->far_plane > 0 ? view->far_plane : dist + 2.0f * rt->radius;
    float near_plane = view->near_plane > 0 ? view->near_plane : fmaxf(1e-4f * far_plane, dist - 2.0f * rt->radius);
    *proj = sam_mat4_perspective(view->fov_deg * 3.14159265f / 180.0f, (float)view->width / (float)view->height,
                                 near_plane, far_plane);
    *view_proj = sam_mat4_mul(*proj, sam_mat4_look_at(view->eye, view->target, view->up));
}

/* The shading pass into the view targets (0 colour or entering light +
 * depth, 1 factor, 2 specular), or with `gbuffer` positions into 0 and
 * normals into 1 through the same rasterisation. */
static void draw_view(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *vp, int mode, GLuint override_tex,
                      int tsm, int gbuffer)
{
    static const GLenum attachments[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glBindFramebuffer(GL_FRAMEBUFFER, rt->view.fbo);
    glDrawBuffers(3, attachments);
    glViewport(0, 0, (GLsizei)view->width, (GLsizei)view->height);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    GLuint p = rt->view.shade_program;
    int texture_space = view->diffusion == 3 && !gbuffer;
    glUseProgram(p);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_proj"), 1, GL_FALSE, vp->m);
    glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, view->eye);
    glUniform3fv(glGetUniformLocation(p, "u_albedo"), 1, view->albedo);
    glUniform3fv(glGetUniformLocation(p, "u_total_reflectance"), 1, rt->total_reflectance);
    glUniform1i(glGetUniformLocation(p, "u_front"), view->front);
    glUniform1i(glGetUniformLocation(p, "u_gbuffer"), gbuffer);
    glUniform1f(glGetUniformLocation(p, "u_roughness"), rt->surface.roughness);
    glUniform1f(glGetUniformLocation(p, "u_f0"), SKIN_F0);
    glUniform1ui(glGetUniformLocation(p, "u_light_count"), view->front ? rt->lights.count : 0);
    glUniform1i(glGetUniformLocation(p, "u_split"), view->diffusion == 1);
    glUniform1i(glGetUniformLocation(p, "u_preintegrated"), view->diffusion == 2);
    glUniform1i(glGetUniformLocation(p, "u_texture_space"), texture_space);
    /* A TSM's atlas holds the front light even when the view shows none. */
    glUniform1i(glGetUniformLocation(p, "u_read_atlas"), !(tsm && !view->front));
    glUniform1i(glGetUniformLocation(p, "u_tsm"), tsm);
    glActiveTexture(GL_TEXTURE0 + UNIT_ATLAS);
    glBindTexture(GL_TEXTURE_2D, texture_space ? rt->tsd.atlas_tex[ATLAS_SUM] : 0);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_atlas"), UNIT_ATLAS);
    if (texture_space) {
        glUniform1f(glGetUniformLocation(p, "u_atlas_scale"), (float)rt->tsd.atlas_used / (float)rt->tsd.atlas_allocated);
        glUniform1f(glGetUniformLocation(p, "u_atlas_texel"), 1.0f / (float)rt->tsd.atlas_allocated);
    }
    sam_runtime_bind_albedo(rt, p);
    sam_runtime_bind_uv_atlas(rt, p);
    glUniform1i(glGetUniformLocation(p, "u_pre_size"), PRE_SIZE);
    glUniform1f(glGetUniformLocation(p, "u_pre_max_curvature"), PRE_MAX_CURVATURE);
    glUniform1f(glGetUniformLocation(p, "u_pre_max_penumbra"), PRE_MAX_PENUMBRA_MM);
    glUniform1f(glGetUniformLocation(p, "u_min_penumbra"), rt->diffusion.min_penumbra_mm);
    float forward[3] = {view->target[0] - view->eye[0], view->target[1] - view->eye[1],
                        view->target[2] - view->eye[2]};
    float fl = sqrtf(forward[0] * forward[0] + forward[1] * forward[1] + forward[2] * forward[2]);
    for (int c = 0; c < 3; ++c)
        forward[c] /= fl;
    glUniform3fv(glGetUniformLocation(p, "u_forward"), 1, forward);
    sam_runtime_set_surface_uniforms(rt, p);
    sam_runtime_bind_shadows(rt, p);
    sam_runtime_bind_buffers(rt);
    /* With texture space the atlas carries the translucency (the override
     * there is atlas-sized): the pass itself adds none. */
    sam_runtime_bind_technique(rt, p, texture_space ? TECHNIQUE_NONE : mode, texture_space ? 0 : override_tex);
    sam_runtime_bind_tsm(rt, p);
    /* The G-buffer is no frame: it leaves the shading pass's time alone. */
    if (!gbuffer)
        sam_runtime_begin_timer(rt, SAM_PASS_SHADE);
    glBindVertexArray(rt->vao);
    glDrawElements(GL_TRIANGLES, (GLsizei)rt->triangle_count * 3, GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);
    if (!gbuffer)
        sam_runtime_end_timer(rt, SAM_PASS_SHADE);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

sam_status sam_runtime_render_texture(sam_runtime *rt, const sam_render_view *model_view, GLuint *texture,
                                     sam_error *err)
{
    *texture = 0;
    const sam_render_view framed = in_frame(rt, model_view), *view = &framed;
    sam_status st = check_view(rt, view, err);
    if (st == SAM_OK && view->diffusion == 2)
        st = sam_runtime_ensure_preintegrated(rt, err);
    if (st == SAM_OK && view->diffusion == 1)
        st = sam_runtime_ensure_kernel(rt, view->options.sss_kernel, view->options.sss_samples ? view->options.sss_samples : 17,
                           err);
    if (st == SAM_OK)
        st = ensure_view_targets(rt, view->width, view->height, err);
    if (st != SAM_OK)
        return st;
    sam_mat4 proj, vp;
    view_matrices(rt, view, &proj, &vp);
    int mode = sam_runtime_technique_mode(view);
    int tsm = view->technique == SAM_TECHNIQUE_TSM && !view->translucency;
    GLuint override_tex = 0;
    /* View-sized overrides run top-down like the images; atlas-sized ones
     * in read_atlas's order, which is GL's. */
    if (view->translucency && !(override_tex = sam_runtime_image_texture(view->translucency, 1, view->diffusion != 3)))
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "render: the GL could not store a %ux%u translucency override",
                        view->translucency->width, view->translucency->height);
    if (tsm)
        st = sam_runtime_render_tsm(rt, err);
    if (mode == TECHNIQUE_THICKNESS)
        st = sam_runtime_thickness_pass(rt, err);
    if (st == SAM_OK && view->diffusion == 3) {
        sam_runtime_begin_timer(rt, SAM_PASS_DIFFUSION);
        st = sam_runtime_texture_space(rt, view, &vp, &proj, mode, override_tex, tsm, err);
        sam_runtime_end_timer(rt, SAM_PASS_DIFFUSION);
    }
    if (st != SAM_OK)
        goto done;
    draw_view(rt, view, &vp, mode, override_tex, tsm, 0);
    GLuint result = rt->view.tex[0];
    if (view->diffusion == 1) {
        sam_runtime_begin_timer(rt, SAM_PASS_DIFFUSION);
        sam_runtime_screen_space_diffusion(rt, view, rt->view.tex, rt->view.sss_mips);
        sam_runtime_end_timer(rt, SAM_PASS_DIFFUSION);
        result = rt->view.tex[3];
    }
    *texture = result;
done:
    if (override_tex)
        glDeleteTextures(1, &override_tex);
    return st;
}

sam_status sam_runtime_render(sam_runtime *rt, const sam_render_view *view, sam_image *out, sam_error *err)
{
    memset(out, 0, sizeof *out);
    GLuint result;
    sam_status st = sam_runtime_render_texture(rt, view, &result, err);
    /* GL's rows run bottom-up; images top-down. */
    if (st == SAM_OK)
        st = sam_runtime_read_texture(result, view->width, view->height, view->width, view->height, 1, out, err);
    return st;
}

void sam_runtime_view_projection(const sam_runtime *rt, const sam_render_view *view, float m[16])
{
    sam_mat4 proj, vp;
    const sam_render_view framed = in_frame(rt, view);
    view_matrices(rt, &framed, &proj, &vp);
    /* Model units in: the frame's offset comes first. */
    const float back[3] = {-rt->frame[0], -rt->frame[1], -rt->frame[2]};
    vp = sam_mat4_mul(vp, sam_mat4_translate(back));
    memcpy(m, vp.m, sizeof vp.m);
}

sam_status sam_runtime_gbuffer(sam_runtime *rt, const sam_render_view *model_view, sam_gbuffer_space space,
                               sam_image *positions, sam_image *normals, sam_error *err)
{
    const sam_render_view framed = in_frame(rt, model_view), *view = &framed;
    memset(positions, 0, sizeof *positions);
    memset(normals, 0, sizeof *normals);
    if ((unsigned)space > SAM_GBUFFER_ATLAS)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "gbuffer: unknown space %d", (int)space);
    /* Only the geometry matters: no technique, override or TSM checks. */
    sam_render_view geometry = *view;
    geometry.technique = SAM_TECHNIQUE_SAM;
    geometry.translucency = NULL;
    geometry.diffusion = space == SAM_GBUFFER_ATLAS ? 3 : 0;
    sam_status st = check_view(rt, &geometry, err);
    if (st != SAM_OK)
        return st;
    uint32_t side = sam_runtime_atlas_size(view);
    if (space == SAM_GBUFFER_ATLAS && (side < 64 || side > 4096 || view->options.depth_sized))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "gbuffer: the atlas needs a fixed side in 64..4096 (atlas size %u, depth_sized %d)", side,
                        view->options.depth_sized);
    sam_mat4 proj, vp;
    view_matrices(rt, view, &proj, &vp);
    GLuint tex[2] = {0, 0}, fbo = 0;
    uint32_t w = view->width, h = view->height;
    if (space == SAM_GBUFFER_SCREEN) {
        if ((st = ensure_view_targets(rt, w, h, err)) != SAM_OK)
            return st;
        draw_view(rt, &geometry, &vp, TECHNIQUE_NONE, 0, 0, 1);
        tex[0] = rt->view.tex[0];
        tex[1] = rt->view.tex[1];
    } else {
        w = h = side;
        while (glGetError() != GL_NO_ERROR) {
        }
        glGenTextures(2, tex);
        for (int i = 0; i < 2; ++i) {
            glBindTexture(GL_TEXTURE_2D, tex[i]);
            glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, (GLsizei)side, (GLsizei)side);
        }
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, tex[1], 0);
        static const GLenum two[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glDrawBuffers(2, two);
        if (glGetError() != GL_NO_ERROR || glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "gbuffer: the GL could not make two %u^2 atlas maps", side);
        else
            sam_runtime_draw_atlas(rt, &geometry, &vp, &proj, side, TECHNIQUE_NONE, 0, 0, 1);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    /* Screen rows top-down like sam_runtime_render; atlas rows in
     * read_atlas's order (row v = texel row v). */
    int flip = space == SAM_GBUFFER_SCREEN;
    if (st == SAM_OK && (st = sam_runtime_read_texture(tex[0], w, h, w, h, flip, positions, err)) == SAM_OK &&
        (st = sam_runtime_read_texture(tex[1], w, h, w, h, flip, normals, err)) != SAM_OK)
        sam_image_destroy(positions);
    /* Covered texels (w = 1) back to model units. */
    for (size_t i = 0; st == SAM_OK && i < (size_t)w * h; ++i)
        if (positions->pixels[4 * i + 3] != 0.0f)
            sam_runtime_from_frame(rt, positions->pixels + 4 * i, positions->pixels + 4 * i);
    if (space == SAM_GBUFFER_ATLAS) {
        glDeleteFramebuffers(1, &fbo);
        glDeleteTextures(2, tex);
    }
    return st;
}
