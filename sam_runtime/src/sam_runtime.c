/* A .sam as GPU buffers, and the translucency pass. */
#include "sam/sam_runtime.h"

#include <math.h>

#include "sam/sam_brdf.h"
#include <stdlib.h>
#include <string.h>

enum { B_POSITIONS, B_NORMALS, B_SAMPLES, B_FAN_AREAS, B_IRRADIANCE, B_TRANSLUCENCY, B_ADJ_OFFSETS, B_ADJACENCY,
       B_LIGHTS, B_RHO_DT, B_COUNT };

/* std430 image of lights.glsl's Light. */
typedef struct gpu_light {
    float color_type[4], position[4], direction[4], params[4], normal[4], vertices[8][4];
} gpu_light;

#define RHO_SIZE SAM_BRDF_RHO_DT_TABLE_SIZE
#define SKIN_F0 0.028f

struct sam_runtime {
    uint32_t vertex_count, stride;
    float mm_per_unit;
    sam_profile profile;
    GLuint buffer[B_COUNT];
    GLuint translucency_program, irradiance_program;
    GLuint query[SAM_PASS_COUNT];
    int query_used[SAM_PASS_COUNT];
    uint32_t light_count;
    int has_environment;
    float sh[9][3];
    float roughness, rho_s, environment_rho_dt;
    float rho_table[RHO_SIZE * RHO_SIZE];
};

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
            SAM_OK)
        goto done;
    if ((st = sam_brdf_rho_dt_table(RHO_SIZE, RHO_SIZE, SKIN_F0, SAM_BRDF_ROUGHNESS_MAX, rt->rho_table, err)) !=
            SAM_OK ||
        (st = upload(rt, B_RHO_DT, rt->rho_table, sizeof rt->rho_table, err)) != SAM_OK ||
        (st = upload(rt, B_LIGHTS, NULL, sizeof(gpu_light), err)) != SAM_OK)
        goto done;
    if ((st = sam_gl_compute_program("translucency.comp", NULL, &rt->translucency_program, err)) != SAM_OK ||
        (st = sam_gl_compute_program("irradiance.comp", NULL, &rt->irradiance_program, err)) != SAM_OK)
        goto done;
    set_profile_uniforms(rt->translucency_program, profile);
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
    if (rt->irradiance_program)
        glDeleteProgram(rt->irradiance_program);
    free(rt);
}

uint32_t sam_runtime_vertex_count(const sam_runtime *rt)
{
    return rt->vertex_count;
}

sam_status sam_runtime_set_lights(sam_runtime *rt, const sam_light *lights, size_t count, sam_error *err)
{
    if (count > SAM_SCENE_MAX_LIGHTS || (count && !lights))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: %zu lights (at most %d)", count,
                        SAM_SCENE_MAX_LIGHTS);
    gpu_light *g = calloc(count ? count : 1, sizeof *g);
    if (!g)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory");
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

sam_status sam_runtime_irradiance(sam_runtime *rt, sam_error *err)
{
    (void)err;
    GLuint p = rt->irradiance_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_light_count"), rt->light_count);
    glUniform3fv(glGetUniformLocation(p, "u_sh"), 9, &rt->sh[0][0]);
    glUniform1i(glGetUniformLocation(p, "u_has_environment"), rt->has_environment);
    glUniform1f(glGetUniformLocation(p, "u_environment_rho_dt"), rt->environment_rho_dt);
    glUniform1i(glGetUniformLocation(p, "u_rho_size_ndotl"), RHO_SIZE);
    glUniform1i(glGetUniformLocation(p, "u_rho_size_roughness"), RHO_SIZE);
    glUniform1f(glGetUniformLocation(p, "u_roughness_coord"), rt->roughness / SAM_BRDF_ROUGHNESS_MAX);
    glUniform1f(glGetUniformLocation(p, "u_specular_k"), (float)(3.14159265358979323846 * rt->rho_s));
    for (int b = 0; b < B_COUNT; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
    glBeginQuery(GL_TIME_ELAPSED, rt->query[SAM_PASS_IRRADIANCE]);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    glEndQuery(GL_TIME_ELAPSED);
    rt->query_used[SAM_PASS_IRRADIANCE] = 1;
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    return SAM_OK;
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
    GLuint p = rt->translucency_program;
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_vertex_count"), rt->vertex_count);
    glUniform1ui(glGetUniformLocation(p, "u_stride"), rt->stride);
    glUniform1ui(glGetUniformLocation(p, "u_samples"), samples && samples < rt->stride ? samples : rt->stride);
    glUniform1f(glGetUniformLocation(p, "u_mm_per_unit"), rt->mm_per_unit);
    glUniform1f(glGetUniformLocation(p, "u_alpha"), reset ? 1.0f : sam_runtime_smoothing_alpha(dt));
    for (int b = 0; b < B_COUNT; ++b)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, (GLuint)b, rt->buffer[b]);
    glBeginQuery(GL_TIME_ELAPSED, rt->query[SAM_PASS_TRANSLUCENCY]);
    glDispatchCompute((rt->vertex_count + 63) / 64, 1, 1);
    glEndQuery(GL_TIME_ELAPSED);
    rt->query_used[SAM_PASS_TRANSLUCENCY] = 1;
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
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

sam_status sam_runtime_read_irradiance(sam_runtime *rt, float *rgb, sam_error *err)
{
    return read_vec4(rt, B_IRRADIANCE, rgb, err);
}

sam_status sam_runtime_read_translucency(sam_runtime *rt, float *rgb, sam_error *err)
{
    return read_vec4(rt, B_TRANSLUCENCY, rgb, err);
}

double sam_runtime_pass_ms(sam_runtime *rt, sam_pass pass)
{
    if (pass >= SAM_PASS_COUNT || !rt->query_used[pass])
        return -1.0;
    GLuint64 ns = 0;
    glGetQueryObjectui64v(rt->query[pass], GL_QUERY_RESULT, &ns);
    return (double)ns * 1e-6;
}
