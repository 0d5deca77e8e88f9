/*
 * sam_viewer_load: what the viewer shows, before any window: the scene of
 * its input (a scene file, or one made for a bare mesh or .sam) and the
 * default lights of a bare input. The map comes from the tools' shared
 * cache (sam_app_cache.h). Needs no GL.
 */
#ifndef SAM_VIEWER_LOAD_H
#define SAM_VIEWER_LOAD_H

#include <stddef.h>

#include "sam/sam_app_stage.h"
#include "sam/sam_common.h"
#include "sam/sam_profile.h"
#include "sam/sam_scene.h"
#include "sam/samfile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What sam_view was given. */
typedef enum sam_viewer_input {
    SAM_VIEWER_INPUT_SCENE, /* a scene file */
    SAM_VIEWER_INPUT_SAM,   /* a bare .sam: sam_viewer_default_lights lights it */
    SAM_VIEWER_INPUT_MESH   /* a bare mesh, staged: its back light is placed on the runtime */
} sam_viewer_input;

/* The scene of `input`: a scene file (.json) is loaded; a mesh gets the
 * staged scene sam_render gives it with the `stage` options (size, up axis;
 * NULL: those of sam_app_stage_defaults; the assumptions printed on stderr); a .sam
 * gets a scene naming it and no lights. `material` may be NULL (the .sam's
 * own, or skin for a mesh), the lat-long `environment` EXR too. `*kind`
 * (may be NULL) says which it was. `scene` is the caller's, freed with
 * sam_scene_destroy whatever the result.
 * Errors: SAM_ERR_INVALID_ARGUMENT (`material` or `environment` given with
 * a scene file, an up axis with a scene file or .sam), SAM_ERR_IO (no
 * environment file), and those of
 * sam_scene_load, sam_scene_parse and sam_app_stage_scene. */
sam_status sam_viewer_load_scene(const char *input, const char *material, const sam_app_stage_options *stage,
                                 const char *environment, sam_scene *scene, sam_viewer_input *kind, sam_error *err);

/* Replaces the scene's lights (it must have none) with two point lights
 * about the object at `centre` of `radius`: one behind it as the camera
 * starts (-Z) that shines through its thin parts, and a dim one in front so
 * its shape reads. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_viewer_default_lights(sam_scene *scene, const float centre[3], float radius, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
