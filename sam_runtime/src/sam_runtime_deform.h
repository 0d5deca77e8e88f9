/* Deformation and the sample walk (Sec. 3.4): the rest pose kept on the
 * GPU, deformers and keyframes, the posed positions, normals, fan areas,
 * curvature and bounds, and the walk of the samples (state in
 * rt->deform). Calls no other pass. Not installed. */
#ifndef SAM_RUNTIME_DEFORM_H
#define SAM_RUNTIME_DEFORM_H

#include "sam_runtime_internal.h"

/* Step 4 of sam_runtime_create: the deform, normals and walk programs.
 * Errors: SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_deform_create(sam_runtime *rt, sam_error *err);
void sam_runtime_deform_destroy(sam_runtime *rt);

#endif
