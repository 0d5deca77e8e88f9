/* A .sam as GPU buffers, the SAM passes, and shading. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_mesh.h"
#include "sam/sam_preint.h"
#include "sam/sam_uv.h"
#include "sam_runtime_internal.h"

/* std430 image of lights.glsl's Light. */
typedef struct gpu_light {
    float color_type[4], position[4], direction[4], params[4], normal[4], vertices[8][4];
} gpu_light;

float sam_runtime_smoothing_alpha(float dt)
{
    /* eq. 18: alpha = 1 - (1e-10)^dt = 1 - exp(dt ln 1e-10) */
    return (float)-expm1((double)dt * log(1e-10));
}

static sam_status upload(sam_runtime *rt, int binding, const void *data, size_t bytes, sam_error *err)
{
    GLint limit = 0;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &limit);
    if (bytes > (size_t)limit)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "runtime: buffer %d needs %zu bytes but the GL allows %d per storage block", binding, bytes,
                        limit);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[binding]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(bytes ? bytes : 16), data, GL_DYNAMIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)binding, rt->buffer[binding]);
    return glGetError() == GL_NO_ERROR
               ? SAM_OK
               : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not allocate %zu bytes", bytes);
}

/* vec4 per vertex from 3 floats per vertex. */
static float *widen(const float *xyz, uint32_t count, float w)
{
    float *out = malloc((size_t)count * 4 * sizeof *out);
    if (out)
        for (uint32_t v = 0; v < count; ++v) {
            memcpy(out + 4 * (size_t)v, xyz + 3 * (size_t)v, 3 * sizeof(float));
            out[4 * (size_t)v + 3] = w;
        }
    return out;
}

static void set_profile_uniforms(GLuint program, const sam_profile *p)
{
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "u_profile_kind"), p->kind == SAM_PROFILE_DIPOLE ? 1 : 0);
    if (p->kind == SAM_PROFILE_DIPOLE) {
        sam_dipole_terms t;
        sam_profile_dipole_terms(p, &t);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_alpha"), 1, t.alpha);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_sigma_tr"), 1, t.sigma_tr);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_zr"), 1, t.z_r);
        glUniform3fv(glGetUniformLocation(program, "u_dipole_zv"), 1, t.z_v);
    } else {
        float g[SAM_PROFILE_MAX_GAUSSIANS][4];
        for (uint32_t i = 0; i < p->gaussian_count; ++i) {
            memcpy(g[i], p->weight[i], 3 * sizeof(float));
            g[i][3] = p->variance[i];
        }
        glUniform1i(glGetUniformLocation(program, "u_gaussian_count"), (GLint)p->gaussian_count);
        glUniform4fv(glGetUniformLocation(program, "u_gaussians"), (GLsizei)p->gaussian_count, &g[0][0]);
    }
}

static void release_view_targets(sam_runtime *rt)
{
    if (rt->view_fbo) {
        glDeleteFramebuffers(1, &rt->view_fbo);
        glDeleteTextures(5, rt->view_tex);
        glDeleteRenderbuffers(1, &rt->view_depth);
    }
    rt->view_fbo = rt->view_depth = 0;
    memset(rt->view_tex, 0, sizeof rt->view_tex);
    rt->view_width = rt->view_height = 0;
}

/* The view-sized targets of sam_runtime_render, kept between renders of
 * one size: 0 colour (or entering light + depth), 1 factor, 2 specular,
 * 3 and 4 the blur's ping-pong and the composed result; and depth. */
static sam_status ensure_view_targets(sam_runtime *rt, uint32_t width, uint32_t height, sam_error *err)
{
    if (rt->view_fbo && rt->view_width == width && rt->view_height == height)
        return SAM_OK;
    release_view_targets(rt);
    glGenFramebuffers(1, &rt->view_fbo);
    glGenTextures(5, rt->view_tex);
    glGenRenderbuffers(1, &rt->view_depth);
    for (int i = 0; i < 5; ++i) {
        glBindTexture(GL_TEXTURE_2D, rt->view_tex[i]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, (GLsizei)width, (GLsizei)height);
    }
    glBindRenderbuffer(GL_RENDERBUFFER, rt->view_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, (GLsizei)width, (GLsizei)height);
    glBindFramebuffer(GL_FRAMEBUFFER, rt->view_fbo);
    for (int i = 0; i < 3; ++i)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, rt->view_tex[i], 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rt->view_depth);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        release_view_targets(rt);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "render: framebuffer incomplete (0x%04x) at %ux%u", status, width,
                        height);
    }
    rt->view_width = width;
    rt->view_height = height;
    return SAM_OK;
}

/* The bounds every range is taken from (shadow maps, automatic near and far
 * planes, depth-sized atlases): the box and the sphere around it. */
static void set_box(sam_runtime *rt, const float lo[3], const float hi[3])
{
    double r2 = 0;
    for (int c = 0; c < 3; ++c) {
        rt->centre[c] = 0.5f * (lo[c] + hi[c]);
        r2 += 0.25 * ((double)hi[c] - lo[c]) * ((double)hi[c] - lo[c]);
    }
    rt->radius = (float)sqrt(r2);
    memcpy(rt->box_lo, lo, 3 * sizeof(float));
    memcpy(rt->box_hi, hi, 3 * sizeof(float));
}

sam_status sam_runtime_create(const samfile_data *sam, const sam_profile *profile, float mm_per_unit,
                              sam_runtime **out, sam_error *err)
{
    *out = NULL;
    if (!sam || !profile || !(mm_per_unit > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: no .sam, no profile or a scale <= 0");
    sam_runtime *rt = calloc(1, sizeof *rt);
    if (!rt)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    rt->vertex_count = sam->vertex_count;
    rt->stride = sam->samples_per_vertex;
    rt->mm_per_unit = mm_per_unit;
    rt->profile = *profile;
    glGenBuffers(B_COUNT, rt->buffer);
    glGenQueries(SAM_PASS_COUNT, rt->query);
    const size_t nv = sam->vertex_count, n = sam->samples_per_vertex;
    float *pos = widen(sam->positions, sam->vertex_count, 1.0f), *nrm = widen(sam->normals, sam->vertex_count, 0.0f);
    /* Samples interleave the index with its K' (the index's bits stored as a float slot). */
    uint32_t *samples = malloc(nv * n * 4 * sizeof *samples);
    float *zero = calloc(nv * 4, sizeof *zero);
    sam_status st = SAM_OK;
    if (!pos || !nrm || !samples || !zero) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu vertices", nv);
        goto done;
    }
    for (size_t i = 0; i < nv * n; ++i) {
        samples[4 * i] = sam->sample_index[i];
        memcpy(samples + 4 * i + 1, sam->sample_kprime + 3 * i, 3 * sizeof(float));
    }
    if ((st = upload(rt, B_POSITIONS, pos, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = upload(rt, B_NORMALS, nrm, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = upload(rt, B_SAMPLES, samples, nv * n * 4 * sizeof(uint32_t), err)) != SAM_OK ||
        (st = upload(rt, B_FAN_AREAS, sam->fan_area, nv * sizeof(float), err)) != SAM_OK ||
        (st = upload(rt, B_IRRADIANCE, zero, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = upload(rt, B_TRANSLUCENCY, zero, nv * 4 * sizeof(float), err)) != SAM_OK ||
        (st = upload(rt, B_ADJ_OFFSETS, sam->adjacency_offsets, (nv + 1) * sizeof(uint32_t), err)) != SAM_OK ||
        (st = upload(rt, B_ADJACENCY, sam->adjacency, (size_t)sam->adjacency_count * sizeof(uint32_t), err)) !=
            SAM_OK ||
        (st = upload(rt, B_TRIANGLES, sam->triangles, (size_t)sam->triangle_count * 3 * sizeof(uint32_t), err)) !=
            SAM_OK)
        goto done;
    rt->triangle_count = sam->triangle_count;
    {
        /* Mean curvature in 1/mm from the .sam's own rings. */
        float *curvature = malloc(nv * sizeof *curvature);
        if (!curvature) {
            st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
            goto done;
        }
        sam_mesh_ring_curvature(sam->vertex_count, sam->positions, NULL, sam->normals, sam->adjacency_offsets,
                                sam->adjacency, curvature);
        for (size_t v = 0; v < nv; ++v)
            curvature[v] /= mm_per_unit;
        st = upload(rt, B_CURVATURE, curvature, nv * sizeof *curvature, err);
        free(curvature);
        if (st != SAM_OK)
            goto done;
    }
    {
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t v = 0; v < nv; ++v)
            for (int c = 0; c < 3; ++c) {
                lo[c] = fminf(lo[c], sam->positions[3 * v + c]);
                hi[c] = fmaxf(hi[c], sam->positions[3 * v + c]);
            }
        memcpy(rt->rest_box_lo, lo, sizeof lo);
        memcpy(rt->rest_box_hi, hi, sizeof hi);
        set_box(rt, lo, hi);
        double area = 0;
        for (size_t t = 0; t < sam->triangle_count; ++t) {
            const float *a = sam->positions + 3 * (size_t)sam->triangles[3 * t],
                        *b = sam->positions + 3 * (size_t)sam->triangles[3 * t + 1],
                        *c = sam->positions + 3 * (size_t)sam->triangles[3 * t + 2];
            double e1[3], e2[3];
            for (int k = 0; k < 3; ++k) {
                e1[k] = (double)b[k] - a[k];
                e2[k] = (double)c[k] - a[k];
            }
            double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
                   z = e1[0] * e2[1] - e1[1] * e2[0];
            area += 0.5 * sqrt(x * x + y * y + z * z);
        }
        rt->surface_area = (float)area;
    }
    glGenVertexArrays(1, &rt->vao);
    glBindVertexArray(rt->vao);
    glBindBuffer(GL_ARRAY_BUFFER, rt->buffer[B_POSITIONS]);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), NULL);
    glBindBuffer(GL_ARRAY_BUFFER, rt->buffer[B_NORMALS]);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), NULL);
    if (sam->uvs) {
        rt->has_uvs = 1;
        /* Texture-space diffusion needs charts inside [0, 1]^2 that do not
         * overlap: mirrored islands would sum two places' light in one texel. */
        sam_uv_report report;
        if ((st = sam_uv_check(sam->uvs, sam->vertex_count, sam->triangles, sam->triangle_count, 1024, &report,
                               err)) != SAM_OK)
            goto done;
        rt->uv_usable = sam_uv_usable(&report, rt->uv_reason, sizeof rt->uv_reason);
        rt->uv_coverage = report.resolution ? (float)((double)report.covered_texels /
                                                      ((double)report.resolution * report.resolution))
                                            : 0.0f;
        if ((st = upload(rt, B_UVS, sam->uvs, nv * 2 * sizeof(float), err)) != SAM_OK)
            goto done;
        glBindBuffer(GL_ARRAY_BUFFER, rt->buffer[B_UVS]);
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), NULL);
    } else {
        snprintf(rt->uv_reason, sizeof rt->uv_reason, "the mesh has no UVs");
        glVertexAttrib2f(2, 0.0f, 0.0f);
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, rt->buffer[B_TRIANGLES]);
    glBindVertexArray(0);
    glGenFramebuffers(1, &rt->fbo);
    if ((st = sam_gl_render_program("shadow.vert", "shadow.frag", NULL, &rt->shadow_program, err)) != SAM_OK ||
        (st = sam_gl_render_program("shade.vert", "shade.frag", NULL, &rt->shade_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("sss_blur.comp", NULL, &rt->blur_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("sss_compose.comp", NULL, &rt->compose_program, err)) != SAM_OK ||
        (st = sam_gl_render_program("tsd_irradiance.vert", "tsd_irradiance.frag", NULL, &rt->tsd_program, err)) !=
            SAM_OK ||
        (st = sam_gl_compute_program("tsd_blur.comp", NULL, &rt->tsd_blur_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("tsd_accumulate.comp", NULL, &rt->tsd_accumulate_program, err)) != SAM_OK ||
        (st = sam_gl_render_program("tsm.vert", "tsm.frag", NULL, &rt->tsm_program, err)) != SAM_OK ||
        (st = sam_profile_fit_gaussians(profile, &rt->fit, err)) != SAM_OK)
        goto done;
    sam_profile_total_reflectance(profile, rt->total_reflectance);
    glGenSamplers(1, &rt->distance_sampler);
    glSamplerParameteri(rt->distance_sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(rt->distance_sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(rt->distance_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(rt->distance_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(rt->distance_sampler, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(rt->distance_sampler, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    if ((st = sam_brdf_rho_dt_table(RHO_SIZE, RHO_SIZE, SKIN_F0, SAM_BRDF_ROUGHNESS_MAX, rt->rho_table, err)) !=
            SAM_OK ||
        (st = upload(rt, B_RHO_DT, rt->rho_table, sizeof rt->rho_table, err)) != SAM_OK ||
        (st = upload(rt, B_LIGHTS, NULL, sizeof(gpu_light), err)) != SAM_OK)
        goto done;
    if ((st = sam_gl_compute_program("translucency.comp", NULL, &rt->translucency_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("translucency.comp", "#define SAM_POSED 1\n", &rt->translucency_posed_program,
                                     err)) != SAM_OK ||
        (st = sam_gl_compute_program("translucency.comp", "#define SAM_POSED 1\n#define SAM_POSED_EQ15 1\n",
                                     &rt->translucency_eq15_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("irradiance.comp", NULL, &rt->irradiance_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("deform.comp", NULL, &rt->deform_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("deform_normals.comp", NULL, &rt->deform_normals_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("walk.comp", NULL, &rt->walk_program, err)) != SAM_OK)
        goto done;
    set_profile_uniforms(rt->translucency_program, profile);
    set_profile_uniforms(rt->translucency_posed_program, profile);
    set_profile_uniforms(rt->translucency_eq15_program, profile);
    set_profile_uniforms(rt->walk_program, profile);
    if ((st = sam_runtime_set_surface(rt, 0.3f, 0.18f, err)) != SAM_OK)
        goto done;
done:
    free(pos);
    free(nrm);
    free(samples);
    free(zero);
    if (st != SAM_OK) {
        sam_runtime_destroy(rt);
        return st;
    }
    *out = rt;
    return SAM_OK;
}

void sam_runtime_destroy(sam_runtime *rt)
{
    if (!rt)
        return;
    glDeleteBuffers(B_COUNT, rt->buffer);
    glDeleteQueries(SAM_PASS_COUNT, rt->query);
    if (rt->translucency_program)
        glDeleteProgram(rt->translucency_program);
    if (rt->translucency_posed_program)
        glDeleteProgram(rt->translucency_posed_program);
    if (rt->translucency_eq15_program)
        glDeleteProgram(rt->translucency_eq15_program);
    if (rt->irradiance_program)
        glDeleteProgram(rt->irradiance_program);
    if (rt->deform_program)
        glDeleteProgram(rt->deform_program);
    if (rt->deform_normals_program)
        glDeleteProgram(rt->deform_normals_program);
    if (rt->walk_program)
        glDeleteProgram(rt->walk_program);
    if (rt->rest_buffer[0])
        glDeleteBuffers(REST_COUNT, rt->rest_buffer);
    if (rt->bounds_buffer)
        glDeleteBuffers(1, &rt->bounds_buffer);
    if (rt->keyframe_buffer)
        glDeleteBuffers(1, &rt->keyframe_buffer);
    free(rt->keyframe_times);
    if (rt->shadow_program)
        glDeleteProgram(rt->shadow_program);
    if (rt->shade_program)
        glDeleteProgram(rt->shade_program);
    if (rt->blur_program)
        glDeleteProgram(rt->blur_program);
    if (rt->compose_program)
        glDeleteProgram(rt->compose_program);
    if (rt->tsd_program)
        glDeleteProgram(rt->tsd_program);
    if (rt->tsd_blur_program)
        glDeleteProgram(rt->tsd_blur_program);
    if (rt->tsd_accumulate_program)
        glDeleteProgram(rt->tsd_accumulate_program);
    if (rt->tsm_program)
        glDeleteProgram(rt->tsm_program);
    sam_runtime_tsm_destroy(rt);
    if (rt->distance_sampler)
        glDeleteSamplers(1, &rt->distance_sampler);
    glDeleteVertexArrays(1, &rt->vao);
    glDeleteFramebuffers(1, &rt->fbo);
    sam_runtime_texture_space_destroy(rt);
    if (rt->tsd_fbo)
        glDeleteFramebuffers(1, &rt->tsd_fbo);
    if (rt->albedo_tex)
        glDeleteTextures(1, &rt->albedo_tex);
    release_view_targets(rt);
    glDeleteTextures(MAX_CUBE_SHADOWS, rt->cube_tex);
    glDeleteTextures(MAX_FLAT_SHADOWS, rt->flat_tex);
    free(rt->lights);
    free(rt);
}

uint32_t sam_runtime_vertex_count(const sam_runtime *rt)
{
    return rt->vertex_count;
}

uint32_t sam_runtime_samples_per_vertex(const sam_runtime *rt)
{
    return rt->stride;
}

/* Point and area lights cast all round: a cube map; spot and directional
 * lights a flat one. */
static int cube_shadowed(const sam_light *l)
{
    return l->type == SAM_LIGHT_POINT || l->type == SAM_LIGHT_AREA;
}

sam_status sam_runtime_set_lights(sam_runtime *rt, const sam_light *lights, size_t count, sam_error *err)
{
    if (count > SAM_SCENE_MAX_LIGHTS || (count && !lights))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu lights (at most %d)", count,
                        SAM_SCENE_MAX_LIGHTS);
    uint32_t cubes = 0, flats = 0;
    for (size_t i = 0; i < count; ++i) {
        if (!lights[i].shadow)
            continue;
        if (cube_shadowed(&lights[i]))
            cubes++;
        else
            flats++;
    }
    if (cubes > MAX_CUBE_SHADOWS || flats > MAX_FLAT_SHADOWS)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "runtime: %u shadowed point/area and %u shadowed spot/directional lights; at most %d of each "
                        "(turn \"shadow\" off for the others)",
                        cubes, flats, MAX_CUBE_SHADOWS);
    gpu_light *g = calloc(count ? count : 1, sizeof *g);
    sam_light *copy = malloc((count ? count : 1) * sizeof *copy);
    if (!g || !copy) {
        free(g);
        free(copy);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    }
    if (count)
        memcpy(copy, lights, count * sizeof *copy);
    free(rt->lights);
    rt->lights = copy;
    rt->cube_count = rt->flat_count = 0;
    const double deg = 3.14159265358979323846 / 180.0;
    for (size_t i = 0; i < count; ++i) {
        const sam_light *l = &lights[i];
        for (int c = 0; c < 3; ++c) {
            g[i].color_type[c] = l->color[c] * l->intensity;
            g[i].position[c] = l->position[c];
            g[i].direction[c] = l->direction[c];
            g[i].normal[c] = l->normal[c];
        }
        g[i].color_type[3] = (float)l->type;
        g[i].position[3] = (float)l->vertex_count;
        g[i].direction[3] = (float)cos(l->inner_angle_deg * deg);
        g[i].params[0] = (float)cos(l->outer_angle_deg * deg);
        g[i].params[1] = (float)l->two_sided;
        g[i].params[2] = -1.0f;
        if (l->shadow) {
            int cube = cube_shadowed(l);
            g[i].params[2] = (float)(cube ? rt->cube_count++ : rt->flat_count++);
            g[i].params[3] = (float)cube;
        }
        for (uint32_t k = 0; k < l->vertex_count && k < SAM_AREA_LIGHT_MAX_VERTICES; ++k)
            memcpy(g[i].vertices[k], l->vertices[k], 3 * sizeof(float));
    }
    sam_status st = upload(rt, B_LIGHTS, g, (count ? count : 1) * sizeof *g, err);
    free(g);
    if (st == SAM_OK)
        rt->light_count = (uint32_t)count;
    return st;
}

void sam_runtime_set_environment(sam_runtime *rt, const float sh[9][3])
{
    rt->has_environment = sh != NULL;
    if (sh)
        memcpy(rt->sh, sh, sizeof rt->sh);
}

float sam_runtime_rho_dt(const sam_runtime *rt, float n_dot_l)
{
    float table = sam_brdf_rho_dt_table_lookup(rt->rho_table, RHO_SIZE, RHO_SIZE, SAM_BRDF_ROUGHNESS_MAX, n_dot_l,
                                               rt->roughness);
    return 1.0f - (float)(3.14159265358979323846 * rt->rho_s) * (1.0f - table);
}

float sam_runtime_environment_rho_dt(const sam_runtime *rt)
{
    return rt->environment_rho_dt;
}

sam_status sam_runtime_set_surface(sam_runtime *rt, float roughness, float rho_s, sam_error *err)
{
    if (!(roughness > 0 && roughness <= SAM_BRDF_ROUGHNESS_MAX) || !(rho_s >= 0 && rho_s <= 1))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: roughness must be in (0, %g] and rho_s in [0, 1], got %g and %g",
                        SAM_BRDF_ROUGHNESS_MAX, roughness, rho_s);
    rt->roughness = roughness;
    rt->rho_s = rho_s;
    /* Uniform light from the hemisphere enters as 2 int_0^1 rho_dt(mu) mu dmu. */
    double sum = 0;
    const int steps = 256;
    for (int i = 0; i < steps; ++i) {
        double mu = (i + 0.5) / steps;
        sum += sam_runtime_rho_dt(rt, (float)mu) * mu;
    }
    rt->environment_rho_dt = (float)(2.0 * sum / steps);
    return SAM_OK;
}

static GLuint shadow_texture(GLenum target, GLsizei size)
{
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(target, tex);
    if (target == GL_TEXTURE_CUBE_MAP)
        for (int f = 0; f < 6; ++f)
            glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f, 0, GL_DEPTH_COMPONENT32F, size, size, 0,
                         GL_DEPTH_COMPONENT, GL_FLOAT, NULL);
    else
        glTexImage2D(target, 0, GL_DEPTH_COMPONENT32F, size, size, 0, GL_DEPTH_COMPONENT, GL_FLOAT, NULL);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(target, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return tex;
}

static void draw_depth(sam_runtime *rt, GLenum attach_target, GLuint tex, GLsizei size, sam_mat4 view_proj,
                       int distance, const float light[3], float far_plane)
{
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, attach_target, tex, 0);
    glViewport(0, 0, size, size);
    glClear(GL_DEPTH_BUFFER_BIT);
    GLuint p = rt->shadow_program;
    sam_mat4 identity = sam_mat4_identity();
    glUniformMatrix4fv(glGetUniformLocation(p, "u_model"), 1, GL_FALSE, identity.m);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_proj"), 1, GL_FALSE, view_proj.m);
    glUniform1i(glGetUniformLocation(p, "u_distance"), distance);
    glUniform3fv(glGetUniformLocation(p, "u_light"), 1, light);
    glUniform1f(glGetUniformLocation(p, "u_far"), far_plane);
    glDrawElements(GL_TRIANGLES, (GLsizei)rt->triangle_count * 3, GL_UNSIGNED_INT, NULL);
}

sam_mat4 sam_runtime_cube_face(const float origin[3], float far_plane, int face)
{
    static const float face_dir[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const float face_up[6][3] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
    float target[3] = {origin[0] + face_dir[face][0], origin[1] + face_dir[face][1], origin[2] + face_dir[face][2]};
    return sam_mat4_mul(sam_mat4_perspective(3.14159265f / 2, 1.0f, 1e-4f * far_plane, far_plane),
                        sam_mat4_look_at(origin, target, face_up[face]));
}

/* Renders every shadowed light's map from the current positions. */
static void render_shadows(sam_runtime *rt)
{
    if (!rt->cube_count && !rt->flat_count)
        return;
    glBindFramebuffer(GL_FRAMEBUFFER, rt->fbo);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(rt->vao);
    glUseProgram(rt->shadow_program);
    for (sam_runtime_shadow s = {0}; sam_runtime_next_shadow(rt, &s);) {
        const sam_light *l = &rt->lights[s.light];
        if (s.cube) {
            uint32_t cube = s.map;
            float o[3];
            memcpy(o, l->position, sizeof o);
            if (l->type == SAM_LIGHT_AREA) {
                o[0] = o[1] = o[2] = 0;
                for (uint32_t k = 0; k < l->vertex_count; ++k)
                    for (int c = 0; c < 3; ++c)
                        o[c] += l->vertices[k][c] / (float)l->vertex_count;
            }
            float dc = sqrtf((o[0] - rt->centre[0]) * (o[0] - rt->centre[0]) +
                             (o[1] - rt->centre[1]) * (o[1] - rt->centre[1]) +
                             (o[2] - rt->centre[2]) * (o[2] - rt->centre[2]));
            float far_plane = 1.01f * (dc + rt->radius);
            if (!rt->cube_tex[cube])
                rt->cube_tex[cube] = shadow_texture(GL_TEXTURE_CUBE_MAP, CUBE_SHADOW_SIZE);
            for (int f = 0; f < 6; ++f)
                draw_depth(rt, GL_TEXTURE_CUBE_MAP_POSITIVE_X + (GLenum)f, rt->cube_tex[cube], CUBE_SHADOW_SIZE,
                           sam_runtime_cube_face(o, far_plane, f), 1, o, far_plane);
            memcpy(rt->cube_origin[cube], o, sizeof o);
            rt->cube_far[cube] = far_plane;
        } else {
            uint32_t flat = s.map;
            const float *d = l->direction;
            float up[3] = {0, 1, 0};
            if (fabsf(d[1]) > 0.9f)
                up[0] = 1, up[1] = 0;
            sam_mat4 vp;
            float far_plane = 0.0f;
            if (l->type == SAM_LIGHT_SPOT) {
                float dc = sqrtf((l->position[0] - rt->centre[0]) * (l->position[0] - rt->centre[0]) +
                                 (l->position[1] - rt->centre[1]) * (l->position[1] - rt->centre[1]) +
                                 (l->position[2] - rt->centre[2]) * (l->position[2] - rt->centre[2]));
                far_plane = 1.01f * (dc + rt->radius);
                float fov = fminf(2.0f * l->outer_angle_deg, 170.0f) * 3.14159265f / 180.0f;
                float target[3] = {l->position[0] + d[0], l->position[1] + d[1], l->position[2] + d[2]};
                vp = sam_mat4_mul(sam_mat4_perspective(fov, 1.0f, 1e-3f * far_plane, far_plane),
                                  sam_mat4_look_at(l->position, target, up));
            } else {
                float r = 1.01f * rt->radius;
                float eye[3] = {rt->centre[0] - d[0] * 2 * r, rt->centre[1] - d[1] * 2 * r,
                                rt->centre[2] - d[2] * 2 * r};
                vp = sam_mat4_mul(sam_mat4_ortho(-r, r, -r, r, 0.0f, 4 * r), sam_mat4_look_at(eye, rt->centre, up));
                rt->flat_range[flat] = 4 * r;
            }
            if (!rt->flat_tex[flat])
                rt->flat_tex[flat] = shadow_texture(GL_TEXTURE_2D, FLAT_SHADOW_SIZE);
            /* A spot map stores distance / far like a cube map: projected
             * depth crowds near 1 and leaves no room for a bias. */
            draw_depth(rt, GL_TEXTURE_2D, rt->flat_tex[flat], FLAT_SHADOW_SIZE, vp, far_plane > 0, l->position,
                       far_plane);
            rt->flat_matrix[flat] = vp;
            memcpy(rt->flat_origin[flat], l->position, sizeof rt->flat_origin[flat]);
            rt->flat_far[flat] = far_plane;
        }
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

int sam_runtime_next_shadow(const sam_runtime *rt, sam_runtime_shadow *s)
{
    for (; s->next < rt->light_count; ++s->next) {
        const sam_light *l = &rt->lights[s->next];
        if (!l->shadow)
            continue;
        s->light = s->next++;
        s->cube = cube_shadowed(l);
        s->map = s->cube ? s->cubes++ : s->flats++;
        return 1;
    }
    return 0;
}

void sam_runtime_bind_shadows(const sam_runtime *rt, GLuint p)
{
    /* Every sampler gets a unit of its own type, used or not: GL rejects
     * two sampler types on one unit. */
    for (int i = 0; i < MAX_CUBE_SHADOWS; ++i) {
        char name[32];
        glActiveTexture(GL_TEXTURE0 + (GLenum)i);
        glBindTexture(GL_TEXTURE_CUBE_MAP, rt->cube_tex[i]);
        snprintf(name, sizeof name, "u_cube_shadow[%d]", i);
        glUniform1i(glGetUniformLocation(p, name), i);
    }
    for (int i = 0; i < MAX_FLAT_SHADOWS; ++i) {
        char name[32];
        glActiveTexture(GL_TEXTURE0 + MAX_CUBE_SHADOWS + (GLenum)i);
        glBindTexture(GL_TEXTURE_2D, rt->flat_tex[i]);
        snprintf(name, sizeof name, "u_flat_shadow[%d]", i);
        glUniform1i(glGetUniformLocation(p, name), MAX_CUBE_SHADOWS + i);
    }
    glActiveTexture(GL_TEXTURE0);
    glUniform1fv(glGetUniformLocation(p, "u_cube_far"), MAX_CUBE_SHADOWS, rt->cube_far);
    glUniform3fv(glGetUniformLocation(p, "u_cube_origin"), MAX_CUBE_SHADOWS, &rt->cube_origin[0][0]);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_flat_matrix"), MAX_FLAT_SHADOWS, GL_FALSE, rt->flat_matrix[0].m);
    glUniform3fv(glGetUniformLocation(p, "u_flat_origin"), MAX_FLAT_SHADOWS, &rt->flat_origin[0][0]);
    glUniform1fv(glGetUniformLocation(p, "u_flat_far"), MAX_FLAT_SHADOWS, rt->flat_far);
    glUniform1f(glGetUniformLocation(p, "u_normal_offset"), 0.01f * rt->radius);
    glUniform1f(glGetUniformLocation(p, "u_depth_bias"), 0.002f);
}

/* The uniforms of surface.glsl, which the irradiance and shading passes share. */
static void set_surface_uniforms(const sam_runtime *rt, GLuint p)
{
    glUniform1i(glGetUniformLocation(p, "u_rho_size"), RHO_SIZE);
    glUniform1f(glGetUniformLocation(p, "u_roughness_coord"), rt->roughness / SAM_BRDF_ROUGHNESS_MAX);
    glUniform1f(glGetUniformLocation(p, "u_specular_k"), (float)(3.14159265358979323846 * rt->rho_s));
    glUniform3fv(glGetUniformLocation(p, "u_sh"), 9, &rt->sh[0][0]);
    glUniform1i(glGetUniformLocation(p, "u_has_environment"), rt->has_environment);
    glUniform1f(glGetUniformLocation(p, "u_environment_rho_dt"), rt->environment_rho_dt);
}

/* The bound compute program once per vertex (groups of 64), timed as
 * `pass`, its storage writes made visible to later passes and read-backs. */
static void dispatch_per_vertex(sam_runtime *rt, sam_pass pass)
{
    glBeginQuery(GL_TIME_ELAPSED, rt->query[pass]);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    glEndQuery(GL_TIME_ELAPSED);
    rt->query_used[pass] = 1;
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

sam_status sam_runtime_irradiance(sam_runtime *rt, sam_error *err)
{
    (void)err;
    render_shadows(rt);
    GLuint p = rt->irradiance_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_light_count"), rt->light_count);
    set_surface_uniforms(rt, p);
    sam_runtime_bind_shadows(rt, p);
    for (int b = 0; b < B_COUNT; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
    dispatch_per_vertex(rt, SAM_PASS_IRRADIANCE);
    return SAM_OK;
}

void sam_runtime_bounds(const sam_runtime *rt, float centre[3], float *radius)
{
    memcpy(centre, rt->centre, 3 * sizeof(float));
    *radius = rt->radius;
}

/* Builds and uploads the pre-integrated tables on first use (about 0.3 s). */
static sam_status ensure_preintegrated(sam_runtime *rt, sam_error *err)
{
    if (rt->preint_ready)
        return SAM_OK;
    float *table = malloc(PRE_SIZE * PRE_SIZE * 3 * sizeof *table);
    if (!table)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    sam_status st = sam_preint_diffuse_table(&rt->profile, PRE_SIZE, PRE_SIZE, PRE_MAX_CURVATURE, table, err);
    if (st == SAM_OK)
        st = upload(rt, B_PRE_DIFFUSE, table, PRE_SIZE * PRE_SIZE * 3 * sizeof *table, err);
    if (st == SAM_OK)
        st = sam_preint_penumbra_table(&rt->profile, PRE_SIZE, PRE_SIZE, PRE_MAX_PENUMBRA_MM, table, err);
    if (st == SAM_OK)
        st = upload(rt, B_PRE_PENUMBRA, table, PRE_SIZE * PRE_SIZE * 3 * sizeof *table, err);
    free(table);
    rt->min_penumbra_mm = fminf(sam_profile_radius(&rt->profile, 0.01f), PRE_MAX_PENUMBRA_MM);
    rt->preint_ready = st == SAM_OK;
    return st;
}

/* The screen-space kernel of the given fit and taps, made on first use. */
static sam_status ensure_kernel(sam_runtime *rt, sam_sss_kernel kind, uint32_t taps, sam_error *err)
{
    if (rt->kernel.taps == taps && rt->kernel_kind == kind)
        return SAM_OK;
    sam_status st = kind == SAM_SSS_KERNEL_EQ1        ? sam_profile_separable_kernel(&rt->profile, taps, &rt->kernel, err)
                    : kind == SAM_SSS_KERNEL_MARGINAL ? sam_profile_separable_kernel_direct(&rt->profile, taps,
                                                                                            &rt->kernel, err)
                                                      : sam_profile_separable_kernel_fit2d(&rt->profile, taps,
                                                                                           &rt->kernel, err);
    rt->kernel_kind = kind;
    if (st != SAM_OK)
        rt->kernel.taps = 0;
    return st;
}

int sam_runtime_uv_status(const sam_runtime *rt, char *reason, size_t n)
{
    if (reason && n)
        snprintf(reason, n, "%s", rt->uv_usable ? "" : rt->uv_reason);
    return rt->uv_usable;
}

sam_status sam_runtime_set_albedo_map(sam_runtime *rt, const sam_image *map, sam_error *err)
{
    if (map && !rt->has_uvs)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "runtime: an albedo map needs UVs and this mesh has none");
    GLint limit = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &limit);
    if (map && (map->channels < 3 || !map->width || !map->height || map->width > (uint32_t)limit ||
                map->height > (uint32_t)limit))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: albedo map %ux%u with %u channels; need 3 or 4 channels and at most %d texels a side",
                        map->width, map->height, map->channels, limit);
    if (rt->albedo_tex)
        glDeleteTextures(1, &rt->albedo_tex);
    rt->albedo_tex = 0;
    if (!map)
        return SAM_OK;
    GLsizei levels = 1;
    for (uint32_t side = map->width > map->height ? map->width : map->height; side > 1; side /= 2)
        levels++;
    /* Image rows run top-down and UV's v up. */
    rt->albedo_tex = sam_runtime_image_texture(map, levels, 1);
    if (!rt->albedo_tex)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not store a %ux%u albedo map",
                        map->width, map->height);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    return SAM_OK;
}

GLuint sam_runtime_image_texture(const sam_image *image, GLsizei levels, int flip)
{
    while (glGetError() != GL_NO_ERROR) {
    }
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, levels, GL_RGBA32F, (GLsizei)image->width, (GLsizei)image->height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    GLenum format = image->channels == 4 ? GL_RGBA : GL_RGB;
    for (uint32_t y = 0; y < image->height; ++y)
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, (GLint)(flip ? image->height - 1 - y : y), (GLsizei)image->width, 1,
                        format, GL_FLOAT, image->pixels + (size_t)y * image->width * image->channels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteTextures(1, &tex);
        return 0;
    }
    return tex;
}

sam_status sam_runtime_read_texture(GLuint tex, uint32_t full_width, uint32_t full_height, uint32_t w, uint32_t h,
                                    int flip, sam_image *out, sam_error *err)
{
    sam_image whole;
    sam_status st = sam_image_create(&whole, full_width, full_height, 4, err);
    if (st != SAM_OK)
        return st;
    if ((st = sam_image_create(out, w, h, 4, err)) != SAM_OK) {
        sam_image_destroy(&whole);
        return st;
    }
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, whole.pixels);
    for (uint32_t y = 0; y < h; ++y)
        memcpy(out->pixels + (size_t)(flip ? h - 1 - y : y) * w * 4, whole.pixels + (size_t)y * full_width * 4,
               (size_t)w * 4 * sizeof(float));
    sam_image_destroy(&whole);
    return SAM_OK;
}

void sam_runtime_bind_albedo(const sam_runtime *rt, GLuint p)
{
    glActiveTexture(GL_TEXTURE0 + UNIT_ALBEDO);
    glBindTexture(GL_TEXTURE_2D, rt->albedo_tex);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_albedo_map"), UNIT_ALBEDO);
    glUniform1i(glGetUniformLocation(p, "u_has_albedo_map"), rt->albedo_tex != 0);
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
    if ((unsigned)view->technique > SAM_TECHNIQUE_TRANSMITTANCE)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "render: unknown technique %d", (int)view->technique);
    int tsm = view->technique == SAM_TECHNIQUE_TSM && !view->translucency;
    if (tsm && view->diffusion != 3)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "render: the tsm technique needs texture-space diffusion (diffusion 3) and usable UVs; "
                        "got diffusion %d",
                        view->diffusion);
    if (view->diffusion == 3 && !rt->uv_usable)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "render: texture-space diffusion%s cannot run: %s",
                        tsm ? " (which tsm needs)" : "", rt->uv_reason);
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

/* Two 1D passes of the separable kernel over the entering light (target
 * 0), then the composition with the factor and specular; into target 3. */
static void screen_space_diffusion(sam_runtime *rt, const sam_render_view *view)
{
    const GLuint *tex = rt->view_tex;
    GLuint gx = (view->width + 7) / 8, gy = (view->height + 7) / 8;
    GLuint b = rt->blur_program;
    glUseProgram(b);
    float offsets[SAM_KERNEL_MAX_TAPS];
    for (uint32_t k = 0; k < rt->kernel.taps; ++k)
        offsets[k] = rt->kernel.offset_mm[k];
    glUniform1i(glGetUniformLocation(b, "u_taps"), (GLint)rt->kernel.taps);
    glUniform1fv(glGetUniformLocation(b, "u_offset_mm"), (GLsizei)rt->kernel.taps, offsets);
    glUniform3fv(glGetUniformLocation(b, "u_weight"), (GLsizei)rt->kernel.taps, &rt->kernel.weight[0][0]);
    glUniform1f(glGetUniformLocation(b, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1f(glGetUniformLocation(b, "u_pixels_per_unit_at_depth_one"),
                (float)view->height / (2.0f * tanf(0.5f * view->fov_deg * 3.14159265f / 180.0f)));
    glUniform1f(glGetUniformLocation(b, "u_depth_jump"), rt->kernel.width_mm / rt->mm_per_unit);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    for (int pass = 0; pass < 2; ++pass) {
        glUniform2i(glGetUniformLocation(b, "u_direction"), pass == 0, pass == 1);
        glBindImageTexture(0, pass == 0 ? tex[0] : tex[3], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(1, pass == 0 ? tex[3] : tex[4], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(gx, gy, 1);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    glUseProgram(rt->compose_program);
    glBindImageTexture(0, tex[4], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, tex[1], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(2, tex[2], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(3, tex[3], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(gx, gy, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

/* The camera of `view`: near and far from the object's bounds where 0. */
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
    glBindFramebuffer(GL_FRAMEBUFFER, rt->view_fbo);
    glDrawBuffers(3, attachments);
    glViewport(0, 0, (GLsizei)view->width, (GLsizei)view->height);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    GLuint p = rt->shade_program;
    int texture_space = view->diffusion == 3 && !gbuffer;
    glUseProgram(p);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_view_proj"), 1, GL_FALSE, vp->m);
    glUniform3fv(glGetUniformLocation(p, "u_eye"), 1, view->eye);
    glUniform3fv(glGetUniformLocation(p, "u_albedo"), 1, view->albedo);
    glUniform3fv(glGetUniformLocation(p, "u_total_reflectance"), 1, rt->total_reflectance);
    glUniform1i(glGetUniformLocation(p, "u_front"), view->front);
    glUniform1i(glGetUniformLocation(p, "u_gbuffer"), gbuffer);
    glUniform1f(glGetUniformLocation(p, "u_roughness"), rt->roughness);
    glUniform1f(glGetUniformLocation(p, "u_f0"), SKIN_F0);
    glUniform1ui(glGetUniformLocation(p, "u_light_count"), view->front ? rt->light_count : 0);
    glUniform1i(glGetUniformLocation(p, "u_split"), view->diffusion == 1);
    glUniform1i(glGetUniformLocation(p, "u_preintegrated"), view->diffusion == 2);
    glUniform1i(glGetUniformLocation(p, "u_texture_space"), texture_space);
    /* A TSM's atlas holds the front light even when the view shows none. */
    glUniform1i(glGetUniformLocation(p, "u_read_atlas"), !(tsm && !view->front));
    glUniform1i(glGetUniformLocation(p, "u_tsm"), tsm);
    glActiveTexture(GL_TEXTURE0 + UNIT_ATLAS);
    glBindTexture(GL_TEXTURE_2D, texture_space ? rt->atlas_tex[ATLAS_SUM] : 0);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_atlas"), UNIT_ATLAS);
    if (texture_space) {
        glUniform1f(glGetUniformLocation(p, "u_atlas_scale"), (float)rt->atlas_used / (float)rt->atlas_allocated);
        glUniform1f(glGetUniformLocation(p, "u_atlas_texel"), 1.0f / (float)rt->atlas_allocated);
    }
    sam_runtime_bind_albedo(rt, p);
    glUniform1i(glGetUniformLocation(p, "u_pre_size"), PRE_SIZE);
    glUniform1f(glGetUniformLocation(p, "u_pre_max_curvature"), PRE_MAX_CURVATURE);
    glUniform1f(glGetUniformLocation(p, "u_pre_max_penumbra"), PRE_MAX_PENUMBRA_MM);
    glUniform1f(glGetUniformLocation(p, "u_min_penumbra"), rt->min_penumbra_mm);
    float forward[3] = {view->target[0] - view->eye[0], view->target[1] - view->eye[1],
                        view->target[2] - view->eye[2]};
    float fl = sqrtf(forward[0] * forward[0] + forward[1] * forward[1] + forward[2] * forward[2]);
    for (int c = 0; c < 3; ++c)
        forward[c] /= fl;
    glUniform3fv(glGetUniformLocation(p, "u_forward"), 1, forward);
    set_surface_uniforms(rt, p);
    sam_runtime_bind_shadows(rt, p);
    /* With texture space the atlas carries the translucency (the override
     * there is atlas-sized): the pass itself adds none. */
    sam_runtime_bind_technique(rt, p, texture_space ? TECHNIQUE_NONE : mode, texture_space ? 0 : override_tex);
    sam_runtime_bind_tsm(rt, p);
    for (int b = 0; b < B_COUNT; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
    /* The G-buffer is no frame: it leaves the shading pass's time alone. */
    if (!gbuffer)
        glBeginQuery(GL_TIME_ELAPSED, rt->query[SAM_PASS_SHADE]);
    glBindVertexArray(rt->vao);
    glDrawElements(GL_TRIANGLES, (GLsizei)rt->triangle_count * 3, GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);
    if (!gbuffer) {
        glEndQuery(GL_TIME_ELAPSED);
        rt->query_used[SAM_PASS_SHADE] = 1;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

sam_status sam_runtime_render_texture(sam_runtime *rt, const sam_render_view *view, GLuint *texture, sam_error *err)
{
    *texture = 0;
    sam_status st = check_view(rt, view, err);
    if (st == SAM_OK && view->diffusion == 2)
        st = ensure_preintegrated(rt, err);
    if (st == SAM_OK && view->diffusion == 1)
        st = ensure_kernel(rt, view->options.sss_kernel, view->options.sss_samples ? view->options.sss_samples : 17,
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
    if (st == SAM_OK && view->diffusion == 3) {
        glBeginQuery(GL_TIME_ELAPSED, rt->query[SAM_PASS_DIFFUSION]);
        st = sam_runtime_texture_space(rt, view, &vp, &proj, mode, override_tex, tsm, err);
        glEndQuery(GL_TIME_ELAPSED);
        rt->query_used[SAM_PASS_DIFFUSION] = 1;
    }
    if (st != SAM_OK)
        goto done;
    draw_view(rt, view, &vp, mode, override_tex, tsm, 0);
    GLuint result = rt->view_tex[0];
    if (view->diffusion == 1) {
        glBeginQuery(GL_TIME_ELAPSED, rt->query[SAM_PASS_DIFFUSION]);
        screen_space_diffusion(rt, view);
        glEndQuery(GL_TIME_ELAPSED);
        rt->query_used[SAM_PASS_DIFFUSION] = 1;
        result = rt->view_tex[3];
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
    view_matrices(rt, view, &proj, &vp);
    memcpy(m, vp.m, sizeof vp.m);
}

sam_status sam_runtime_gbuffer(sam_runtime *rt, const sam_render_view *view, sam_gbuffer_space space,
                               sam_image *positions, sam_image *normals, sam_error *err)
{
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
        tex[0] = rt->view_tex[0];
        tex[1] = rt->view_tex[1];
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
    if (space == SAM_GBUFFER_ATLAS) {
        glDeleteFramebuffers(1, &fbo);
        glDeleteTextures(2, tex);
    }
    return st;
}

sam_status sam_runtime_set_irradiance(sam_runtime *rt, const float *rgb, sam_error *err)
{
    float *v4 = widen(rgb, rt->vertex_count, 0.0f);
    if (!v4)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[B_IRRADIANCE]);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)rt->vertex_count * 4 * sizeof(float), v4);
    free(v4);
    return SAM_OK;
}

sam_status sam_runtime_translucency(sam_runtime *rt, uint32_t samples, float dt, int reset, sam_error *err)
{
    if (!(dt >= 0) || !isfinite(dt))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: frame time must be finite and >= 0, got %g", dt);
    int carried = rt->posed && rt->posed_k == SAM_POSED_K_CARRIED;
    GLuint p = !rt->posed ? rt->translucency_program : carried ? rt->translucency_posed_program
                                                               : rt->translucency_eq15_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_stride"), rt->stride);
    glUniform1ui(glGetUniformLocation(p, "u_samples"), samples && samples < rt->stride ? samples : rt->stride);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1f(glGetUniformLocation(p, "u_alpha"), reset ? 1.0f : sam_runtime_smoothing_alpha(dt));
    for (int b = 0; b < B_COUNT; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
    /* A posed K is carried from the rest pose (shaders/fan_form_factor.glsl). */
    if (carried)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, B_REST_POSITIONS, rt->rest_buffer[REST_POSITIONS]);
    dispatch_per_vertex(rt, SAM_PASS_TRANSLUCENCY);
    return SAM_OK;
}

static sam_status read_vec4(sam_runtime *rt, int binding, float *rgb, sam_error *err)
{
    float *v4 = malloc((size_t)rt->vertex_count * 4 * sizeof *v4);
    if (!v4)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[binding]);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)rt->vertex_count * 4 * sizeof(float), v4);
    for (uint32_t v = 0; v < rt->vertex_count; ++v)
        memcpy(rgb + 3 * (size_t)v, v4 + 4 * (size_t)v, 3 * sizeof(float));
    free(v4);
    return SAM_OK;
}

sam_status sam_runtime_read_positions(sam_runtime *rt, float *xyz, sam_error *err)
{
    return read_vec4(rt, B_POSITIONS, xyz, err);
}

sam_status sam_runtime_read_normals(sam_runtime *rt, float *xyz, sam_error *err)
{
    return read_vec4(rt, B_NORMALS, xyz, err);
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
    return read_floats(rt, B_FAN_AREAS, mm2);
}

sam_status sam_runtime_read_curvature(sam_runtime *rt, float *per_mm, sam_error *err)
{
    (void)err;
    return read_floats(rt, B_CURVATURE, per_mm);
}

sam_status sam_runtime_read_irradiance(sam_runtime *rt, float *rgb, sam_error *err)
{
    return read_vec4(rt, B_IRRADIANCE, rgb, err);
}

sam_status sam_runtime_read_translucency(sam_runtime *rt, float *rgb, sam_error *err)
{
    return read_vec4(rt, B_TRANSLUCENCY, rgb, err);
}

/* The bytes of the buffers the rest pose keeps, in REST_* order. */
static void rest_sizes(const sam_runtime *rt, GLsizeiptr bytes[REST_COUNT])
{
    bytes[REST_POSITIONS] = bytes[REST_NORMALS] = (GLsizeiptr)rt->vertex_count * 4 * sizeof(float);
    bytes[REST_FAN_AREAS] = bytes[REST_CURVATURE] = (GLsizeiptr)rt->vertex_count * sizeof(float);
    bytes[REST_SAMPLES] = (GLsizeiptr)rt->vertex_count * rt->stride * 4 * sizeof(uint32_t);
}

static const int rest_binding[REST_COUNT] = {B_POSITIONS, B_NORMALS, B_FAN_AREAS, B_SAMPLES, B_CURVATURE};

/* Keeps the current positions, normals, fan areas and samples as the rest
 * pose, once: every pose is computed from it. */
static sam_status keep_rest_pose(sam_runtime *rt, sam_error *err)
{
    if (rt->rest_buffer[0])
        return SAM_OK;
    GLsizeiptr bytes[REST_COUNT];
    rest_sizes(rt, bytes);
    glGenBuffers(REST_COUNT, rt->rest_buffer);
    for (int i = 0; i < REST_COUNT; ++i) {
        glBindBuffer(GL_COPY_WRITE_BUFFER, rt->rest_buffer[i]);
        glBufferData(GL_COPY_WRITE_BUFFER, bytes[i], NULL, GL_STATIC_DRAW);
        glBindBuffer(GL_COPY_READ_BUFFER, rt->buffer[rest_binding[i]]);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, bytes[i]);
    }
    if (glGetError() != GL_NO_ERROR) {
        glDeleteBuffers(REST_COUNT, rt->rest_buffer);
        memset(rt->rest_buffer, 0, sizeof rt->rest_buffer);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not keep the rest pose of %u vertices",
                        rt->vertex_count);
    }
    return SAM_OK;
}

sam_status sam_runtime_set_deformers(sam_runtime *rt, const sam_deformer *deformers, size_t count,
                                     sam_error *err)
{
    if (count > SAM_DEFORM_MAX || (count && !deformers))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu deformers%s (at most %d)", count,
                        count && !deformers ? " but none given" : "", SAM_DEFORM_MAX);
    sam_status st;
    if (count && (st = keep_rest_pose(rt, err)) != SAM_OK)
        return st;
    if (count)
        memcpy(rt->deformers, deformers, count * sizeof *deformers);
    rt->deformer_count = count;
    return SAM_OK;
}

sam_status sam_runtime_set_keyframes(sam_runtime *rt, const float *const *positions, const float *times,
                                     size_t count, sam_error *err)
{
    if (count && (!positions || !times))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu keyframes but no %s given", count,
                        positions ? "times" : "positions");
    for (size_t i = 0; i < count; ++i) {
        if (!positions[i])
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: keyframe %zu has no positions", i);
        if (!(isfinite(times[i]) && times[i] > 0.0f && (i == 0 || times[i] > times[i - 1])))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "runtime: keyframe %zu at time %g: times must be finite, > 0 and increasing (previous %g)",
                            i, times[i], i ? times[i - 1] : 0.0f);
    }
    const size_t nv = rt->vertex_count;
    float *times_copy = count ? malloc(count * sizeof *times_copy) : NULL;
    float *vec4s = count ? malloc(count * nv * 4 * sizeof *vec4s) : NULL;
    if (count && (!times_copy || !vec4s)) {
        free(times_copy);
        free(vec4s);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu keyframes of %zu vertices", count,
                        nv);
    }
    sam_status st;
    if (count && (st = keep_rest_pose(rt, err)) != SAM_OK) {
        free(times_copy);
        free(vec4s);
        return st;
    }
    for (size_t i = 0; i < count; ++i) {
        for (size_t v = 0; v < nv; ++v) {
            memcpy(vec4s + (i * nv + v) * 4, positions[i] + 3 * v, 3 * sizeof(float));
            vec4s[(i * nv + v) * 4 + 3] = 1.0f;
        }
    }
    if (count)
        memcpy(times_copy, times, count * sizeof *times_copy);
    if (rt->keyframe_buffer)
        glDeleteBuffers(1, &rt->keyframe_buffer);
    rt->keyframe_buffer = 0;
    free(rt->keyframe_times);
    rt->keyframe_times = times_copy;
    rt->keyframe_count = 0;
    if (count) {
        glGenBuffers(1, &rt->keyframe_buffer);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->keyframe_buffer);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(count * nv * 4 * sizeof *vec4s), vec4s, GL_STATIC_DRAW);
        free(vec4s);
        if (glGetError() != GL_NO_ERROR) {
            glDeleteBuffers(1, &rt->keyframe_buffer);
            rt->keyframe_buffer = 0;
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not keep %zu keyframes of %zu vertices",
                            count, nv);
        }
    }
    rt->keyframe_count = count;
    return SAM_OK;
}

/* The keyframe pose at `time_s` as two keys and a weight: positions =
 * key a + (key b - key a) * w, key -1 being the rest pose at time 0.
 * Returns 0 when that is the rest pose itself. */
static int keyframe_pose(const sam_runtime *rt, float time_s, GLint *a, GLint *b, float *w)
{
    *a = *b = -1;
    *w = 0.0f;
    if (!rt->keyframe_count || time_s <= 0.0f)
        return 0;
    const float *t = rt->keyframe_times;
    size_t n = rt->keyframe_count;
    if (time_s >= t[n - 1]) {
        *a = *b = (GLint)(n - 1); /* after the last key the pose holds */
        return 1;
    }
    size_t i = 0;
    while (time_s >= t[i])
        ++i; /* t[i - 1] <= time_s < t[i], t[-1] = 0 */
    float t0 = i ? t[i - 1] : 0.0f;
    *a = (GLint)i - 1;
    *b = (GLint)i;
    *w = (time_s - t0) / (t[i] - t0);
    return 1;
}

sam_status sam_runtime_deform(sam_runtime *rt, float time_s, sam_error *err)
{
    if (!isfinite(time_s))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: deform time must be finite, got %g", time_s);
    if (!rt->rest_buffer[0])
        return SAM_OK; /* never deformed: the buffers hold the rest pose */
    sam_deform_step steps[SAM_DEFORM_MAX];
    GLint key_a, key_b;
    float key_w;
    int keyed = keyframe_pose(rt, time_s, &key_a, &key_b, &key_w);
    glBeginQuery(GL_TIME_ELAPSED, rt->query[SAM_PASS_DEFORM]);
    if (!sam_deform_prepare(rt->deformers, rt->deformer_count, time_s, steps) && !keyed) {
        /* A copy, not the passes, so the rest pose comes back bit for bit. */
        GLsizeiptr bytes[REST_COUNT];
        rest_sizes(rt, bytes);
        for (int i = 0; i < REST_COUNT; ++i) {
            glBindBuffer(GL_COPY_READ_BUFFER, rt->rest_buffer[i]);
            glBindBuffer(GL_COPY_WRITE_BUFFER, rt->buffer[rest_binding[i]]);
            glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, bytes[i]);
        }
        rt->posed = 0;
    } else {
        rt->posed = 1;
        GLint type[SAM_DEFORM_MAX];
        float axis[SAM_DEFORM_MAX][3], direction[SAM_DEFORM_MAX][3], center[SAM_DEFORM_MAX][3],
            param[SAM_DEFORM_MAX][3];
        GLint used = 0;
        for (size_t i = 0; i < rt->deformer_count; ++i) {
            if (steps[i].identity)
                continue;
            type[used] = (GLint)steps[i].type;
            memcpy(axis[used], steps[i].axis, sizeof axis[used]);
            memcpy(direction[used], steps[i].direction, sizeof direction[used]);
            memcpy(center[used], steps[i].center, sizeof center[used]);
            memcpy(param[used], steps[i].param, sizeof param[used]);
            used++;
        }
        GLuint p = rt->deform_program;
        glUseProgram(p);
        glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
        glUniform1i(glGetUniformLocation(p, "u_step_count"), used);
        glUniform1iv(glGetUniformLocation(p, "u_type"), used, type);
        glUniform3fv(glGetUniformLocation(p, "u_axis"), used, &axis[0][0]);
        glUniform3fv(glGetUniformLocation(p, "u_direction"), used, &direction[0][0]);
        glUniform3fv(glGetUniformLocation(p, "u_center"), used, &center[0][0]);
        glUniform3fv(glGetUniformLocation(p, "u_param"), used, &param[0][0]);
        glUniform1i(glGetUniformLocation(p, "u_key_a"), key_a);
        glUniform1i(glGetUniformLocation(p, "u_key_b"), key_b);
        glUniform1f(glGetUniformLocation(p, "u_key_w"), key_w);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, B_POSITIONS, rt->buffer[B_POSITIONS]);
        /* Without keyframes the shader never reads binding 1; the rest
         * positions stand in so that every declared block is bound. */
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, B_NORMALS,
                         rt->keyframe_buffer ? rt->keyframe_buffer : rt->rest_buffer[REST_POSITIONS]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, B_SAMPLES, rt->rest_buffer[REST_POSITIONS]);
        glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, B_NORMALS, rt->buffer[B_NORMALS]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, B_SAMPLES, rt->buffer[B_SAMPLES]);
        p = rt->deform_normals_program;
        glUseProgram(p);
        glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
        glUniform1f(glGetUniformLocation(p, "u_mm2_per_unit2"), rt->mm_per_unit * rt->mm_per_unit);
        glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
        glUniform1i(glGetUniformLocation(p, "u_stage"), 0);
        for (int b = 0; b < B_COUNT; ++b)
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
        static const GLuint empty_box[6] = {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu, 0, 0, 0};
        if (!rt->bounds_buffer) {
            glGenBuffers(1, &rt->bounds_buffer);
            glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->bounds_buffer);
            glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof empty_box, NULL, GL_DYNAMIC_READ);
        }
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->bounds_buffer);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof empty_box, empty_box);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, B_BOUNDS, rt->bounds_buffer);
        glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
        /* Boundary vertices take their curvature from interior neighbours. */
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glUniform1i(glGetUniformLocation(p, "u_stage"), 1);
        glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    }
    glEndQuery(GL_TIME_ELAPSED);
    rt->query_used[SAM_PASS_DEFORM] = 1;
    /* Positions and normals are vertex attributes of the draws as well. */
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
    if (!rt->posed) {
        set_box(rt, rt->rest_box_lo, rt->rest_box_hi);
        return SAM_OK;
    }
    /* The shadow maps' and the camera's ranges need the pose's bounds on the
     * CPU this frame: the one read-back of the update (24 bytes; it waits
     * for the deform passes). */
    GLuint key[6];
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->bounds_buffer);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof key, key);
    float lo[3], hi[3];
    for (int c = 0; c < 3; ++c) {
        uint32_t a = key[c] & 0x80000000u ? key[c] & 0x7FFFFFFFu : ~key[c];
        uint32_t b = key[3 + c] & 0x80000000u ? key[3 + c] & 0x7FFFFFFFu : ~key[3 + c];
        memcpy(&lo[c], &a, sizeof a);
        memcpy(&hi[c], &b, sizeof b);
    }
    set_box(rt, lo, hi);
    return SAM_OK;
}

sam_status sam_runtime_set_posed_k(sam_runtime *rt, sam_posed_k mode, sam_error *err)
{
    if (mode != SAM_POSED_K_CARRIED && mode != SAM_POSED_K_EQ15)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: unknown posed-K mode %d (expected 0 or 1)",
                        (int)mode);
    rt->posed_k = mode;
    return SAM_OK;
}

sam_status sam_runtime_walk(sam_runtime *rt, sam_error *err)
{
    (void)err;
    if (!rt->posed)
        return SAM_OK; /* the builder's samples are exact at rest; the walk's estimates could only move them */
    GLuint p = rt->walk_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_stride"), rt->stride);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    for (int b = 0; b < B_COUNT; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
    dispatch_per_vertex(rt, SAM_PASS_WALK);
    return SAM_OK;
}

sam_status sam_runtime_read_samples(sam_runtime *rt, uint32_t *index, float *kprime, sam_error *err)
{
    const size_t count = (size_t)rt->vertex_count * rt->stride;
    uint32_t *raw = malloc(count * 4 * sizeof *raw);
    if (!raw)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu samples", count);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, rt->buffer[B_SAMPLES]);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(count * 4 * sizeof *raw), raw);
    for (size_t i = 0; i < count; ++i) {
        index[i] = raw[4 * i];
        memcpy(kprime + 3 * i, raw + 4 * i + 1, 3 * sizeof(float));
    }
    free(raw);
    return SAM_OK;
}

double sam_runtime_pass_ms(sam_runtime *rt, sam_pass pass)
{
    if (pass >= SAM_PASS_COUNT || !rt->query_used[pass])
        return -1.0;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(rt->query[pass], GL_QUERY_RESULT, &ns);
    return (double)ns * 1e-6;
}
