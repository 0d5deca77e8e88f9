/*
 * sam_scene_write: a sam_scene as a scene file that loads back to the same
 * scene (sam_scene_write in sam_scene.h). The text is built with cJSON and
 * checked by sam_scene_parse before anything is written.
 */
#include "sam_scene_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Shortest decimal text that reads back (as the parser reads it: double,
 * then float) to exactly `v`. Non-finite values become null, which the
 * parse-back check then reports with the key's path. */
static cJSON *number_item(float v)
{
    char buf[40];
    if (!isfinite(v))
        return cJSON_CreateNull();
    for (int digits = 6; digits <= 9; ++digits) {
        snprintf(buf, sizeof buf, "%.*g", digits, (double)v);
        if ((float)strtod(buf, NULL) == v)
            break;
    }
    return cJSON_CreateRaw(buf);
}

/* cJSON's add functions return NULL on failure; the build tracks that in
 * one flag instead of testing every call. */
typedef struct builder {
    int failed;
} builder;

static void add(builder *b, cJSON *object, const char *key, cJSON *item)
{
    if (!item || !object || !cJSON_AddItemToObject(object, key, item)) {
        cJSON_Delete(item);
        b->failed = 1;
    }
}

static void append(builder *b, cJSON *array, cJSON *item)
{
    if (!item || !array || !cJSON_AddItemToArray(array, item)) {
        cJSON_Delete(item);
        b->failed = 1;
    }
}

static cJSON *vec3_item(builder *b, const float v[3])
{
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; k < 3; ++k)
        append(b, a, number_item(v[k]));
    return a;
}

static void add_path(builder *b, cJSON *object, const char *key, const char *path)
{
    char *abs = sam_scene_absolute_path(NULL, path);
    if (!abs) {
        b->failed = 1;
        return;
    }
    add(b, object, key, cJSON_CreateString(abs));
    free(abs);
}

static cJSON *light_item(builder *b, const sam_light *l)
{
    cJSON *o = cJSON_CreateObject();
    add(b, o, "type", cJSON_CreateString(sam_light_type_name(l->type)));
    if (l->type == SAM_LIGHT_POINT || l->type == SAM_LIGHT_SPOT)
        add(b, o, "position", vec3_item(b, l->position));
    if (l->type == SAM_LIGHT_SPOT || l->type == SAM_LIGHT_DIRECTIONAL)
        add(b, o, "direction", vec3_item(b, l->direction));
    if (l->type == SAM_LIGHT_SPOT) {
        add(b, o, "inner_angle_deg", number_item(l->inner_angle_deg));
        add(b, o, "outer_angle_deg", number_item(l->outer_angle_deg));
    }
    if (l->type == SAM_LIGHT_AREA) {
        cJSON *vertices = cJSON_CreateArray();
        for (uint32_t i = 0; i < l->vertex_count && i < SAM_AREA_LIGHT_MAX_VERTICES; ++i)
            append(b, vertices, vec3_item(b, l->vertices[i]));
        add(b, o, "vertices", vertices);
        add(b, o, "two_sided", cJSON_CreateBool(l->two_sided));
    }
    add(b, o, "color", vec3_item(b, l->color));
    add(b, o, "intensity", number_item(l->intensity));
    add(b, o, "shadow", cJSON_CreateBool(l->shadow));
    return o;
}

static cJSON *deformer_item(builder *b, const sam_deformer *d)
{
    cJSON *o = cJSON_CreateObject();
    add(b, o, "type", cJSON_CreateString(sam_deformer_type_name(d->type)));
    add(b, o, "axis", vec3_item(b, d->axis));
    if (d->type == SAM_DEFORM_BEND || d->type == SAM_DEFORM_WAVE)
        add(b, o, "direction", vec3_item(b, d->direction));
    if (d->type != SAM_DEFORM_WAVE)
        add(b, o, "center", vec3_item(b, d->center));
    if (d->type == SAM_DEFORM_BEND || d->type == SAM_DEFORM_TWIST) {
        add(b, o, "angle_deg", number_item(d->angle_deg));
        add(b, o, "length", number_item(d->length));
    }
    if (d->type == SAM_DEFORM_SQUASH)
        add(b, o, "amount", number_item(d->amount));
    if (d->type == SAM_DEFORM_WAVE) {
        add(b, o, "amplitude", number_item(d->amplitude));
        add(b, o, "wavelength", number_item(d->wavelength));
        add(b, o, "speed", number_item(d->speed));
    }
    add(b, o, "period_s", number_item(d->period_s));
    return o;
}

static cJSON *scene_item(builder *b, const sam_scene *s)
{
    cJSON *root = cJSON_CreateObject();
    if (s->mesh_path)
        add_path(b, root, "mesh", s->mesh_path);
    if (s->sam_path)
        add_path(b, root, "sam", s->sam_path);
    if (s->material) {
        if (sam_scene_is_preset(s->material))
            add(b, root, "material", cJSON_CreateString(s->material));
        else
            add_path(b, root, "material", s->material);
    }
    if (s->scale_kind != SAM_SCALE_FROM_SAM) {
        cJSON *scale = cJSON_CreateObject();
        add(b, scale, s->scale_kind == SAM_SCALE_MM_PER_UNIT ? "mm_per_unit" : "size_mm",
            number_item(s->scale_value));
        add(b, root, "scale", scale);
    }
    add(b, root, "albedo", vec3_item(b, s->albedo));
    if (s->albedo_map)
        add_path(b, root, "albedo_map", s->albedo_map);
    if (!s->vertex_colors)
        add(b, root, "vertex_colors", cJSON_CreateBool(0));
    cJSON *lights = cJSON_CreateArray();
    for (size_t i = 0; i < s->light_count; ++i)
        append(b, lights, light_item(b, &s->lights[i]));
    add(b, root, "lights", lights);
    if (s->environment.map) {
        cJSON *env = cJSON_CreateObject();
        add_path(b, env, "map", s->environment.map);
        add(b, env, "intensity", number_item(s->environment.intensity));
        add(b, env, "rotation_deg", number_item(s->environment.rotation_deg));
        add(b, root, "environment", env);
    }
    if (s->has_camera) {
        const sam_camera *c = &s->camera;
        cJSON *cam = cJSON_CreateObject();
        add(b, cam, "position", vec3_item(b, c->position));
        add(b, cam, "target", vec3_item(b, c->target));
        add(b, cam, "up", vec3_item(b, c->up));
        add(b, cam, "fov_deg", number_item(c->fov_deg));
        /* 0 means automatic, which is the key's absence. */
        if (c->near_plane != 0.0f)
            add(b, cam, "near", number_item(c->near_plane));
        if (c->far_plane != 0.0f)
            add(b, cam, "far", number_item(c->far_plane));
        add(b, root, "camera", cam);
    }
    cJSON *res = cJSON_CreateArray();
    append(b, res, cJSON_CreateNumber(s->width));
    append(b, res, cJSON_CreateNumber(s->height));
    add(b, root, "resolution", res);
    add(b, root, "technique", cJSON_CreateString(sam_technique_name(s->technique)));
    add(b, root, "samples_per_vertex", cJSON_CreateNumber(s->samples_per_vertex));
    add(b, root, "diffusion", cJSON_CreateString(sam_diffusion_name(s->diffusion)));
    const sam_diffusion_options *o = &s->diffusion_options;
    cJSON *screen = cJSON_CreateObject();
    add(b, screen, "kernel", cJSON_CreateString(sam_sss_kernel_name(o->sss_kernel)));
    add(b, screen, "samples", cJSON_CreateNumber(o->sss_samples));
    add(b, root, "screen_space", screen);
    cJSON *texture = cJSON_CreateObject();
    add(b, texture, "atlas_size", cJSON_CreateNumber(o->atlas_size));
    add(b, texture, "culled", cJSON_CreateBool(o->culled));
    add(b, texture, "depth_sized", cJSON_CreateBool(o->depth_sized));
    add(b, texture, "clipped", cJSON_CreateBool(o->clipped));
    add(b, texture, "texels_per_pixel", number_item(o->texels_per_pixel));
    add(b, root, "texture_space", texture);
    add(b, root, "tonemap", cJSON_CreateString(sam_tonemap_name(s->tonemap)));
    add(b, root, "exposure", number_item(s->exposure));
    cJSON *deformers = cJSON_CreateArray();
    for (size_t i = 0; i < s->deformer_count && i < SAM_DEFORM_MAX; ++i)
        append(b, deformers, deformer_item(b, &s->deformers[i]));
    add(b, root, "deformers", deformers);
    cJSON *keyframes = cJSON_CreateArray();
    for (size_t i = 0; i < s->keyframe_count; ++i) {
        cJSON *k = cJSON_CreateObject();
        add_path(b, k, "mesh", s->keyframes[i].mesh);
        add(b, k, "time_s", number_item(s->keyframes[i].time_s));
        append(b, keyframes, k);
    }
    add(b, root, "keyframes", keyframes);
    return root;
}

sam_status sam_scene_write(const char *path, const sam_scene *scene, sam_error *err)
{
    if (!path || !path[0] || !scene)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scene write: NULL %s",
                        scene ? "path" : "scene");
    builder b = {0};
    cJSON *root = scene_item(&b, scene);
    char *text = root && !b.failed ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory building the scene", path);

    /* Parsing the text back validates the scene with the loader's own rules
     * and messages (an unknown enum value, a light out of range, a missing
     * file), so a file that is written always loads. */
    size_t len = strlen(text);
    sam_scene check;
    sam_status st = sam_scene_parse(text, len, NULL, path, &check, err);
    sam_scene_destroy(&check);
    if (st != SAM_OK) {
        cJSON_free(text);
        return st;
    }
    sam_atomic_file file;
    if ((st = sam_atomic_open(&file, path, err)) != SAM_OK) {
        cJSON_free(text);
        return st;
    }
    int ok = fwrite(text, 1, len, file.fp) == len && fputc('\n', file.fp) != EOF;
    cJSON_free(text);
    if (!ok) {
        int e = errno;
        sam_atomic_abort(&file);
        return sam_fail(err, SAM_ERR_IO, "%s: write failed: %s", path, strerror(e));
    }
    return sam_atomic_commit(&file, err);
}
