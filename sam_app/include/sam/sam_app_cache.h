/*
 * sam_app_cache: one cache of the maps of bare meshes, shared by sam_render,
 * sam_view and sam_compare, so a mesh's map is built once whichever tool
 * renders it first. A map is cached under a name from the mesh's SHA-256
 * and everything else the build depends on (material, scale, the build
 * settings, the builder's SAM_BUILD_VERSION), so a changed mesh, material,
 * scale or builder never reads a stale map.
 * Part of sam_app_build: a map missing from the cache is built.
 */
#ifndef SAM_APP_CACHE_H
#define SAM_APP_CACHE_H

#include <stddef.h>

#include "sam/sam_build.h"
#include "sam/sam_scene.h"
#include "sam/samfile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The cache folder into `out` of `n` bytes: `given` when not NULL, else
 * $XDG_CACHE_HOME/sam, ~/.cache/sam or /tmp/.cache/sam. */
void sam_app_cache_dir(const char *given, char *out, size_t n);

/* The scene's map into `sam` (the caller frees it with samfile_free), with
 * the material's `profile` and the scene's `mm_per_unit`, built with
 * `settings` (NULL: the defaults), which are part of the cache's key.
 * `*built_seconds` (may be NULL) gets the build's time, the recorded one
 * for a cached map, 0 for a prebuilt .sam. A scene naming a mesh and no
 * .sam reads the map from
 * `cache_dir` when `use_cache` and it is there (a damaged entry is rebuilt
 * with a note), else builds it with a progress bar on stderr
 * (SIGINT/SIGTERM cancel the build) and caches it; the scene then names the
 * cached .sam, so a scene saved from it needs no build. A scene naming a
 * .sam has it read. Messages start with `tool`. A cache that cannot be
 * written is a warning.
 * Errors: those of sam_app_scene_object and sam_sha256_file;
 * SAM_ERR_INVALID_ARGUMENT for a cache path too long. */
sam_status sam_app_cache_object(sam_scene *scene, const sam_build_settings *settings, const char *cache_dir,
                                int use_cache, const char *tool, samfile_data *sam, sam_profile *profile,
                                float *mm_per_unit, double *built_seconds, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
