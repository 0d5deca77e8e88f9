/*
 * sam_app_scene: a scene's object as a map, read from its .sam or built from
 * its mesh, for the tools that render scenes (sam_render, sam_compare,
 * sam_view, the benchmarks). Part of the sam_app_build library: links the
 * builder.
 */
#ifndef SAM_APP_SCENE_H
#define SAM_APP_SCENE_H

#include "sam/sam_build.h"
#include "sam/sam_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The object of a scene as a map, for the tools that render scenes: a
 * scene naming a .sam has it read (checked against the scene's mesh, when it
 * names one too, by the SHA-256 INFO records), its material and scale taken
 * from the scene where given, else from INFO; a scene naming only a mesh has
 * its map built with `settings` (NULL: the defaults, a cut map) and the scene's
 * material and scale, `progress` as in sam_build_run (may be NULL), and
 * INFO recording the mesh's path and SHA-256 so a saved copy can be checked.
 * `*built_seconds` (may be NULL) gets the build time, 0 when read.
 * On success the caller frees `sam` with samfile_free; on failure it is
 * zeroed. Errors: those of samfile_read, samfile_info_read, sam_mesh_load
 * and sam_build_samfile; SAM_ERR_FORMAT when the .sam records no material
 * or scale the scene does not give, or was built from another mesh (the
 * message names both files and their hashes). A prebuilt map given another
 * material or a scale more than 1% off its own by the scene gets a warning
 * on stderr: it was built for its own, and renders otherwise than a map
 * built for the scene's; so does a mesh wound inside out, which is turned
 * outside out. `tool` (may be NULL) prefixes those warnings. */
sam_status sam_app_scene_object(const sam_scene *scene, const char *tool, const sam_build_settings *settings,
                                sam_build_progress_fn progress, void *user, samfile_data *sam, sam_profile *profile,
                                float *mm_per_unit, double *built_seconds, sam_error *err);

/* A shallow copy of `scene` in *out whose map is built from its mesh with
 * `profile` and `mm_per_unit` (those sam_app_scene_object gave): how a tool
 * rebuilds a scene's map at another N or kind, also when the scene names a
 * prebuilt map. `out` shares the scene's strings and arrays: do not destroy
 * it, and do not use it after the scene is destroyed. The scene must name
 * a mesh. */
void sam_app_scene_from_mesh(const sam_scene *scene, const sam_profile *profile, float mm_per_unit,
                             sam_scene *out);

#ifdef __cplusplus
}
#endif

#endif
