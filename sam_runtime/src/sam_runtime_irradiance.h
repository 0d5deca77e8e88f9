/* The irradiance pass: shadow maps, then L_d at every vertex (eq. 4; state
 * in rt->irradiance). Not installed. */
#ifndef SAM_RUNTIME_IRRADIANCE_H
#define SAM_RUNTIME_IRRADIANCE_H

#include "sam_runtime_internal.h"

/* Step 5 of sam_runtime_create: the irradiance program. Errors:
 * SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_irradiance_create(sam_runtime *rt, sam_error *err);
void sam_runtime_irradiance_destroy(sam_runtime *rt);

#endif
