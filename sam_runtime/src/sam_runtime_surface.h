/* The surface's reflection: rho_dt (the light the specular lobe leaves to
 * enter the surface), its table on the GPU, the albedo map (state in
 * rt->surface) and where the UVs lie in the atlas. Not installed. */
#ifndef SAM_RUNTIME_SURFACE_H
#define SAM_RUNTIME_SURFACE_H

#include "sam_runtime_internal.h"

/* Step 2 of sam_runtime_create: the rho_dt table on the GPU, the default
 * lobe (d'Eon's skin), and the order of `sam`'s source vertices, which
 * sam_runtime_set_vertex_colors takes colours in. Errors: those of
 * sam_brdf_rho_dt_table and sam_runtime_upload, SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_surface_create(sam_runtime *rt, const samfile_data *sam, sam_error *err);
void sam_runtime_surface_destroy(sam_runtime *rt);

/* Sets surface.glsl's uniforms (the irradiance and shading passes share
 * them) for the current program p. */
void sam_runtime_set_surface_uniforms(const sam_runtime *rt, GLuint p);

/* Binds the albedo map (or a white texel's absence: u_has_albedo_map = 0)
 * for the current program p, and sets the vertex colours' attribute (3)
 * to white where the mesh has none: a disabled array reads the context's
 * current value, which a host may have changed. */
void sam_runtime_bind_albedo(const sam_runtime *rt, GLuint p);

/* Sets the program's u_uv_atlas (uv_atlas.glsl) to where the UVs lie in
 * the texture-space atlas (rt->tsd.uv_atlas, set by sam_runtime_tsd_create). */
void sam_runtime_bind_uv_atlas(const sam_runtime *rt, GLuint p);

#endif
