/* The rest-K pass: each stored sample's K at the rest pose, K = K' F'_b
 * R_d(|v_b - v|) (eq. 15), computed once into a buffer beside the samples
 * (12 bytes per stored sample) so that the rest pose's translucency pass
 * reads K instead of evaluating R_d per sample every frame, and a posed
 * frame reads a tree node's rest K (state in rt->rest_k; the mode is
 * sam_runtime_set_rest_k's). Calls the node pass. Not installed.
 *
 * Order: sam_runtime_rest_k_create once, after the node pass's create and
 * before the translucency pass's; then sam_runtime_rest_k_fill and
 * sam_runtime_rest_k_release as the mode changes. */
#ifndef SAM_RUNTIME_REST_K_H
#define SAM_RUNTIME_REST_K_H

#include "sam_runtime_internal.h"

/* Part of sam_runtime_create (the buffers hold the rest pose): compiles the
 * pass and fills the buffer. A GL that cannot hold the buffer leaves the
 * runtime in SAM_REST_K_EVALUATED instead of failing. Errors:
 * SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_rest_k_create(sam_runtime *rt, sam_error *err);
void sam_runtime_rest_k_destroy(sam_runtime *rt);

/* Allocates the buffer when it is missing and computes every sample's rest
 * K into it, from the rest pose whether or not the live buffers hold it
 * now. Errors: SAM_ERR_OUT_OF_MEMORY (the buffer is then freed),
 * SAM_ERR_UNSUPPORTED (larger than a storage block may be). */
sam_status sam_runtime_rest_k_fill(sam_runtime *rt, sam_error *err);

/* Frees the buffer (the evaluated mode needs none). */
void sam_runtime_rest_k_release(sam_runtime *rt);

#endif
