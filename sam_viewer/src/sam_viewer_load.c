/* The viewer's scene (sam_viewer_load.h). */
#define _DEFAULT_SOURCE /* realpath */
#define _POSIX_C_SOURCE 200809L
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "sam/sam_app_stage.h"
#include "sam/sam_light.h"
#include "sam/sam_viewer_load.h"

static int has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && !strcmp(s + n - m, suffix);
}

/* A scene for a bare .sam, written as JSON and parsed, so it goes through
 * the scene loader's checks like any scene file. */
static sam_status bare_sam_scene(const char *input, const char *material, const char *environment,
                                 sam_scene *scene, sam_error *err)
{
    cJSON *root = cJSON_CreateObject();
    if (!root)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
    cJSON_AddStringToObject(root, "sam", input);
    if (material)
        cJSON_AddStringToObject(root, "material", material);
    if (environment) {
        cJSON *env = cJSON_AddObjectToObject(root, "environment");
        if (env)
            cJSON_AddStringToObject(env, "map", environment);
    }
    char *text = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    if (!text)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
    sam_status st = sam_scene_parse(text, strlen(text), NULL, input, scene, err);
    free(text);
    return st;
}

/* A bare mesh's staged scene (sam_app_stage.h), its assumptions printed,
 * with the environment map when given. */
static sam_status mesh_scene(const char *input, const char *material, const sam_app_stage_options *stage,
                             const char *environment, sam_scene *scene, sam_error *err)
{
    sam_app_stage_options defaults;
    sam_app_stage_defaults(&defaults);
    sam_app_stage_notes notes;
    sam_status st = sam_app_stage_scene(input, material, stage ? stage : &defaults, scene, &notes, err);
    if (st != SAM_OK)
        return st;
    for (int i = 0; i < notes.count; ++i)
        fprintf(stderr, "sam_view: %s\n", notes.line[i]);
    if (!environment)
        return SAM_OK;
    char path[PATH_MAX];
    if (!realpath(environment, path))
        return sam_fail(err, SAM_ERR_IO, "--environment: cannot open %s", environment);
    scene->environment.map = strdup(path);
    scene->environment.intensity = 1.0f;
    return scene->environment.map ? SAM_OK : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
}

sam_status sam_viewer_load_scene(const char *input, const char *material, const sam_app_stage_options *stage,
                                 const char *environment, sam_scene *scene, sam_viewer_input *kind, sam_error *err)
{
    const int scene_file = has_suffix(input, ".json"), sam_file = has_suffix(input, ".sam");
    if (kind)
        *kind = scene_file ? SAM_VIEWER_INPUT_SCENE : sam_file ? SAM_VIEWER_INPUT_SAM : SAM_VIEWER_INPUT_MESH;
    if (scene_file && (material || environment))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "--material and --environment are for a bare mesh or .sam; %s sets its own", input);
    if ((scene_file || sam_file) && stage && stage->up >= 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "--up is for a bare mesh; %s is seen from its own camera",
                        input);
    if (scene_file)
        return sam_scene_load(input, scene, err);
    return sam_file ? bare_sam_scene(input, material, environment, scene, err)
                    : mesh_scene(input, material, stage, environment, scene, err);
}

sam_status sam_viewer_default_lights(sam_scene *s, const float centre[3], float radius, sam_error *err)
{
    s->lights = calloc(2, sizeof *s->lights);
    if (!s->lights)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
    s->light_count = 2;
    for (int i = 0; i < 2; ++i) {
        sam_light *l = &s->lights[i];
        l->type = SAM_LIGHT_POINT;
        l->shadow = 1;
        for (int c = 0; c < 3; ++c)
            l->color[c] = 1.0f;
        float side = i == 0 ? -2.5f : 3.0f;
        l->position[0] = centre[0] + (i == 0 ? 0.3f : -0.8f) * radius;
        l->position[1] = centre[1] + 0.5f * radius;
        l->position[2] = centre[2] + side * radius;
        /* Intensity in the scene's units: about 1 of irradiance at the object. */
        float d = (i == 0 ? 2.5f : 3.0f) * radius;
        l->intensity = (i == 0 ? 2.0f : 0.25f) * d * d;
    }
    return SAM_OK;
}
