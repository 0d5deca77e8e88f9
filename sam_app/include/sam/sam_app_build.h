/*
 * sam_app_build: sam_build's job as a library call: a mesh file and a
 * material in, a .sam file out, with the progress bar and a summary line on
 * stderr.
 *
 * Step by step, sam_app_build_run: checks the settings and that the output
 * can be written (before any long work), loads and repairs the mesh (one
 * line when it repaired something), scales it, builds the map, writes it
 * atomically, and prints what it wrote. Links the builder.
 */
#ifndef SAM_APP_BUILD_H
#define SAM_APP_BUILD_H

#include <signal.h>

#include "sam/sam_build.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_app_build_job {
    const char *mesh_path;        /* required */
    const char *out_path;         /* required; replaced only with `force` */
    const char *material;         /* a preset name or a profile file (sam_profile_from_spec); required */
    float mm_per_unit;            /* NAN, or millimetres per model unit */
    float size_mm;                /* NAN, or the bounding-box diagonal in mm; exactly one of the two */
    sam_build_settings settings;  /* sam_build_default_settings, then the caller's changes */
    int force, quiet;
    int keep_orientation;         /* 1: a closed mesh facing inward stays so (else turned out, with a warning) */
    volatile sig_atomic_t *cancel; /* non-zero stops the build, leaving no output; may be NULL */
} sam_app_build_job;

/* Defaults: no paths, no scale, the builder's default settings. */
void sam_app_build_defaults(sam_app_build_job *job);

/* Runs `job`. Returns 0 on success, 2 for arguments that cannot work
 * (both or neither scale, a size <= 0, settings out of range), 1 for any
 * other failure (a missing or bad mesh or material, an existing output
 * without force, I/O, a cancelled build); each failure prints one line on
 * stderr prefixed with `tool`. */
int sam_app_build_run(const sam_app_build_job *job, const char *tool);

#ifdef __cplusplus
}
#endif

#endif
