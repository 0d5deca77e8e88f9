/* Reading and checking JSON files with messages (sam_json.h). */
#include "sam/sam_json.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

sam_status sam_json_fail(const sam_json_ctx *ctx, sam_status status, const char *key, const char *fmt, ...)
{
    char what[SAM_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    return sam_fail(ctx->err, status, "%s: %s: %s", ctx->name, key, what);
}

const char *sam_json_kind(const cJSON *item)
{
    if (cJSON_IsNumber(item))
        return "a number";
    if (cJSON_IsString(item))
        return "a string";
    if (cJSON_IsArray(item))
        return "an array";
    if (cJSON_IsObject(item))
        return "an object";
    if (cJSON_IsBool(item))
        return "a boolean";
    if (cJSON_IsNull(item))
        return "null";
    return "an invalid value";
}

const char *sam_json_describe(const cJSON *item, char *buf, size_t size)
{
    if (!item)
        snprintf(buf, size, "nothing");
    else if (cJSON_IsNumber(item))
        snprintf(buf, size, "%.9g", item->valuedouble);
    else if (cJSON_IsString(item))
        snprintf(buf, size, "\"%.60s%s\"", item->valuestring, strlen(item->valuestring) > 60 ? "..." : "");
    else if (cJSON_IsBool(item))
        snprintf(buf, size, "%s", cJSON_IsTrue(item) ? "true" : "false");
    else if (cJSON_IsArray(item))
        snprintf(buf, size, "an array of %d elements", cJSON_GetArraySize(item));
    else /* an object, null or invalid: its kind says it all */
        snprintf(buf, size, "%s", sam_json_kind(item));
    return buf;
}

const char *sam_json_key_path(char *buf, size_t size, const char *parent, const char *key)
{
    if (parent && parent[0])
        snprintf(buf, size, "%s.%s", parent, key);
    else
        snprintf(buf, size, "%s", key);
    return buf;
}

const char *sam_json_index_path(char *buf, size_t size, const char *parent, int index)
{
    snprintf(buf, size, "%s[%d]", parent, index);
    return buf;
}

void sam_json_join_names(const char *const *names, size_t count, char *buf, size_t size)
{
    size_t len = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < count && len < size; ++i)
        len += (size_t)snprintf(buf + len, size - len, "%s%s", i ? ", " : "", names[i]);
}

/* A member's key; cJSON leaves it NULL only outside objects. */
static const char *member_key(const cJSON *member)
{
    return member->string ? member->string : "";
}

const cJSON *sam_json_bad_key(const cJSON *object, const char *const *allowed, size_t count, int *duplicate)
{
    for (const cJSON *child = object->child; child; child = child->next) {
        const char *key = member_key(child);
        size_t k = 0;
        while (k < count && strcmp(key, allowed[k]) != 0)
            ++k;
        if (k == count) {
            *duplicate = 0;
            return child;
        }
        for (const cJSON *prev = object->child; prev != child; prev = prev->next) {
            if (strcmp(member_key(prev), key) == 0) {
                *duplicate = 1;
                return child;
            }
        }
    }
    *duplicate = 0;
    return NULL;
}

sam_status sam_json_check_keys(const sam_json_ctx *ctx, const cJSON *object, const char *path,
                               const char *const *allowed, size_t count)
{
    int duplicate;
    const cJSON *bad = sam_json_bad_key(object, allowed, count, &duplicate);
    if (!bad)
        return SAM_OK;
    char at[256];
    sam_json_key_path(at, sizeof at, path, member_key(bad));
    if (duplicate)
        return sam_json_fail(ctx, SAM_ERR_FORMAT, at, "duplicate key");
    char list[256];
    sam_json_join_names(allowed, count, list, sizeof list);
    return sam_json_fail(ctx, SAM_ERR_FORMAT, at, "unknown key (expected one of: %s)", list);
}

sam_status sam_json_float(const sam_json_ctx *ctx, const cJSON *item, const char *path, double lo, int lo_open,
                          double hi, int hi_open, const char *range, float *out)
{
    if (cJSON_IsNumber(item)) {
        double v = item->valuedouble;
        int ok = isfinite(v) && fabs(v) <= FLT_MAX && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
        /* 1e-300 passes "> 0" as a double and is 0 as the float it is kept in. */
        const float f = ok ? (float)v : 0.0f;
        if (ok && !((lo_open ? f > lo : f >= lo) && (hi_open ? f < hi : f <= hi)))
            return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "expected a number %s, found %g, which a 32-bit float "
                                 "holds as %g", range, v, (double)f);
        if (ok) {
            *out = f;
            return SAM_OK;
        }
    }
    return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "expected a number %s, found %s", range,
                         SAM_JSON_DESCRIBE(item));
}

sam_status sam_json_any_float(const sam_json_ctx *ctx, const cJSON *item, const char *path, float *out)
{
    return sam_json_float(ctx, item, path, -INFINITY, 0, INFINITY, 0, "(finite)", out);
}

sam_status sam_json_non_negative(const sam_json_ctx *ctx, const cJSON *item, const char *path, float *out)
{
    return sam_json_float(ctx, item, path, 0.0, 0, INFINITY, 0, ">= 0 (finite)", out);
}

sam_status sam_json_positive(const sam_json_ctx *ctx, const cJSON *item, const char *path, float *out)
{
    return sam_json_float(ctx, item, path, 0.0, 1, INFINITY, 0, "> 0 (finite)", out);
}

sam_status sam_json_uint(const sam_json_ctx *ctx, const cJSON *item, const char *path, uint32_t lo, uint32_t hi,
                         int odd, uint32_t *out)
{
    double v = cJSON_IsNumber(item) ? item->valuedouble : NAN;
    if (v >= lo && v <= hi && v == floor(v) && (!odd || fmod(v, 2.0) == 1.0)) {
        *out = (uint32_t)v;
        return SAM_OK;
    }
    return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "expected %s integer in [%u, %u], found %s", odd ? "an odd" : "an",
                         lo, hi, SAM_JSON_DESCRIBE(item));
}

sam_status sam_json_bool(const sam_json_ctx *ctx, const cJSON *item, const char *path, int *out)
{
    if (!cJSON_IsBool(item))
        return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "expected true or false, found %s", SAM_JSON_DESCRIBE(item));
    *out = cJSON_IsTrue(item) ? 1 : 0;
    return SAM_OK;
}

sam_status sam_json_string(const sam_json_ctx *ctx, const cJSON *item, const char *path, const char **out)
{
    if (!cJSON_IsString(item) || !item->valuestring[0])
        return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "expected a non-empty string, found %s",
                             SAM_JSON_DESCRIBE(item));
    *out = item->valuestring;
    return SAM_OK;
}

sam_status sam_json_vec3(const sam_json_ctx *ctx, const cJSON *item, const char *path, int non_negative,
                         float out[3])
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "expected an array of 3 numbers, found %s",
                             SAM_JSON_DESCRIBE(item));
    int i = 0;
    for (const cJSON *e = item->child; e; e = e->next, ++i) {
        char at[280];
        sam_json_index_path(at, sizeof at, path, i);
        sam_status st =
            non_negative ? sam_json_non_negative(ctx, e, at, &out[i]) : sam_json_any_float(ctx, e, at, &out[i]);
        if (st != SAM_OK)
            return st;
    }
    return SAM_OK;
}

sam_status sam_json_enum(const sam_json_ctx *ctx, const cJSON *item, const char *path, const char *what,
                         const char *const *names, size_t count, int *out)
{
    const char *s = NULL; /* set when it succeeds; GCC's -O3 cannot tell */
    sam_status st = sam_json_string(ctx, item, path, &s);
    if (st != SAM_OK)
        return st;
    for (size_t i = 0; i < count; ++i) {
        if (strcmp(s, names[i]) == 0) {
            *out = (int)i;
            return SAM_OK;
        }
    }
    char list[256];
    sam_json_join_names(names, count, list, sizeof list);
    return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "unknown %s \"%.60s\" (expected %s)", what, s, list);
}

sam_status sam_json_typed_object(const sam_json_ctx *ctx, const cJSON *item, const char *path, const char *what,
                                 const char *const *names, size_t count, int *out)
{
    if (!cJSON_IsObject(item))
        return sam_json_fail(ctx, SAM_ERR_FORMAT, path, "expected an object, found %s", SAM_JSON_DESCRIBE(item));
    char at[128];
    sam_json_key_path(at, sizeof at, path, "type");
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(item, "type");
    if (type)
        return sam_json_enum(ctx, type, at, what, names, count, out);
    char list[256];
    sam_json_join_names(names, count, list, sizeof list);
    return sam_json_fail(ctx, SAM_ERR_FORMAT, at, "missing (expected %s)", list);
}

sam_status sam_json_checked_number(const sam_json_ctx *ctx, const cJSON *item, const char *key,
                                   const char *(*check)(double), float *out)
{
    if (!cJSON_IsNumber(item))
        return sam_json_fail(ctx, SAM_ERR_FORMAT, key, "expected a number, found %s", sam_json_kind(item));
    double v = item->valuedouble;
    const char *why = check ? check(v) : NULL;
    if (why)
        return sam_json_fail(ctx, SAM_ERR_FORMAT, key, "%g %s", v, why);
    *out = (float)v;
    return SAM_OK;
}

sam_status sam_json_checked_rgb(const sam_json_ctx *ctx, const cJSON *item, const char *key,
                                const char *(*check)(double), float out[3])
{
    if (!cJSON_IsArray(item))
        return sam_json_fail(ctx, SAM_ERR_FORMAT, key, "expected an array of 3 numbers, found %s",
                             sam_json_kind(item));
    int n = cJSON_GetArraySize(item);
    if (n != 3)
        return sam_json_fail(ctx, SAM_ERR_FORMAT, key, "expected 3 numbers (r, g, b), found %d", n);
    int c = 0;
    for (const cJSON *e = item->child; e; e = e->next, c++) {
        char sub[160];
        sam_status s = sam_json_checked_number(ctx, e, sam_json_index_path(sub, sizeof sub, key, c), check, &out[c]);
        if (s != SAM_OK)
            return s;
    }
    return SAM_OK;
}

void sam_json_line_column(const char *text, size_t offset, size_t *line, size_t *column)
{
    *line = 1;
    *column = 1;
    for (size_t i = 0; i < offset; ++i) {
        if (text[i] == '\n') {
            ++*line;
            *column = 1;
        } else {
            ++*column;
        }
    }
}

/* Walks the brackets outside strings: returns 1 when the text stops inside
 * a string or with a bracket open; *deepest gets the deepest nesting. */
static int scan_brackets(const char *text, size_t size, long *deepest)
{
    long depth = 0;
    int in_string = 0, escaped = 0;
    *deepest = 0;
    for (size_t i = 0; i < size; ++i) {
        char ch = text[i];
        if (in_string) {
            if (escaped)
                escaped = 0;
            else if (ch == '\\')
                escaped = 1;
            else if (ch == '"')
                in_string = 0;
        } else if (ch == '"') {
            in_string = 1;
        } else if (ch == '{' || ch == '[') {
            if (++depth > *deepest)
                *deepest = depth;
        } else if (ch == '}' || ch == ']') {
            --depth;
        }
    }
    return in_string || depth > 0;
}

int sam_json_ends_early(const char *text, size_t size)
{
    long deepest;
    return scan_brackets(text, size, &deepest);
}

int sam_json_too_deep(const char *text, size_t size)
{
    long deepest;
    scan_brackets(text, size, &deepest);
    return deepest > CJSON_NESTING_LIMIT;
}
