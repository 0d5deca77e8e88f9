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

/* Keeps the current positions, normals, fan areas, samples and curvature
 * as the rest pose, once (later calls do nothing): every pose is computed,
 * and a posed K carried, from it. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_deform_keep_rest(sam_runtime *rt, sam_error *err);

/* After a pass wrote posed positions, inside the caller's SAM_PASS_DEFORM
 * timer: the pose's normals, fan areas, curvature and bounds. */
void sam_runtime_deform_finish(sam_runtime *rt);

/* After the timer: the pose's box from those bounds (one 24-byte read-back,
 * which waits for the passes), and the barrier that lets the draws read
 * the posed positions and normals. */
void sam_runtime_deform_read_box(sam_runtime *rt);

#endif
