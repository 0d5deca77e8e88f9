/*
 * sam_app: what the command-line programs share and a library embedding SAM
 * does not need: the build's progress bar on stderr and the signal handling
 * that cancels a build (sam_app_catch_interrupts). The option parser
 * (sam_args.h) is part of the same library. Two more libraries sit above
 * it: sam_app_build (sam_app_build.h, sam_app_scene.h: a map from a mesh or
 * a scene, sam_app_thickness.h: a map's local thickness; on the builder) and
 * sam_app_render (sam_app_render.h, on the runtime).
 *
 * sam_app depends on sam_core only. A renderer that loads prebuilt maps
 * reads the .sam with samfile_read and its material and scale with
 * samfile_info_read (samfile.h), and links no builder code.
 */
#ifndef SAM_APP_H
#define SAM_APP_H

#include <signal.h>

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A progress display on stderr for sam_build_progress_fn (sam_build.h): a carriage-return
 * bar with the vertex count, elapsed time and ETA on a terminal, a line per
 * 10% in a log (stderr not a terminal), nothing when quiet. */
typedef struct sam_app_progress {
    const char *tool;               /* names the log lines; the caller keeps it */
    double start;                   /* sam_seconds() at init */
    int tty, quiet, last_decile;
    int open_line;                  /* a bar is on screen without its newline: print one before a message */
    volatile sig_atomic_t *cancel;  /* non-zero cancels the build (a signal handler's flag); may be NULL */
} sam_app_progress;

/* Starts the clock; `tool` is not copied. */
void sam_app_progress_init(sam_app_progress *bar, const char *tool, int quiet, volatile sig_atomic_t *cancel);

/* A sam_build_progress_fn: `user` is a sam_app_progress. Returns non-zero
 * (cancel) once *cancel is set. */
int sam_app_progress_update(void *user, uint64_t done, uint64_t total);

/* Installs `handler` for SIGINT and SIGTERM, for one signal each: the
 * handler sets the flag that sam_app_progress_update turns into a clean
 * cancel, which is read between build steps only, so a second signal ends
 * the program at once (during a long load, say). `handler` NULL restores
 * the default action. */
void sam_app_catch_interrupts(void (*handler)(int));

#ifdef __cplusplus
}
#endif

#endif
