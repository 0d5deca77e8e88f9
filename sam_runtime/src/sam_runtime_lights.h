/* The lights and the environment (sam_runtime_set_lights,
 * sam_runtime_set_environment; state in rt->lights). Not installed. */
#ifndef SAM_RUNTIME_LIGHTS_H
#define SAM_RUNTIME_LIGHTS_H

#include "sam_runtime_internal.h"

/* Step 1 of sam_runtime_create: an empty lights buffer, so every pass that
 * declares it has one bound. Errors as sam_runtime_upload. */
sam_status sam_runtime_lights_create(sam_runtime *rt, sam_error *err);
void sam_runtime_lights_destroy(sam_runtime *rt);

/* The vector from `p` to the object's centre (rt->centre) into `d` (3
 * floats); returns its length, model units. */
float sam_runtime_to_centre(const sam_runtime *rt, const float p[3], float d[3]);

/* The half-angle, in radians, of the cone that the object's bounding
 * sphere (rt->centre, rt->radius, widened by the shadow lookups' reach)
 * fills seen from `position`; pi/2 from inside it. A point light's 2D
 * shadow map is fitted to this cone. */
float sam_runtime_object_half_angle(const sam_runtime *rt, const float position[3]);

#endif
