/* Shadow maps of the shadowed lights, rendered from the current positions
 * (state in rt->shadows). Calls no other pass. Not installed. */
#ifndef SAM_RUNTIME_SHADOWS_H
#define SAM_RUNTIME_SHADOWS_H

#include "sam_runtime_internal.h"

/* Step 3 of sam_runtime_create: the depth program and framebuffer (the maps
 * themselves come on first use). Errors: SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_shadows_create(sam_runtime *rt, sam_error *err);
void sam_runtime_shadows_destroy(sam_runtime *rt);

/* Renders every shadowed light's map from the current positions and bounds. */
void sam_runtime_render_shadows(sam_runtime *rt);

/* Binds the shadow maps and their uniforms (shadows.glsl) to program p. */
void sam_runtime_bind_shadows(const sam_runtime *rt, GLuint p);

/* The view-projection of face `face` of a cube map at `origin` reaching
 * `far_plane` (the shadow maps' and the TSMs'). */
sam_mat4 sam_runtime_cube_face(const float origin[3], float far_plane, int face);

/* One step of a walk over the shadowed lights (sam_runtime_next_shadow). */
typedef struct sam_runtime_shadow {
    uint32_t light; /* index in rt->lights.lights */
    int cube;       /* 1: a cube map (area lights, point lights close to the object); 0: a flat map (the others) */
    uint32_t map;   /* its index among the cube maps, or among the flat ones */
    uint32_t next, cubes, flats; /* the walk's own state */
} sam_runtime_shadow;

/* Steps `s` (zeroed before the first call) to the next shadowed light and
 * returns 1; 0 after the last. The maps are numbered as
 * sam_runtime_set_lights numbers them for the shaders, so every pass that
 * draws them walks this way. */
int sam_runtime_next_shadow(const sam_runtime *rt, sam_runtime_shadow *s);

#endif
