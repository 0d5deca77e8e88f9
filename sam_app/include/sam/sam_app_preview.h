/*
 * sam_app_preview: sam_preview's job as a library call: the translucency a
 * .sam encodes, drawn on the CPU with no GL, so a map can be looked at on
 * any machine.
 *
 * Step by step, sam_app_preview_write: reads the map and the material and
 * scale its INFO records, places an orthographic camera along the object's
 * thinnest extent (or the axis asked for) and a point light behind the
 * object, computes L_d at every vertex with Embree shadow rays, sums the
 * stored samples (SAM eq. 12), exposes on the 95th percentile of the lit
 * vertices, adds a dim grey headlight that shows the shape, rasterises and
 * writes an sRGB PNG atomically. Its own library (sam_app_preview) because
 * it links Embree; it links no builder or GL code.
 */
#ifndef SAM_APP_PREVIEW_H
#define SAM_APP_PREVIEW_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_app_preview_job {
    const char *in;   /* the .sam (required) */
    const char *out;  /* the PNG (required) */
    long size;        /* image side in pixels, 16..4096 (default 512) */
    int axis;         /* -1: the thinnest extent; 0, 1, 2: x, y, z */
    int sign;         /* 1: the camera on the +axis side looking back; -1: the other side */
} sam_app_preview_job;

void sam_app_preview_defaults(sam_app_preview_job *job);

/* Runs `job` and prints one line on stderr (prefixed with `tool`) naming
 * what it wrote. Errors: those of samfile_read and samfile_info_read,
 * SAM_ERR_FORMAT (INFO records no material), SAM_ERR_INVALID_ARGUMENT (a
 * size or axis out of range), SAM_ERR_OUT_OF_MEMORY, and those of
 * sam_image_write_png. */
sam_status sam_app_preview_write(const sam_app_preview_job *job, const char *tool, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
