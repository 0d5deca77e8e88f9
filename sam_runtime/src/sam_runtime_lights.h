/* The lights and the environment (sam_runtime_set_lights,
 * sam_runtime_set_environment; state in rt->lights). Not installed. */
#ifndef SAM_RUNTIME_LIGHTS_H
#define SAM_RUNTIME_LIGHTS_H

#include "sam_runtime_internal.h"

/* Step 1 of sam_runtime_create: an empty lights buffer, so every pass that
 * declares it has one bound. Errors as sam_runtime_upload. */
sam_status sam_runtime_lights_create(sam_runtime *rt, sam_error *err);
void sam_runtime_lights_destroy(sam_runtime *rt);

/* 1 when light `l` casts a cube shadow map (point and area lights cast all
 * round), 0 for a flat one (spot and directional). */
int sam_runtime_light_casts_cube(const sam_light *l);

#endif
