/* The engine's own vertex buffers as the pose, and T handed back in the
 * engine's vertex order (state in rt->engine). Not installed. */
#ifndef SAM_RUNTIME_ENGINE_H
#define SAM_RUNTIME_ENGINE_H

#include "sam_runtime_internal.h"

/* Part of sam_runtime_create: the engine's vertex order from the .sam's
 * SRCV chunk (identity without one); the programs wait for the first
 * engine call. Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_runtime_engine_create(sam_runtime *rt, const samfile_data *sam, sam_error *err);
void sam_runtime_engine_destroy(sam_runtime *rt);

#endif
