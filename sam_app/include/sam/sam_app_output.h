/*
 * sam_app_output: the tools' outputs checked before any work, so that a
 * long build or render never ends in "cannot write".
 */
#ifndef SAM_APP_OUTPUT_H
#define SAM_APP_OUTPUT_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Whether a file can be written at `path`: its folder exists and is
 * writable, `path` is not a folder or another non-regular file, and it is
 * no existing file unless `force` (the tools' --force). When
 * `extensions` is not NULL (a NULL-terminated list such as {".png", ".exr",
 * NULL}) the name must end in one of them (case-insensitive). `what` names
 * the output in messages (e.g. "-o"). Whether the folder takes a new file
 * is asked by creating (and at once removing) a hidden probe file there,
 * since permission bits do not tell (root, sysfs, read-only mounts); it
 * leaves nothing behind.
 * Errors: SAM_ERR_INVALID_ARGUMENT naming `what`, the path and the reason. */
sam_status sam_app_check_output(const char *what, const char *path, const char *const *extensions, int force,
                                sam_error *err);

/* 1 when `path` ends in `extension` (case-insensitive). */
int sam_app_has_extension(const char *path, const char *extension);

#ifdef __cplusplus
}
#endif

#endif
