/* The comparison techniques' GL side: the uniforms of technique.glsl
 * (transmittance, the translucency override) and the translucent shadow
 * maps (state in rt->technique). Calls the shadows and the thickness pass's
 * binding. Not installed. */
#ifndef SAM_RUNTIME_TECHNIQUE_H
#define SAM_RUNTIME_TECHNIQUE_H

#include "sam_runtime_internal.h"

/* Step 7 of sam_runtime_create: the TSM program and the sampler that reads
 * shadow maps as distances. Errors: SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_technique_create(sam_runtime *rt, sam_error *err);
void sam_runtime_technique_destroy(sam_runtime *rt);

/* The translucency source of `view`'s passes (TECHNIQUE_*). */
int sam_runtime_technique_mode(const sam_render_view *view);

/* Sets technique.glsl's uniforms for program p: `mode`, the fit, the
 * shadow maps read as distances, and `override_tex` (0: none) on its unit;
 * for TECHNIQUE_THICKNESS also binds that pass's T where T is read, so
 * call it after sam_runtime_bind_buffers. */
void sam_runtime_bind_technique(const sam_runtime *rt, GLuint p, int mode, GLuint override_tex);

/* Binds tsm_read.glsl's maps for program p (the shading program); the
 * levels and stretch map come from the last texture-space render. */
void sam_runtime_bind_tsm(const sam_runtime *rt, GLuint p);

/* Renders a TSM for every shadowed point, spot and directional light, from
 * the shadow maps' last positions. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_render_tsm(sam_runtime *rt, sam_error *err);

#endif
