/* The local-thickness technique's pass: each vertex's back-side light
 * through a slab of its thickness (shaders/thickness.comp), into a T of its
 * own that shading reads in SAM's T's place (state in rt->thickness).
 * Calls the surface's uniforms only. Not installed. */
#ifndef SAM_RUNTIME_THICKNESS_H
#define SAM_RUNTIME_THICKNESS_H

#include "sam_runtime_internal.h"

/* Step 11 of sam_runtime_create: the program and its two buffers (filled by
 * sam_runtime_set_thickness). Errors: SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_thickness_create(sam_runtime *rt, sam_error *err);
void sam_runtime_thickness_destroy(sam_runtime *rt);

/* Runs the pass from the current lights, environment, positions and
 * normals, timed as SAM_PASS_TRANSLUCENCY. Errors: SAM_ERR_INVALID_ARGUMENT
 * when no thickness was given. */
sam_status sam_runtime_thickness_pass(sam_runtime *rt, sam_error *err);

/* Binds the pass's T where shading reads T (SAM_B_TRANSLUCENCY), after
 * sam_runtime_bind_buffers bound SAM's there. */
void sam_runtime_bind_thickness(const sam_runtime *rt);

#endif
