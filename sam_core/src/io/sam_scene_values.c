/*
 * sam_scene_values: what every part of a scene file reads alike: names of
 * enum values, file references (resolved against the scene's directory)
 * and directions. Contracts in sam_scene_internal.h.
 */
#define _POSIX_C_SOURCE 200809L
#include "sam_scene_internal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *sam_scene_name_at(const char *const *names, size_t count, int value)
{
    return value >= 0 && (size_t)value < count ? names[value] : "unknown";
}

/* The current directory in a new malloc'd string, or NULL. */
static char *current_dir(void)
{
    for (size_t n = 256; n <= (1u << 20); n *= 2) {
        char *buf = malloc(n);
        if (!buf)
            return NULL;
        if (getcwd(buf, n))
            return buf;
        free(buf);
        if (errno != ERANGE)
            return NULL;
    }
    return NULL;
}

char *sam_scene_absolute_path(const char *base_dir, const char *path)
{
    char *cwd = NULL;
    const char *parts[3] = {NULL, NULL, path};
    if (path[0] != '/') {
        parts[1] = base_dir && base_dir[0] ? base_dir : NULL;
        if (!parts[1] || parts[1][0] != '/') {
            cwd = current_dir();
            if (!cwd)
                return NULL;
            parts[0] = cwd;
        }
    }
    size_t total = 2;
    for (int i = 0; i < 3; ++i)
        total += parts[i] ? strlen(parts[i]) + 1 : 0;
    char *out = malloc(total);
    if (!out) {
        free(cwd);
        return NULL;
    }
    size_t len = 0;
    for (int i = 0; i < 3; ++i) {
        const char *s = parts[i];
        while (s && *s) {
            while (*s == '/')
                ++s;
            const char *end = s;
            while (*end && *end != '/')
                ++end;
            size_t n = (size_t)(end - s);
            if (n > 0 && !(n == 1 && s[0] == '.')) {
                out[len++] = '/';
                memcpy(out + len, s, n);
                len += n;
            }
            s = end;
        }
    }
    if (len == 0)
        out[len++] = '/';
    out[len] = 0;
    free(cwd);
    return out;
}

sam_status sam_scene_out_of_memory(const sam_scene_parser *p)
{
    return sam_fail(p->json.err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory", p->json.name);
}

double sam_scene_length3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* Normalises in place, keeping a unit vector bit for bit. */
static void normalize3(float v[3])
{
    double d[3] = {v[0], v[1], v[2]};
    double len = sam_scene_length3(d);
    if (fabs(len - 1.0) <= 1e-6)
        return;
    for (int k = 0; k < 3; ++k)
        v[k] = (float)(d[k] / len);
}

sam_status sam_scene_get_direction(const sam_scene_parser *p, const cJSON *item, const char *path, float out[3])
{
    sam_status st = sam_json_vec3(&p->json, item, path, 0, out);
    if (st != SAM_OK)
        return st;
    double d[3] = {out[0], out[1], out[2]};
    if (!(sam_scene_length3(d) > 1e-12))
        return sam_json_fail(&p->json, SAM_ERR_FORMAT, path, "expected a non-zero direction, found [%g, %g, %g]",
                             out[0], out[1], out[2]);
    normalize3(out);
    return SAM_OK;
}

sam_status sam_scene_get_file(const sam_scene_parser *p, const cJSON *item, const char *path, char **out)
{
    const char *s;
    sam_status st = sam_json_string(&p->json, item, path, &s);
    if (st != SAM_OK)
        return st;
    char *abs = sam_scene_absolute_path(p->base_dir, s);
    if (!abs)
        return sam_json_fail(&p->json, SAM_ERR_IO, path, "cannot resolve \"%s\" (current directory unknown)",
                             s);
    struct stat sb;
    if (stat(abs, &sb) != 0) {
        int e = errno;
        st = sam_json_fail(&p->json, SAM_ERR_IO, path, "%s: %s", e == ENOENT ? "file not found" : strerror(e),
                           abs);
        free(abs);
        return st;
    }
    if (!S_ISREG(sb.st_mode)) {
        st = sam_json_fail(&p->json, SAM_ERR_IO, path, "not a regular file: %s", abs);
        free(abs);
        return st;
    }
    *out = abs;
    return SAM_OK;
}
