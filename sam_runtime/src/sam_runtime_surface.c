/* rho_dt, the specular lobe and the albedo map (sam_runtime_surface.h). */
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_surface.h"

sam_status sam_runtime_surface_create(sam_runtime *rt, const samfile_data *sam, sam_error *err)
{
    sam_status st;
    if (sam->vertex_source) {
        const size_t bytes = (size_t)rt->vertex_count * sizeof *rt->surface.vertex_source;
        if (!(rt->surface.vertex_source = malloc(bytes)))
            return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %u source vertices",
                            rt->vertex_count);
        memcpy(rt->surface.vertex_source, sam->vertex_source, bytes);
        rt->surface.source_count = sam->source_vertex_count;
    }
    if ((st = sam_brdf_rho_dt_table(RHO_SIZE, RHO_SIZE, SKIN_F0, SAM_BRDF_ROUGHNESS_MAX, rt->surface.rho_table, err)) !=
            SAM_OK ||
        (st = sam_runtime_upload(rt, SAM_B_RHO_DT, rt->surface.rho_table, sizeof rt->surface.rho_table, err)) !=
            SAM_OK)
        return st;
    return sam_runtime_set_surface(rt, 0.3f, 0.18f, err);
}

void sam_runtime_surface_destroy(sam_runtime *rt)
{
    if (rt->surface.albedo_tex)
        glDeleteTextures(1, &rt->surface.albedo_tex);
    rt->surface.albedo_tex = 0;
    if (rt->surface.color_buffer)
        glDeleteBuffers(1, &rt->surface.color_buffer);
    rt->surface.color_buffer = 0;
    free(rt->surface.vertex_source);
    rt->surface.vertex_source = NULL;
}

float sam_runtime_rho_dt(const sam_runtime *rt, float n_dot_l)
{
    float table = sam_brdf_rho_dt_table_lookup(rt->surface.rho_table, RHO_SIZE, RHO_SIZE, SAM_BRDF_ROUGHNESS_MAX, n_dot_l,
                                               rt->surface.roughness);
    return 1.0f - (float)(3.14159265358979323846 * rt->surface.rho_s) * (1.0f - table);
}

float sam_runtime_environment_rho_dt(const sam_runtime *rt)
{
    return rt->surface.environment_rho_dt;
}

sam_status sam_runtime_set_surface(sam_runtime *rt, float roughness, float rho_s, sam_error *err)
{
    if (!(roughness > 0 && roughness <= SAM_BRDF_ROUGHNESS_MAX) || !(rho_s >= 0 && rho_s <= 1))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: roughness must be in (0, %g] and rho_s in [0, 1], got %g and %g",
                        SAM_BRDF_ROUGHNESS_MAX, roughness, rho_s);
    rt->surface.roughness = roughness;
    rt->surface.rho_s = rho_s;
    /* Uniform light from the hemisphere enters as 2 int_0^1 rho_dt(mu) mu dmu. */
    double sum = 0;
    const int steps = 256;
    for (int i = 0; i < steps; ++i) {
        double mu = (i + 0.5) / steps;
        sum += sam_runtime_rho_dt(rt, (float)mu) * mu;
    }
    rt->surface.environment_rho_dt = (float)(2.0 * sum / steps);
    return SAM_OK;
}

void sam_runtime_set_surface_uniforms(const sam_runtime *rt, GLuint p)
{
    glUniform1i(glGetUniformLocation(p, "u_rho_size"), RHO_SIZE);
    glUniform1f(glGetUniformLocation(p, "u_roughness_coord"), rt->surface.roughness / SAM_BRDF_ROUGHNESS_MAX);
    glUniform1f(glGetUniformLocation(p, "u_specular_k"), (float)(3.14159265358979323846 * rt->surface.rho_s));
    glUniform3fv(glGetUniformLocation(p, "u_sh"), 9, &rt->lights.sh[0][0]);
    glUniform1i(glGetUniformLocation(p, "u_has_environment"), rt->lights.has_environment);
    glUniform1f(glGetUniformLocation(p, "u_environment_rho_dt"), rt->surface.environment_rho_dt);
}

sam_status sam_runtime_set_albedo_map(sam_runtime *rt, const sam_image *map, sam_error *err)
{
    if (map && !rt->tsd.has_uvs)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "runtime: an albedo map needs UVs and this mesh has none");
    GLint limit = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &limit);
    if (map && (map->channels < 3 || !map->width || !map->height || map->width > (uint32_t)limit ||
                map->height > (uint32_t)limit))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: albedo map %ux%u with %u channels; need 3 or 4 channels and at most %d texels a side",
                        map->width, map->height, map->channels, limit);
    if (rt->surface.albedo_tex)
        glDeleteTextures(1, &rt->surface.albedo_tex);
    rt->surface.albedo_tex = 0;
    if (!map)
        return SAM_OK;
    GLsizei levels = 1;
    for (uint32_t side = map->width > map->height ? map->width : map->height; side > 1; side /= 2)
        levels++;
    /* Image rows run top-down and UV's v up. */
    rt->surface.albedo_tex = sam_runtime_image_texture(map, levels, 1);
    if (!rt->surface.albedo_tex)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not store a %ux%u albedo map",
                        map->width, map->height);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    /* Tiled layouts (UVs past [0, 1]) repeat the map, as glTF's default
     * sampler and every DCC tool do. */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    return SAM_OK;
}

sam_status sam_runtime_set_vertex_colors(sam_runtime *rt, const float *rgb, uint32_t count, sam_error *err)
{
    if (!rt)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: NULL runtime");
    const uint32_t want = rt->surface.vertex_source ? rt->surface.source_count : rt->vertex_count;
    if (rgb && count != want)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "runtime: %u vertex colours for a map whose mesh has %u vertices (%s)", count, want,
                        rt->surface.vertex_source ? "the source mesh's, which the map's SRCV names"
                                                  : "the map's own: it has no SRCV");
    glBindVertexArray(rt->vao);
    if (!rgb) {
        glDisableVertexAttribArray(3);
        glBindVertexArray(0);
        if (rt->surface.color_buffer)
            glDeleteBuffers(1, &rt->surface.color_buffer);
        rt->surface.color_buffer = 0;
        return SAM_OK;
    }
    const size_t nv = rt->vertex_count;
    float *rgba = malloc(nv * 4 * sizeof *rgba);
    if (!rgba) {
        glBindVertexArray(0);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for %zu vertex colours", nv);
    }
    for (size_t v = 0; v < nv; ++v) {
        const size_t from = rt->surface.vertex_source ? rt->surface.vertex_source[v] : v;
        for (int k = 0; k < 3; ++k) {
            const float x = rgb[3 * from + (size_t)k];
            rgba[4 * v + (size_t)k] = x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; /* NaN to 0 */
        }
        rgba[4 * v + 3] = 1.0f;
    }
    if (!rt->surface.color_buffer)
        glGenBuffers(1, &rt->surface.color_buffer);
    glBindBuffer(GL_ARRAY_BUFFER, rt->surface.color_buffer);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * 4 * sizeof *rgba), rgba, GL_STATIC_DRAW);
    free(rgba);
    glEnableVertexAttribArray(3);
    glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), NULL);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    if (glGetError() != GL_NO_ERROR)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not store %zu vertex colours", nv);
    return SAM_OK;
}

void sam_runtime_bind_albedo(const sam_runtime *rt, GLuint p)
{
    if (!rt->surface.color_buffer)
        glVertexAttrib4f(3, 1.0f, 1.0f, 1.0f, 1.0f);
    glActiveTexture(GL_TEXTURE0 + UNIT_ALBEDO);
    glBindTexture(GL_TEXTURE_2D, rt->surface.albedo_tex);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_albedo_map"), UNIT_ALBEDO);
    glUniform1i(glGetUniformLocation(p, "u_has_albedo_map"), rt->surface.albedo_tex != 0);
}

void sam_runtime_bind_uv_atlas(const sam_runtime *rt, GLuint p)
{
    const sam_uv_atlas *a = &rt->tsd.uv_atlas;
    glUniform3f(glGetUniformLocation(p, "u_uv_atlas"), a->scale, a->offset[0], a->offset[1]);
}
