/*
 * sam_common: status codes, error messages and atomic file output shared by
 * every module of sam_core.
 *
 * Error model (after OpenEXR Core): every fallible function returns a
 * sam_status and, when it fails, fills a caller-provided sam_error with one
 * line that names the file, chunk, line or key and the values found. A NULL
 * sam_error is allowed everywhere; the status is still returned.
 *
 * No function here keeps global state.
 */
#ifndef SAM_COMMON_H
#define SAM_COMMON_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sam_status {
    SAM_OK = 0,
    SAM_ERR_INVALID_ARGUMENT, /* a caller passed a value outside the contract */
    SAM_ERR_IO,               /* open/read/write/rename failed (errno text in the message) */
    SAM_ERR_FORMAT,           /* input is malformed: bad magic, syntax, truncated, out-of-range */
    SAM_ERR_CORRUPT,          /* input is well formed but fails a checksum or consistency check */
    SAM_ERR_UNSUPPORTED,      /* a valid input this build cannot handle (version, extension) */
    SAM_ERR_OUT_OF_MEMORY,
    SAM_ERR_EMPTY             /* the input holds nothing usable (e.g. a mesh with no triangles) */
} sam_status;

#define SAM_ERROR_MESSAGE_SIZE 1024

typedef struct sam_error {
    sam_status status;
    char message[SAM_ERROR_MESSAGE_SIZE];
} sam_error;

/* Short fixed name of a status ("io error", ...). Never NULL. */
const char *sam_status_name(sam_status status);

/* Records `status` and a printf-formatted message in `err` (may be NULL) and
 * returns `status`, so a failure site reads `return sam_fail(err, ...);`.
 * A message longer than the buffer is truncated, never overrun. */
sam_status sam_fail(sam_error *err, sam_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Clears `err` (may be NULL) to SAM_OK and an empty message. */
void sam_error_clear(sam_error *err);

/*
 * Atomic output: data goes to "<path>.tmp.<pid>.<n>" beside the target and is
 * renamed over `path` only by sam_atomic_commit, after fflush and fsync. A
 * writer that fails calls sam_atomic_abort, which deletes the temporary file,
 * so a reader never sees a half-written file and an existing target survives
 * a failed write.
 */
typedef struct sam_atomic_file {
    FILE *fp;         /* write through this between open and commit/abort */
    char *path;       /* final path (owned) */
    char *temp_path;  /* temporary path (owned) */
} sam_atomic_file;

/* Opens a temporary file next to `path` ("PATH.tmp.PID.N") for binary
 * writing. Temporaries of PATH that a killed writer left (no process of
 * their PID is alive) are removed first, so they never pile up.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL/empty path), SAM_ERR_IO (cannot
 * create the temporary file: the message names it and strerror). */
sam_status sam_atomic_open(sam_atomic_file *file, const char *path, sam_error *err);

/* Flushes, syncs, closes and renames the temporary file onto the final path,
 * then frees the paths. On any failure the temporary file is removed and
 * SAM_ERR_IO returned; `file` is released either way. */
sam_status sam_atomic_commit(sam_atomic_file *file, sam_error *err);

/* Closes and deletes the temporary file and frees the paths. Safe on a file
 * that was never opened successfully or was already committed (zeroed). */
void sam_atomic_abort(sam_atomic_file *file);

/* Reads a whole file into a newly malloc'd buffer (caller frees) with a
 * terminating NUL byte after the data (not counted in *size), so text
 * parsers can use it directly. Only regular files are read: a directory,
 * device, pipe or socket (a link to /dev/zero would never end) is refused
 * (sam_check_regular_file). Errors: SAM_ERR_IO. */
sam_status sam_read_file(const char *path, uint8_t **data, size_t *size, sam_error *err);

/* SAM_OK when `path` names a regular file (after following links).
 * Errors: SAM_ERR_IO, "PATH: cannot open: REASON" when it does not exist or
 * cannot be examined, "PATH: not a regular file (a directory)" (or device,
 * pipe, socket) otherwise. */
sam_status sam_check_regular_file(const char *path, sam_error *err);

/* malloc'd copy of a NUL-terminated string (caller frees), NULL when out of memory. */
char *sam_strdup(const char *s);

/* A text that grows as it is written: start from {0}, append, then the
 * caller frees p. p stays NUL-terminated (NULL until the first append).
 * `oom` is set when an append ran out of memory; later appends then do
 * nothing, so a writer checks it once at the end. */
typedef struct sam_text {
    char *p;
    size_t len, cap; /* bytes written (without the NUL), bytes held */
    int oom;
} sam_text;

/* Appends the n bytes at s (s may hold NULs; n may be 0). */
void sam_text_append(sam_text *text, const char *s, size_t n);

/* 1 when all of `text` (non-empty) is a finite number strtod reads without
 * a range error, stored in `*out`; 0 otherwise (`*out` untouched). For the
 * tools' numeric options; the range and the message are the caller's. */
int sam_parse_double(const char *text, double *out);

/* Seconds on a monotonic clock (for durations, progress and benchmarks). */
double sam_seconds(void);

/* Returns a pointer to the file name part of `path` (after the last '/'). */
const char *sam_path_basename(const char *path);

/* Case-insensitive test that `path` ends with `suffix` (e.g. ".obj"). */
int sam_path_has_extension(const char *path, const char *suffix);

#ifdef __cplusplus
}
#endif

#endif
