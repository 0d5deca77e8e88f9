/* Texture-space diffusion (d'Eon et al. 2007) with Jimenez and Gutierrez's
 * culled, clipped and depth-sized atlases (state in rt->tsd). Calls the
 * techniques, the shadows and the surface. Not installed. */
#ifndef SAM_RUNTIME_TSD_H
#define SAM_RUNTIME_TSD_H

#include "sam_runtime_internal.h"

/* Step 8 of sam_runtime_create: whether the .sam's `uvs` (2 per vertex, or
 * NULL) can carry an atlas (charts that do not overlap once moved into
 * [0, 1]^2 by sam_uv_fit_atlas), and
 * the three programs. The UVs themselves are a mesh buffer (SAM_B_UVS).
 * Errors: those of sam_uv_check, SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_tsd_create(sam_runtime *rt, const samfile_data *sam, sam_error *err);
void sam_runtime_tsd_destroy(sam_runtime *rt);

/* Runs texture-space diffusion of the entering light for `view` (view_proj
 * its camera matrix, proj its projection) into rt->tsd.atlas_tex[ATLAS_SUM]
 * with translucency `mode` (override_tex: the override's texture or 0);
 * sets rt->tsd.atlas_used. `tsm`: front light goes in whatever view->front
 * says, and every level is kept for the TSMs. Errors:
 * SAM_ERR_INVALID_ARGUMENT (atlas size), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_texture_space(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *view_proj,
                                     const sam_mat4 *proj, int mode, GLuint override_tex, int tsm, sam_error *err);

/* The atlas side `view` asks for (options.atlas_size or the default). */
uint32_t sam_runtime_atlas_size(const sam_render_view *view);

/* Draws the mesh unwrapped into the bound framebuffer's side x side corner
 * with the texture-space program: the entering light and stretch map, or
 * with `gbuffer` the position and normal (no culling or clipping). */
void sam_runtime_draw_atlas(sam_runtime *rt, const sam_render_view *view, const sam_mat4 *view_proj,
                            const sam_mat4 *proj, uint32_t side, int mode, GLuint override_tex, int front,
                            int gbuffer);

#endif
