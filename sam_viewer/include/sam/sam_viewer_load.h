/*
 * sam_viewer_load: what the viewer shows, before any window: the scene of
 * its input (a scene file, or one made for a bare mesh or .sam), the map
 * read from a cache or built with a progress bar and cached, and the
 * default lights of a bare input.
 *
 * Needs no GL; the map's build links the builder (sam_app_scene.h, in
 * sam_app_build). A map is cached under a name from the mesh's SHA-256 and
 * everything else the build depends on (material, scale, the build
 * settings), so a changed mesh, material or scale never reads a stale map.
 */
#ifndef SAM_VIEWER_LOAD_H
#define SAM_VIEWER_LOAD_H

#include <stddef.h>

#include "sam/sam_common.h"
#include "sam/sam_profile.h"
#include "sam/sam_scene.h"
#include "sam/samfile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The scene of `input`: a scene file (.json) is loaded; a .sam or a mesh
 * gets a scene naming it, with `material` (may be NULL: the .sam's own, or
 * skin for a mesh), a mesh's bounding-box diagonal of `size_mm` and the
 * lat-long `environment` EXR (may be NULL). `*is_scene` (may be NULL) is
 * set to 1 for a scene file. `scene` is the caller's, freed with
 * sam_scene_destroy whatever the result.
 * Errors: SAM_ERR_INVALID_ARGUMENT (`material` or `environment` given with
 * a scene file), and those of sam_scene_load and sam_scene_parse. */
sam_status sam_viewer_load_scene(const char *input, const char *material, float size_mm, const char *environment,
                                 sam_scene *scene, int *is_scene, sam_error *err);

/* The cache folder into `out` of `n` bytes: `given` when not NULL, else
 * $XDG_CACHE_HOME/sam_view, ~/.cache/sam_view or /tmp/.cache/sam_view. */
void sam_viewer_cache_dir(const char *given, char *out, size_t n);

/* The scene's map into `sam` (the caller frees it with samfile_free), with
 * the material's `profile` and the scene's `mm_per_unit`. A scene naming a
 * mesh and no .sam reads the map from `cache_dir` when `use_cache` and it is
 * there (a damaged entry is rebuilt), else builds it with a progress bar on
 * stderr (SIGINT/SIGTERM cancel the build) and caches it; the scene then
 * names the cached .sam, so screenshots need no build. A cache that cannot
 * be written is a warning.
 * Errors: those of sam_app_scene_object and sam_sha256_file;
 * SAM_ERR_INVALID_ARGUMENT for a cache path too long. */
sam_status sam_viewer_load_map(sam_scene *scene, const char *cache_dir, int use_cache, samfile_data *sam,
                               sam_profile *profile, float *mm_per_unit, sam_error *err);

/* Replaces the scene's lights (it must have none) with two point lights
 * about the object at `centre` of `radius`: one behind it as the camera
 * starts (-Z) that shines through its thin parts, and a dim one in front so
 * its shape reads. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_viewer_default_lights(sam_scene *scene, const float centre[3], float radius, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
