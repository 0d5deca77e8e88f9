/*
 * sam_scene_internal: what the files of the scene parser share (sam_scene.h
 * is the module's interface). sam_scene.c reads the root object and its
 * small sections and calls the parsers of the lights and environment
 * (sam_scene_lights.c) and of the animation (sam_scene_animation.c); all of
 * them read file references and directions through sam_scene_values.c.
 * sam_scene_write.c builds the text and checks it with sam_scene_parse.
 * No file calls back into a file that called it.
 *
 * Every parser reads a cJSON value the caller owns and writes into the
 * caller's scene; what it allocates there is freed by sam_scene_destroy,
 * also after a failure. Errors name the scene and the key's path
 * (sam_json.h).
 */
#ifndef SAM_SCENE_INTERNAL_H
#define SAM_SCENE_INTERNAL_H

#include "sam/sam_json.h"
#include "sam/sam_scene.h"

#define COUNT_OF(a) (sizeof(a) / sizeof((a)[0]))

/* The state of one sam_scene_parse call. */
typedef struct sam_scene_parser {
    sam_json_ctx json;    /* the scene's name and error, for messages */
    const char *base_dir; /* for relative paths; NULL = current directory */
} sam_scene_parser;

/* sam_scene_values.c */

/* names[value], or "unknown" when `value` is outside the `count` names. */
const char *sam_scene_name_at(const char *const *names, size_t count, int value);

/* Absolute form of `path` (not NULL): itself when absolute, else joined to
 * `base_dir` (itself made absolute against the current directory; NULL or
 * "" means the current directory). Empty and "." components are dropped;
 * ".." is kept, since resolving it by text would be wrong across symbolic
 * links. Returns a malloc'd string the caller frees, or NULL when out of
 * memory or the current directory cannot be found. */
char *sam_scene_absolute_path(const char *base_dir, const char *path);

/* Records "name: out of memory" and returns SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_scene_out_of_memory(const sam_scene_parser *p);

/* Euclidean length of `v`. */
double sam_scene_length3(const double v[3]);

/* A non-zero array of 3 numbers at `path`, normalised into `out`. A vector
 * already of unit length within float rounding is kept bit for bit, so a
 * written scene reloads identically.
 * Errors: SAM_ERR_FORMAT (sam_json_vec3's, or a zero vector). */
sam_status sam_scene_get_direction(const sam_scene_parser *p, const cJSON *item, const char *path, float out[3]);

/* A file reference at `path`: a non-empty string resolved against the
 * scene's directory that names an existing regular file. On success `*out`
 * is a malloc'd absolute path the caller owns; on failure it is untouched.
 * Errors: SAM_ERR_FORMAT (not a string), SAM_ERR_IO (missing, not a
 * regular file, or the current directory unknown: naming the absolute
 * path). */
sam_status sam_scene_get_file(const sam_scene_parser *p, const cJSON *item, const char *path, char **out);

/* sam_scene.c */

/* 1 when `spec` names a profile preset (case-insensitively), else 0. */
int sam_scene_is_preset(const char *spec);

/* sam_scene_lights.c: "lights" (at most SAM_SCENE_MAX_LIGHTS; scene->lights
 * is allocated and light_count counts the lights read so far) and
 * "environment" (scene->environment). Errors: SAM_ERR_FORMAT, SAM_ERR_IO
 * (a missing environment map), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_scene_parse_lights(const sam_scene_parser *p, const cJSON *item, sam_scene *scene);
sam_status sam_scene_parse_environment(const sam_scene_parser *p, const cJSON *item, sam_scene *scene);

/* sam_scene_animation.c: "deformers" (at most SAM_DEFORM_MAX, into
 * scene->deformers) and "keyframes" (scene->keyframes is allocated and
 * keyframe_count counts the keyframes read so far). Errors:
 * SAM_ERR_FORMAT, SAM_ERR_IO (a missing keyframe mesh),
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_scene_parse_deformers(const sam_scene_parser *p, const cJSON *item, sam_scene *scene);
sam_status sam_scene_parse_keyframes(const sam_scene_parser *p, const cJSON *item, sam_scene *scene);

#endif
