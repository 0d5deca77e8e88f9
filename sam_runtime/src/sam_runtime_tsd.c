/*
 * Texture-space diffusion (d'Eon et al. 2007, Sec. 5.1) with the three
 * optimisations of Jimenez and Gutierrez ("Faster rendering of human
 * skin"): culled, clipped and depth-sized irradiance maps.
 *
 * The maps stay allocated at the largest side asked for; a depth-sized
 * atlas uses the T x T corner of them (the paper's glViewport(0, 0, T, T)),
 * so shrinking it costs no allocation. Culled and clipped texels are never
 * written: their alpha stays 0 from the clear, and the blur passes skip
 * them and use the centre texel in place of their value.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_uv.h"
#include "sam_runtime_gpu.h"
#include "sam_runtime_shadows.h"
#include "sam_runtime_surface.h"
#include "sam_runtime_technique.h"
#include "sam_runtime_tsd.h"

#define DEFAULT_ATLAS 1024
#define MIN_ATLAS 64
#define CULL_MIN 0.2617993877991494f /* 15 degrees past the silhouette: the paper's 105 */
#define CULL_REACH 4.0f               /* standard deviations of the widest Gaussian */

static void release_maps(sam_runtime *rt)
{
    if (rt->tsd.atlas_allocated)
        glDeleteTextures(ATLAS_COUNT, rt->tsd.atlas_tex);
    memset(rt->tsd.atlas_tex, 0, sizeof rt->tsd.atlas_tex);
    rt->tsd.atlas_allocated = rt->tsd.atlas_used = 0;
    if (rt->tsd.level_count) {
        glDeleteTextures((GLsizei)rt->tsd.level_count, rt->tsd.level_view);
        glDeleteTextures(1, &rt->tsd.level_array);
    }
    memset(rt->tsd.level_view, 0, sizeof rt->tsd.level_view);
    rt->tsd.level_array = 0;
    rt->tsd.level_count = 0;
    if (rt->tsd.deferred)
        glDeleteBuffers(1, &rt->tsd.deferred);
    rt->tsd.deferred = 0;
}

/* The blur's list of texels for its second dispatch: the dispatch's
 * arguments and count, then one uint per texel of a side x side atlas. */
#define DEFERRED_HEADER 16u

static sam_status ensure_deferred(sam_runtime *rt, uint32_t side, sam_error *err)
{
    const size_t bytes = DEFERRED_HEADER + (size_t)side * side * sizeof(uint32_t);
    sam_status st = sam_runtime_check_block_size("the texture-space blur's list of texels", bytes, err);
    if (st != SAM_OK)
        return st;
    glGenBuffers(1, &rt->tsd.deferred);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->tsd.deferred);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)bytes, NULL, GL_DYNAMIC_DRAW);
    if (glGetError() != GL_NO_ERROR)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "render: the GL could not allocate %zu bytes for the blur's texels",
                        bytes);
    return SAM_OK;
}

static sam_status ensure_atlas(sam_runtime *rt, uint32_t side, sam_error *err)
{
    if (rt->tsd.atlas_allocated == side)
        return SAM_OK;
    release_maps(rt);
    while (glGetError() != GL_NO_ERROR) {
    }
    glGenTextures(ATLAS_COUNT, rt->tsd.atlas_tex);
    for (int i = 0; i < ATLAS_COUNT; ++i) {
        glBindTexture(GL_TEXTURE_2D, rt->tsd.atlas_tex[i]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, (GLsizei)side, (GLsizei)side);
        /* Read bilinearly: the sum by the mesh at its UVs, the levels by the
         * blur's taps between texels. */
        GLint filter = i == ATLAS_STRETCH ? GL_NEAREST : GL_LINEAR;
        sam_runtime_texture_sampling(GL_TEXTURE_2D, filter);
    }
    if (glGetError() != GL_NO_ERROR) {
        release_maps(rt);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "render: the GL could not allocate %d texture-space maps of %u^2",
                        ATLAS_COUNT, side);
    }
    sam_status st = ensure_deferred(rt, side, err);
    if (st != SAM_OK) {
        release_maps(rt);
        return st;
    }
    if (!rt->tsd.fbo)
        glGenFramebuffers(1, &rt->tsd.fbo);
    rt->tsd.atlas_allocated = side;
    return SAM_OK;
}

/* Primitive ids reach the blur as floats in the stretch map: exact below
 * 2^24. */
#define MAX_CROSS_TRIANGLES (1u << 24)

/* The crossings buffer: per triangle {across edge 0, 1, 2, chart}. Left
 * one empty entry (and rt->tsd.cross 0) where the mesh has no usable UVs or
 * too many triangles, so the blur's block is always backed. */
static sam_status upload_crossings(sam_runtime *rt, const samfile_data *sam, sam_error *err)
{
    sam_rt_tsd *t = &rt->tsd;
    const uint32_t tc = sam->triangle_count;
    t->cross = t->uv_usable && tc < MAX_CROSS_TRIANGLES;
    const size_t entries = t->cross ? tc : 1;
    uint32_t *packed = calloc(4 * entries, sizeof *packed), *across = NULL, *chart = NULL;
    sam_status st = SAM_OK;
    if (!packed)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "render: out of memory for %zu triangles' crossings", entries);
    if (t->cross) {
        across = malloc(3 * (size_t)tc * sizeof *across);
        chart = malloc((size_t)tc * sizeof *chart);
        st = across && chart ? sam_uv_crossings(sam->positions, sam->uvs, sam->vertex_count, sam->triangles, tc,
                                                across, chart, err)
                             : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "render: out of memory for %u triangles' crossings", tc);
        for (uint32_t k = 0; st == SAM_OK && k < tc; ++k) {
            memcpy(packed + 4 * (size_t)k, across + 3 * (size_t)k, 3 * sizeof *packed);
            packed[4 * (size_t)k + 3] = chart[k];
        }
    }
    if (st == SAM_OK)
        st = sam_runtime_check_block_size("the triangles' crossings", 4 * entries * sizeof *packed, err);
    if (st == SAM_OK) {
        glGenBuffers(1, &t->crossings);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, t->crossings);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(4 * entries * sizeof *packed), packed, GL_STATIC_DRAW);
        if (glGetError() != GL_NO_ERROR)
            st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "render: the GL could not allocate %zu triangles' crossings",
                          entries);
    }
    free(packed);
    free(across);
    free(chart);
    return st;
}

sam_status sam_runtime_tsd_create(sam_runtime *rt, const samfile_data *sam, sam_error *err)
{
    sam_rt_tsd *t = &rt->tsd;
    sam_status st;
    if (sam->uvs) {
        t->has_uvs = 1;
        /* Texture-space diffusion needs charts inside [0, 1]^2 that do not
         * overlap: mirrored islands would sum two places' light in one texel.
         * A layout reaching past [0, 1]^2 is moved into it first. */
        float *atlas_uvs = malloc((sam->vertex_count ? sam->vertex_count : 1) * 2 * sizeof *atlas_uvs);
        if (!atlas_uvs)
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "render: out of memory for %u atlas UVs", sam->vertex_count);
        sam_uv_report report;
        st = sam_uv_fit_atlas(sam->uvs, sam->vertex_count, sam->triangles, sam->triangle_count, &t->uv_atlas,
                              atlas_uvs, err);
        if (st == SAM_OK)
            st = sam_uv_check(atlas_uvs, sam->vertex_count, sam->triangles, sam->triangle_count, 1024, &report, err);
        free(atlas_uvs);
        if (st != SAM_OK)
            return st;
        t->uv_usable = sam_uv_usable(&report, t->uv_reason, sizeof t->uv_reason);
        t->uv_coverage = report.resolution ? (float)((double)report.covered_texels /
                                                     ((double)report.resolution * report.resolution))
                                           : 0.0f;
    } else {
        snprintf(t->uv_reason, sizeof t->uv_reason, "the mesh has no UVs");
    }
    if ((st = sam_gl_render_program("tsd_irradiance.vert", "tsd_irradiance.frag", NULL, &t->program, err)) != SAM_OK)
        return st;
    return upload_crossings(rt, sam, err);
}

void sam_runtime_tsd_destroy(sam_runtime *rt)
{
    release_maps(rt);
    if (rt->tsd.fbo)
        glDeleteFramebuffers(1, &rt->tsd.fbo);
    rt->tsd.fbo = 0;
    sam_runtime_delete_program(&rt->tsd.program);
    sam_runtime_delete_program(&rt->tsd.blur_program);
    sam_runtime_delete_program(&rt->tsd.blur_listed_program);
    sam_runtime_delete_program(&rt->tsd.accumulate_program);
    if (rt->tsd.crossings)
        glDeleteBuffers(1, &rt->tsd.crossings);
    rt->tsd.crossings = 0;
}

int sam_runtime_uv_status(const sam_runtime *rt, char *reason, size_t n, sam_uv_atlas *atlas)
{
    if (atlas)
        *atlas = rt->tsd.uv_atlas;
    if (reason && n)
        snprintf(reason, n, "%s", rt->tsd.uv_usable ? "" : rt->tsd.uv_reason);
    return rt->tsd.uv_usable;
}

/* One layer per Gaussian at the atlas's side, each also a 2D texture (a
 * view of its layer) that the blur reads and writes like the other maps. */
static sam_status ensure_levels(sam_runtime *rt, sam_error *err)
{
    if (rt->tsd.level_count == rt->fit.count)
        return SAM_OK;
    while (glGetError() != GL_NO_ERROR) {
    }
    GLsizei side = (GLsizei)rt->tsd.atlas_allocated, count = (GLsizei)rt->fit.count;
    glGenTextures(1, &rt->tsd.level_array);
    glBindTexture(GL_TEXTURE_2D_ARRAY, rt->tsd.level_array);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_RGBA32F, side, side, count);
    sam_runtime_texture_sampling(GL_TEXTURE_2D_ARRAY, GL_LINEAR);
    glGenTextures(count, rt->tsd.level_view);
    rt->tsd.level_count = rt->fit.count;
    for (GLsizei i = 0; i < count; ++i) {
        glTextureView(rt->tsd.level_view[i], GL_TEXTURE_2D, rt->tsd.level_array, GL_RGBA32F, 0, 1, (GLuint)i, 1);
        glBindTexture(GL_TEXTURE_2D, rt->tsd.level_view[i]);
        sam_runtime_texture_sampling(GL_TEXTURE_2D, GL_LINEAR);
    }
    if (glGetError() != GL_NO_ERROR) {
        release_maps(rt);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                        "render: the GL could not allocate %d texture-space levels of %d^2 for the TSMs", count, side);
    }
    return SAM_OK;
}

uint32_t sam_runtime_atlas_size(const sam_render_view *view)
{
    return view->options.atlas_size ? view->options.atlas_size : DEFAULT_ATLAS;
}

/* Eq. 3-4: T = min(1, d_ref / d) T_max. A texel spans about
 * sqrt(area / coverage) / T model units and a pixel d / f at distance d
 * (f: the focal length in pixels), so texels_per_pixel texels per pixel at
 * the nearest point need T = texels_per_pixel f sqrt(area / coverage) / d. */
static uint32_t atlas_side(const sam_runtime *rt, const sam_render_view *view, uint32_t max_side)
{
    if (!view->options.depth_sized)
        return max_side;
    double d2 = 0;
    for (int c = 0; c < 3; ++c) {
        double e = view->eye[c], q = e < rt->box_lo[c] ? rt->box_lo[c] - e : e > rt->box_hi[c] ? e - rt->box_hi[c] : 0;
        d2 += q * q;
    }
    double f = view->height / (2.0 * tan(0.5 * view->fov_deg * 3.14159265358979323846 / 180.0));
    double tpp = view->options.texels_per_pixel > 0 ? view->options.texels_per_pixel : 1.0;
    double need = tpp * f * sqrt(rt->surface_area / fmax(rt->tsd.uv_coverage, 1e-3)) / fmax(sqrt(d2), 1e-30);
    if (!(need < max_side))
        return max_side;
    return need < MIN_ATLAS ? MIN_ATLAS : (uint32_t)ceil(need);
}

void sam_runtime_draw_atlas(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *view_proj,
                            const sam_mat4 *proj, uint32_t side, int mode, GLuint override_tex, int front,
                            int gbuffer)
{
    int culled = view->options.culled && !gbuffer, clipped = view->options.clipped && !gbuffer;
    glViewport(0, 0, (GLsizei)side, (GLsizei)side);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, (GLsizei)side, (GLsizei)side);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    GLuint p = rt->tsd.program;
    glUseProgram(p);
    sam_runtime_bind_uv_atlas(rt, p);
    glUniform3fv(glGetUniformLocation(p, "u_total_reflectance"), 1, rt->total_reflectance);
    glUniform1i(glGetUniformLocation(p, "u_front"), front);
    glUniform1i(glGetUniformLocation(p, "u_gbuffer"), gbuffer);
    glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, view->eye);
    glUniform1i(glGetUniformLocation(p, "u_culled"), culled);
    float widest = sqrtf(rt->fit.count ? rt->fit.variance[rt->fit.count - 1] : 0.0f);
    glUniform1f(glGetUniformLocation(p, "u_cull_reach"), CULL_REACH * widest);
    glUniform1f(glGetUniformLocation(p, "u_cull_min"), CULL_MIN);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_proj"), 1, GL_FALSE, view_proj->m);
    /* The frustum's side planes moved out by three standard deviations of
     * the widest Gaussian: clip.x shifts by P[0][0] per model unit sideways. */
    float margin = 3.0f * widest / rt->mm_per_unit;
    float clip_margin[2] = {proj->m[0] * margin, proj->m[5] * margin};
    glUniform2fv(glGetUniformLocation(p, "u_clip_margin"), 1, clip_margin);
    glUniform1i(glGetUniformLocation(p, "u_clipped"), clipped);
    glUniform3fv(glGetUniformLocation(p, "u_albedo"), 1, view->albedo);
    sam_runtime_bind_albedo(rt, p);
    sam_runtime_bind_shadows(rt, p);
    sam_runtime_bind_buffers(rt);
    sam_runtime_bind_technique(rt, p, mode, override_tex);
    if (clipped)
        for (int i = 0; i < 4; ++i)
            glEnable(GL_CLIP_DISTANCE0 + (GLenum)i);
    glBindVertexArray(rt->vao);
    glDrawElements(GL_TRIANGLES, (GLsizei)rt->triangle_count * 3, GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);
    for (int i = 0; i < 4; ++i)
        glDisable(GL_CLIP_DISTANCE0 + (GLenum)i);
}

/* Makes blur program b current, set for one pass (0: along u, 1: along v)
 * of a Gaussian of `sigma_mm` over the atlas's used `size`; the caller
 * binds the textures and images. */
static void set_blur(const sam_runtime *rt, GLuint b, float sigma_mm, const GLint size[2], int pass)
{
    glUseProgram(b);
    glUniform1f(glGetUniformLocation(b, "u_sigma_mm"), sigma_mm);
    glUniform2iv(glGetUniformLocation(b, "u_size"), 1, size);
    glUniform1i(glGetUniformLocation(b, "u_cross"), rt->tsd.cross);
    glUniform1f(glGetUniformLocation(b, "u_mm_per_unit"), rt->mm_per_unit);
    sam_runtime_bind_uv_atlas(rt, b);
    glUniform2i(glGetUniformLocation(b, "u_direction"), pass == 0, pass == 1);
    glUniform1i(glGetUniformLocation(b, "u_source"), 0);
    glUniform1i(glGetUniformLocation(b, "u_level"), 1);
}

/* The blur's and the sum's programs, compiled on the first texture-space
 * render: a runtime that never diffuses in texture space need not build
 * them, and every program compiled is one more for Mesa's shader cache
 * thread to write while LeakSanitizer scans at exit (docs/building.md). */
static sam_status ensure_programs(sam_runtime *rt, sam_error *err)
{
    sam_rt_tsd *t = &rt->tsd;
    sam_status st = SAM_OK;
    if (!t->blur_program)
        st = sam_gl_compute_program("tsd_blur.comp", NULL, &t->blur_program, err);
    if (st == SAM_OK && !t->blur_listed_program)
        st = sam_gl_compute_program("tsd_blur.comp", "#define SAM_TSD_LISTED 1\n", &t->blur_listed_program, err);
    if (st == SAM_OK && !t->accumulate_program)
        st = sam_gl_compute_program("tsd_accumulate.comp", NULL, &t->accumulate_program, err);
    return st;
}

sam_status sam_runtime_texture_space(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *view_proj,
                                     const sam_mat4 *proj, int mode, GLuint override_tex, int tsm, sam_error *err)
{
    uint32_t max_side = sam_runtime_atlas_size(view);
    if (max_side < MIN_ATLAS || max_side > 4096)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: atlas size %u outside %d..4096", max_side, MIN_ATLAS);
    sam_status st = ensure_programs(rt, err);
    if (st == SAM_OK)
        st = ensure_atlas(rt, max_side, err);
    if (st == SAM_OK && tsm)
        st = ensure_levels(rt, err);
    if (st != SAM_OK)
        return st;
    uint32_t side = atlas_side(rt, view, max_side);
    const GLuint *tex = rt->tsd.atlas_tex;

    glBindFramebuffer(GL_FRAMEBUFFER, rt->tsd.fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[ATLAS_IRRADIANCE], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, tex[ATLAS_STRETCH], 0);
    static const GLenum two[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, two);
    /* A TSM transmits the light-facing side's front light, shown or not,
     * and that side mostly faces away from the eye or lies off screen: no
     * culling or clipping may drop it. */
    sam_render_view whole = *view;
    if (tsm)
        whole.options.culled = whole.options.clipped = 0;
    sam_runtime_draw_atlas(rt, &whole, view_proj, proj, side, mode, override_tex, view->front || tsm, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);

    /* One level per Gaussian, each the previous blurred by the variance it
     * lacks, ping-ponging between two maps so the irradiance map survives
     * (or, for the TSMs, each in a layer of its own). */
    GLuint groups = (side + 7) / 8, level = tex[ATLAS_IRRADIANCE];
    GLint size[2] = {(GLint)side, (GLint)side};
    float previous_variance = 0.0f;
    for (uint32_t g = 0; g < rt->fit.count; ++g) {
        GLuint next = tsm ? rt->tsd.level_view[g] : g % 2 ? tex[ATLAS_LEVEL_B] : tex[ATLAS_LEVEL_A];
        float sigma = sqrtf(fmaxf(rt->fit.variance[g] - previous_variance, 0.0f));
        previous_variance = rt->fit.variance[g];
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_TSD_CROSSINGS, rt->tsd.crossings);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SAM_B_TSD_DEFERRED, rt->tsd.deferred);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, rt->tsd.deferred);
        glBindImageTexture(SAM_IMAGE_STRETCH, tex[ATLAS_STRETCH], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        for (int pass = 0; pass < 2; ++pass) {
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, pass == 0 ? level : tex[ATLAS_TEMP]);
            glActiveTexture(GL_TEXTURE1);
            glBindTexture(GL_TEXTURE_2D, level);
            glActiveTexture(GL_TEXTURE0);
            glBindImageTexture(SAM_IMAGE_TARGET, pass == 0 ? tex[ATLAS_TEMP] : next, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
            /* Every texel, listing those whose taps leave their chart; then
             * those alone (tsd_blur.comp). */
            static const GLuint empty[4] = {0, 1, 1, 0};
            glBufferSubData(GL_DISPATCH_INDIRECT_BUFFER, 0, sizeof empty, empty);
            set_blur(rt, rt->tsd.blur_program, sigma, size, pass);
            glDispatchCompute(groups, groups, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
            set_blur(rt, rt->tsd.blur_listed_program, sigma, size, pass);
            glDispatchComputeIndirect(0);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        }
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
        GLuint a = rt->tsd.accumulate_program;
        glUseProgram(a);
        float w[3];
        for (int c = 0; c < 3; ++c)
            w[c] = rt->total_reflectance[c] > 0 ? rt->fit.weight[g][c] / rt->total_reflectance[c] : 0.0f;
        glUniform3fv(glGetUniformLocation(a, "u_weight"), 1, w);
        glUniform1i(glGetUniformLocation(a, "u_first"), g == 0);
        glUniform2iv(glGetUniformLocation(a, "u_size"), 1, size);
        glBindImageTexture(SAM_IMAGE_SOURCE, next, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(SAM_IMAGE_TARGET, tex[ATLAS_SUM], 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        glDispatchCompute(groups, groups, 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        level = next;
    }
    rt->tsd.atlas_used = side;
    return SAM_OK;
}

sam_status sam_runtime_read_atlas(sam_runtime *rt, sam_atlas_map map, sam_image *out, sam_error *err)
{
    memset(out, 0, sizeof *out);
    static const int which[3] = {ATLAS_IRRADIANCE, ATLAS_STRETCH, ATLAS_SUM};
    if (!rt->tsd.atlas_used || (unsigned)map > SAM_ATLAS_DIFFUSED)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        rt->tsd.atlas_used ? "read_atlas: unknown map %d" : "read_atlas: no texture-space render yet (map %d)",
                        (int)map);
    /* Row v of the image is texel row v (v = 0 at the bottom of UV space). */
    return sam_runtime_read_texture(rt->tsd.atlas_tex[which[map]], rt->tsd.atlas_allocated, rt->tsd.atlas_allocated,
                                     rt->tsd.atlas_used, rt->tsd.atlas_used, 0, out, err);
}
