/* rho_dt, the specular lobe and the albedo map (sam_runtime_surface.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_mesh.h"
#include "sam_runtime_gpu.h"
#include "sam_runtime_surface.h"

/* Several albedo maps share one array of this many bytes at most: eight
 * maps of 4096 x 4096 (a scan's texture pages), 16 of 2048 x 4096. */
#define ALBEDO_ARRAY_BYTES (1ull << 30)

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

static void clear_albedo_maps(sam_runtime *rt)
{
    if (rt->surface.albedo_array)
        glDeleteTextures(1, &rt->surface.albedo_array);
    if (rt->surface.triangle_map_tex)
        glDeleteTextures(1, &rt->surface.triangle_map_tex);
    if (rt->surface.triangle_map_buffer)
        glDeleteBuffers(1, &rt->surface.triangle_map_buffer);
    rt->surface.albedo_array = rt->surface.triangle_map_tex = rt->surface.triangle_map_buffer = 0;
}

void sam_runtime_surface_destroy(sam_runtime *rt)
{
    if (rt->surface.albedo_tex)
        glDeleteTextures(1, &rt->surface.albedo_tex);
    rt->surface.albedo_tex = 0;
    if (rt->surface.color_buffer)
        glDeleteBuffers(1, &rt->surface.color_buffer);
    rt->surface.color_buffer = 0;
    clear_albedo_maps(rt);
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
    clear_albedo_maps(rt);
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

/* Map `m` resampled (bilinear, wrapping as the sampler does) to w x h,
 * as sRGB-encoded RGBA bytes into `out`, top row first; white when empty. */
static void albedo_layer(const sam_image *m, uint32_t w, uint32_t h, uint8_t *out)
{
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            uint8_t *o = out + 4 * ((size_t)y * w + x);
            o[3] = 255;
            if (!m->pixels) {
                o[0] = o[1] = o[2] = 255;
                continue;
            }
            const float fx = ((float)x + 0.5f) * (float)m->width / (float)w - 0.5f;
            const float fy = ((float)y + 0.5f) * (float)m->height / (float)h - 0.5f;
            const float x0f = floorf(fx), y0f = floorf(fy), ax = fx - x0f, ay = fy - y0f;
            const uint32_t x0 = (uint32_t)((int64_t)x0f + m->width) % m->width, x1 = (x0 + 1) % m->width;
            const uint32_t y0 = (uint32_t)((int64_t)y0f + m->height) % m->height, y1 = (y0 + 1) % m->height;
            for (uint32_t c = 0; c < 3; ++c) {
                const float *p = m->pixels + c;
                const size_t n = m->channels, W = m->width;
                const float v = (1 - ay) * ((1 - ax) * p[n * (y0 * W + x0)] + ax * p[n * (y0 * W + x1)]) +
                                ay * ((1 - ax) * p[n * (y1 * W + x0)] + ax * p[n * (y1 * W + x1)]);
                const float e = sam_linear_to_srgb(v < 0 ? 0 : v > 1 ? 1 : v);
                o[c] = (uint8_t)(e * 255.0f + 0.5f);
            }
        }
}

sam_status sam_runtime_set_albedo_maps(sam_runtime *rt, const sam_image *maps, uint32_t count,
                                       const uint32_t *triangle_map, uint32_t triangle_count, sam_error *err)
{
    if (!rt || !maps || !count || !triangle_map)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: albedo maps: NULL argument or no map");
    if (!rt->tsd.has_uvs)
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "runtime: albedo maps need UVs and this mesh has none");
    if (triangle_count != rt->triangle_count)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: albedo maps for %u triangles, the map has %u",
                        triangle_count, rt->triangle_count);
    GLint side = 0, layers = 0, texels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &side);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &layers);
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    if (count > (uint32_t)layers || triangle_count > (uint32_t)texels)
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "runtime: %u albedo maps on %u triangles; this GL holds %d maps and %d triangles' choice",
                        count, triangle_count, layers, texels);
    uint32_t w = 1, h = 1;
    for (uint32_t m = 0; m < count; ++m) {
        if (maps[m].pixels && (maps[m].channels < 3 || !maps[m].width || !maps[m].height))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: albedo map %u is %ux%u with %u channels; need 3 "
                            "or 4 channels", m, maps[m].width, maps[m].height, maps[m].channels);
        w = maps[m].pixels && maps[m].width > w ? maps[m].width : w;
        h = maps[m].pixels && maps[m].height > h ? maps[m].height : h;
    }
    for (uint32_t t = 0; t < triangle_count; ++t)
        if (triangle_map[t] >= count && triangle_map[t] != SAM_ALBEDO_NO_MAP)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "runtime: triangle %u reads albedo map %u of %u", t,
                            triangle_map[t], count);
    /* The largest map's size for every layer, halved to the GL's side and
     * to ALBEDO_ARRAY_BYTES: sRGB bytes lose nothing of 8-bit textures. */
    while (w > (uint32_t)side || h > (uint32_t)side || (uint64_t)count * w * h * 4 > ALBEDO_ARRAY_BYTES)
        w = w > 1 ? w / 2 : 1, h = h > 1 ? h / 2 : 1;
    uint8_t *layer = malloc((size_t)w * h * 4);
    if (!layer)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: out of memory for a %ux%u albedo map", w, h);
    if (rt->surface.albedo_tex)
        glDeleteTextures(1, &rt->surface.albedo_tex);
    rt->surface.albedo_tex = 0;
    clear_albedo_maps(rt);
    while (glGetError() != GL_NO_ERROR) {
    }
    GLsizei levels = 1;
    for (uint32_t s = w > h ? w : h; s > 1; s /= 2)
        levels++;
    glGenTextures(1, &rt->surface.albedo_array);
    glBindTexture(GL_TEXTURE_2D_ARRAY, rt->surface.albedo_array);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, levels, GL_SRGB8_ALPHA8, (GLsizei)w, (GLsizei)h, (GLsizei)count);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (uint32_t m = 0; m < count; ++m) {
        albedo_layer(&maps[m], w, h, layer);
        /* Image rows run top-down and UV's v up. */
        for (uint32_t y = 0; y < h; ++y)
            glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, (GLint)(h - 1 - y), (GLint)m, (GLsizei)w, 1, 1, GL_RGBA,
                            GL_UNSIGNED_BYTE, layer + (size_t)y * w * 4);
    }
    free(layer);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glGenerateMipmap(GL_TEXTURE_2D_ARRAY);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    glGenBuffers(1, &rt->surface.triangle_map_buffer);
    glBindBuffer(GL_TEXTURE_BUFFER, rt->surface.triangle_map_buffer);
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)((size_t)triangle_count * sizeof *triangle_map), triangle_map,
                 GL_STATIC_DRAW);
    glGenTextures(1, &rt->surface.triangle_map_tex);
    glBindTexture(GL_TEXTURE_BUFFER, rt->surface.triangle_map_tex);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_R32UI, rt->surface.triangle_map_buffer);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
    if (glGetError() != GL_NO_ERROR) {
        clear_albedo_maps(rt);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not store %u albedo maps of %ux%u", count,
                        w, h);
    }
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
    while (glGetError() != GL_NO_ERROR) {
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
    if (glGetError() != GL_NO_ERROR) {
        sam_runtime_set_vertex_colors(rt, NULL, 0, NULL);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "runtime: the GL could not store %zu vertex colours", nv);
    }
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
    glActiveTexture(GL_TEXTURE0 + UNIT_ALBEDO_ARRAY);
    glBindTexture(GL_TEXTURE_2D_ARRAY, rt->surface.albedo_array);
    glActiveTexture(GL_TEXTURE0 + UNIT_TRIANGLE_MAP);
    glBindTexture(GL_TEXTURE_BUFFER, rt->surface.triangle_map_tex);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(glGetUniformLocation(p, "u_albedo_array"), UNIT_ALBEDO_ARRAY);
    glUniform1i(glGetUniformLocation(p, "u_triangle_map"), UNIT_TRIANGLE_MAP);
    glUniform1i(glGetUniformLocation(p, "u_has_albedo_map"),
                rt->surface.albedo_array ? 2 : rt->surface.albedo_tex != 0);
}

void sam_runtime_bind_uv_atlas(const sam_runtime *rt, GLuint p)
{
    const sam_uv_atlas *a = &rt->tsd.uv_atlas;
    glUniform3f(glGetUniformLocation(p, "u_uv_atlas"), a->scale, a->offset[0], a->offset[1]);
}
