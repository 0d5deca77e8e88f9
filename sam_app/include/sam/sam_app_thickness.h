/*
 * sam_app_thickness: a map's per-vertex local thickness for the
 * local-thickness technique, as the programs that render it (sam_render,
 * sam_view, sam_compare) measure it once on load: sam_thickness_compute
 * on the .sam's render vertices with the default rays, a progress bar on
 * stderr once it has run for a second. Part of the sam_app_build library:
 * links the builder.
 */
#ifndef SAM_APP_THICKNESS_H
#define SAM_APP_THICKNESS_H

#include "sam/samfile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The thickness in mm of every vertex of `sam` at `mm_per_unit` into a new
 * array `*mm` of sam->vertex_count floats (the caller frees it; NULL on
 * failure). `tool` names the progress lines (NULL: silent); a bar or, in a
 * log, a line per 10%, and a line with the time taken, appear only when the
 * work takes over a second.
 * Errors: those of sam_thickness_compute, SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_app_thickness(const samfile_data *sam, float mm_per_unit, const char *tool, float **mm,
                             sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
