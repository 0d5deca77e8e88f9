/*
 * sam_runtime_scene: a scene file (sam_scene.h) applied to a runtime, so
 * every tool that renders scenes (sam_render, sam_compare, the benchmarks)
 * lights, frames and shades them the same way.
 *
 * Needs what sam_runtime needs: a current GL context on the calling thread.
 */
#ifndef SAM_RUNTIME_SCENE_H
#define SAM_RUNTIME_SCENE_H

#include "sam/sam_runtime.h"
#include "sam/sam_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Gives `rt` the scene's lights, its deformers (posed by
 * sam_runtime_deform), its environment (the lat-long map's SH-9 radiance,
 * rotated and scaled as the scene says), its albedo maps and its vertex
 * colours, replacing any an earlier setup gave. Keyframes need the .sam
 * as well: sam_runtime_scene_keyframes.
 * `sh` (may be NULL) receives the environment's SH and `*has_environment`
 * (may be NULL) whether there is one, for CPU references that must light
 * the object alike. `warning` (size n, may be NULL) gets one line when
 * something of the scene is left out but the render can go on (an albedo
 * map on a mesh without UVs), else "".
 * Without an "albedo_map" the mesh file's own texture is used, if it
 * brings one (sam_mesh_load_albedo); one it names but that cannot be read
 * is a warning. A file whose faces read several (sam_mesh_load_albedo_maps)
 * gives each its triangles (the mesh is loaded again for its faces,
 * sam_runtime_set_albedo_maps); maps the runtime cannot take are a
 * warning. Unless "vertex_colors" is false, the mesh file's vertex
 * colours are set too (sam_mesh_load_vertex_colors,
 * sam_runtime_set_vertex_colors); colours of another vertex count than
 * the map's mesh (a map without SRCV) are a warning, added after any
 * other with "; ".
 * Errors: those of sam_image_read_exr / sam_image_read_picture (naming the
 * file), sam_mesh_load_albedo, sam_mesh_load_albedo_maps, sam_mesh_load,
 * sam_runtime_set_albedo_maps (but its SAM_ERR_INVALID_ARGUMENT and
 * SAM_ERR_UNSUPPORTED), sam_mesh_load_vertex_colors,
 * sam_light_sh9_from_latlong, sam_runtime_set_lights,
 * sam_runtime_set_deformers, sam_runtime_set_albedo_map and
 * sam_runtime_set_vertex_colors (but its SAM_ERR_INVALID_ARGUMENT). */
sam_status sam_runtime_scene_setup(sam_runtime *rt, const sam_scene *scene, float sh[9][3], int *has_environment,
                                   char *warning, size_t n, sam_error *err);

/* Loads the scene's keyframe meshes (sam_mesh_load) and gives them to `rt`
 * (sam_runtime_set_keyframes); `sam` is the map `rt` was created from. A
 * scene without keyframes removes any earlier ones. Each mesh must have the
 * rest mesh's topology: as many render vertices as the .sam and the same
 * triangles (TRI), in the same order.
 * Errors: sam_mesh_load's (naming the file), SAM_ERR_FORMAT for a mesh of
 * another topology, naming the file and the first difference ("pose1.obj:
 * 1030 vertices, the rest mesh has 1032", "pose1.obj: triangle 17 is
 * (4, 9, 12), the rest mesh's is (4, 9, 13)"), sam_runtime_set_keyframes',
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_scene_keyframes(sam_runtime *rt, const sam_scene *scene, const samfile_data *sam,
                                       sam_error *err);

/* The check sam_runtime_scene_keyframes makes, without a runtime (for
 * sam_info): loads the rest topology (the scene's .sam, or its mesh turned
 * outward as a build turns it) and every keyframe mesh, and compares them.
 * SAM_OK for a scene without keyframes.
 * Errors: those of sam_runtime_scene_keyframes, samfile_read's,
 * SAM_ERR_INVALID_ARGUMENT (NULL scene). */
sam_status sam_runtime_scene_check_keyframes(const sam_scene *scene, sam_error *err);

/* The scene's view: its resolution, camera (or, without one, the bounding
 * sphere framed with a 40 degree field of view from the front
 * sam_scene_default_axes gives: +Z for most meshes, -Y for a Z-up scan), albedo and
 * diffusion settings, front lighting on, technique SAM. Texture-space
 * diffusion on a runtime whose UVs cannot carry it falls back to screen
 * space, and `warning` (size n, may be NULL) says why; else it gets "". */
void sam_runtime_scene_view(const sam_runtime *rt, const sam_scene *scene, sam_render_view *view, char *warning,
                            size_t n);

#ifdef __cplusplus
}
#endif

#endif
