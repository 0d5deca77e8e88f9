/* rho_dt, the specular lobe and the albedo map (sam_runtime_surface.h). */
#include <stdlib.h>
#include <string.h>

#include "sam_runtime_gpu.h"
#include "sam_runtime_surface.h"

sam_status sam_runtime_surface_create(sam_runtime *rt, sam_error *err)
{
    sam_status st;
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

void sam_runtime_bind_albedo(const sam_runtime *rt, GLuint p)
{
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
