/* The translucency pass: eq. 12 over each vertex's samples and the
 * temporal smoothing of eq. 17-18 (state in rt->translucency). Not
 * installed. */
#ifndef SAM_RUNTIME_TRANSLUCENCY_H
#define SAM_RUNTIME_TRANSLUCENCY_H

#include "sam_runtime_internal.h"

/* Part of sam_runtime_create, after the rest-K pass's: the pass's three
 * programs of the rest-K mode in use (the rest pose, a posed K carried
 * from rest, a posed K by eq. 15); the other mode's are compiled when
 * sam_runtime_set_rest_k first chooses it. Errors: SAM_ERR_FORMAT (shader
 * errors). */
sam_status sam_runtime_translucency_create(sam_runtime *rt, sam_error *err);
void sam_runtime_translucency_destroy(sam_runtime *rt);

#endif
