/*
 * sam_json: reading and checking JSON files (through cJSON) with messages
 * that name the file, the key's path and the value found, e.g.
 * "scene.json: lights[0].intensity: expected a number >= 0 (finite),
 * found -1". The scene parser (sam_scene.h) and the profile loader
 * (sam_profile_load) share this vocabulary: key paths, descriptions of
 * wrong values, allowed and repeated keys, typed values, and the line and
 * column of a syntax error.
 *
 * Two styles of number checks exist because the two formats word their
 * messages differently and their messages are kept: a range that the
 * message spells out ("expected a number in (0, 180), found 200"; scene
 * files), or a check function that says what is wrong with the value
 * ("-0.5 must be > 0"; profile files, whose text format shares the checks).
 *
 * Internal to sam_core: this header names cJSON types, and cJSON is a
 * private dependency of sam_core, so no code outside sam_core includes it.
 *
 * Every function is reentrant and keeps no state. Nothing here allocates:
 * a string returned is static or points into the caller's buffer or into
 * the cJSON tree, which the caller owns.
 */
#ifndef SAM_JSON_H
#define SAM_JSON_H

#include <cjson/cJSON.h>

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Where a file's messages go: every message starts with "name: ". */
typedef struct sam_json_ctx {
    const char *name; /* the file as messages name it; not NULL */
    sam_error *err;   /* receives the message; may be NULL */
} sam_json_ctx;

/* Records "name: key: <fmt...>" in ctx->err and returns `status`. `key`
 * is the value's path ("camera.fov_deg"); not NULL. The message is cut at
 * SAM_ERROR_MESSAGE_SIZE - 1 bytes like any sam_fail message. */
sam_status sam_json_fail(const sam_json_ctx *ctx, sam_status status, const char *key, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* The kind of a value for messages: "a number", "a string", "an array",
 * "an object", "a boolean", "null", or "an invalid value" (also for NULL).
 * Returns a static string. */
const char *sam_json_kind(const cJSON *item);

/* The value itself for messages: "200", "\"sun\"" (strings cut after 60
 * bytes with "..."), "true", "null", "an array of 3 elements", "an object",
 * "nothing" for NULL. Writes at most `size` bytes (size > 0) into `buf`
 * and returns it. */
const char *sam_json_describe(const cJSON *item, char *buf, size_t size);

/* sam_json_describe into a temporary that lives until the end of the
 * enclosing full expression: for a message's argument list. */
#define SAM_JSON_DESCRIBE_SIZE 96
#define SAM_JSON_DESCRIBE(item) \
    sam_json_describe((item), (char[SAM_JSON_DESCRIBE_SIZE]){0}, SAM_JSON_DESCRIBE_SIZE)

/* A child's key path: "parent.key", or "key" when `parent` is NULL or "".
 * `key` is not NULL. Writes at most `size` bytes (size > 0, cut short if
 * needed) into `buf` and returns it. */
const char *sam_json_key_path(char *buf, size_t size, const char *parent, const char *key);

/* An array element's path: "parent[index]". As sam_json_key_path. */
const char *sam_json_index_path(char *buf, size_t size, const char *parent, int index);

/* "a, b, c": the `count` names joined into `buf` (size > 0), cut short if
 * they do not fit. */
void sam_json_join_names(const char *const *names, size_t count, char *buf, size_t size);

/* The first member of `object` whose key is not one of the `count` names
 * in `allowed` or repeats an earlier member's key, or NULL when there is
 * none. `*duplicate` (not NULL) is set to 1 for a repeated key, 0 else.
 * For callers that word their own message; sam_json_check_keys words the
 * usual one. */
const cJSON *sam_json_bad_key(const cJSON *object, const char *const *allowed, size_t count, int *duplicate);

/* Refuses an unknown key ("path.key: unknown key (expected one of: a, b)")
 * and a repeated one ("path.key: duplicate key") in `object`. `path` is
 * the object's path ("" or NULL at the top level).
 * Errors: SAM_ERR_FORMAT. */
sam_status sam_json_check_keys(const sam_json_ctx *ctx, const cJSON *object, const char *path,
                               const char *const *allowed, size_t count);

/* Typed values. Each reads `item` (NULL is refused like a wrong type)
 * found at `path` into `*out` (not NULL; on failure a vector may be partly
 * written). Errors: SAM_ERR_FORMAT, naming the path and the value found.
 *
 * A number in [lo, hi], or the open side where lo_open / hi_open, finite
 * and within float range. `range` is the expectation as the message writes
 * it ("in (0, 180)"). */
sam_status sam_json_float(const sam_json_ctx *ctx, const cJSON *item, const char *path, double lo, int lo_open,
                          double hi, int hi_open, const char *range, float *out);
/* sam_json_float for any finite number, >= 0, and > 0. */
sam_status sam_json_any_float(const sam_json_ctx *ctx, const cJSON *item, const char *path, float *out);
sam_status sam_json_non_negative(const sam_json_ctx *ctx, const cJSON *item, const char *path, float *out);
sam_status sam_json_positive(const sam_json_ctx *ctx, const cJSON *item, const char *path, float *out);
/* An integer in [lo, hi]; with `odd` non-zero, an odd one. */
sam_status sam_json_uint(const sam_json_ctx *ctx, const cJSON *item, const char *path, uint32_t lo, uint32_t hi,
                         int odd, uint32_t *out);
/* true or false, as 1 or 0. */
sam_status sam_json_bool(const sam_json_ctx *ctx, const cJSON *item, const char *path, int *out);
/* A non-empty string; `*out` points into the cJSON tree. */
sam_status sam_json_string(const sam_json_ctx *ctx, const cJSON *item, const char *path, const char **out);
/* An array of exactly 3 finite numbers (each >= 0 with `non_negative`);
 * elements are named "path[i]" in messages. */
sam_status sam_json_vec3(const sam_json_ctx *ctx, const cJSON *item, const char *path, int non_negative,
                         float out[3]);
/* One of the `count` strings in `names`, as its index; `what` names the
 * kind in the message ("unknown technique \"x\" (expected sam, none)"). */
sam_status sam_json_enum(const sam_json_ctx *ctx, const cJSON *item, const char *path, const char *what,
                         const char *const *names, size_t count, int *out);
/* An object whose "type" key is one of `names` (sam_json_enum), as its
 * index; a missing "type" is refused naming the choices. Other keys are
 * not checked here. */
sam_status sam_json_typed_object(const sam_json_ctx *ctx, const cJSON *item, const char *path, const char *what,
                                 const char *const *names, size_t count, int *out);

/* A number checked by `check` (may be NULL: any number), which returns
 * NULL for a good value or why it is wrong ("must be > 0"): refused as
 * "key: expected a number, found a string" or "key: -0.5 must be > 0". */
sam_status sam_json_checked_number(const sam_json_ctx *ctx, const cJSON *item, const char *key,
                                   const char *(*check)(double), float *out);
/* An array of 3 numbers (r, g, b), each as sam_json_checked_number. */
sam_status sam_json_checked_rgb(const sam_json_ctx *ctx, const cJSON *item, const char *key,
                                const char *(*check)(double), float out[3]);

/* Line and column (1-based, counted in bytes) of byte `offset` of `text`
 * (at least `offset` bytes long), for syntax errors. */
void sam_json_line_column(const char *text, size_t offset, size_t *line, size_t *column);

/* 1 when the `size` bytes of `text` stop inside a string or with an object
 * or array still open, else 0. cJSON then points at the start of the
 * unfinished token, while the useful message is that the text ends early. */
int sam_json_ends_early(const char *text, size_t size);

/* 1 when objects and arrays in `text` nest deeper than cJSON parses
 * (CJSON_NESTING_LIMIT, 1000 levels), which cJSON reports as a syntax
 * error at the bracket where it stopped. */
int sam_json_too_deep(const char *text, size_t size);

#ifdef __cplusplus
}
#endif

#endif
