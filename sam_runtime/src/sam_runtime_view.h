/* The view: the shading pass into view-sized targets, the diffusion
 * techniques around it, and the G-buffer (state in rt->view). Calls the
 * texture space, the techniques, the local diffusions, the shadows and the
 * surface. Not installed. */
#ifndef SAM_RUNTIME_VIEW_H
#define SAM_RUNTIME_VIEW_H

#include "sam_runtime_internal.h"

/* Step 10 of sam_runtime_create: the shading program (the targets come with
 * the first render). Errors: SAM_ERR_FORMAT (shader errors). */
sam_status sam_runtime_view_create(sam_runtime *rt, sam_error *err);
void sam_runtime_view_destroy(sam_runtime *rt);

#endif
