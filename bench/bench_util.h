/* Helpers shared by the benchmark programs. */
#ifndef BENCH_UTIL_H
#define BENCH_UTIL_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "sam/sam_app.h"
#include "sam/sam_app_scene.h"
#include "sam/sam_common.h"
#include "sam/sam_runtime_scene.h"

/* Prints "<program>: <what>: <message>" and exits with status 1. */
_Noreturn static inline void bench_die(const char *program, const char *what, const sam_error *err)
{
    fprintf(stderr, "%s: %s: %s\n", program, what, err ? err->message : "failed");
    exit(1);
}

/* qsort comparator for doubles, ascending. */
static inline int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of `n` values (sorts them; the mean of the middle two for an
 * even n, so two runs taken in A B B A order cancel a linear drift). */
static inline double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, bench_cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* A wall-time limit on a build, as sam_build_run's progress callback
 * (bench_deadline_progress, `user` the deadline): the cut map's build time
 * grows faster than the vertex count, so a benchmark that must end stops a
 * build that would not, and keeps the whole build's estimate. */
typedef struct bench_deadline {
    double limit_s;  /* <= 0: none */
    double start;    /* sam_seconds() when the build began */
    double setup_s;  /* seconds to the first vertex (context, tree) */
    double fraction; /* vertices started / all at the last report */
    double elapsed_s;
    int cancelled;
} bench_deadline;

static inline void bench_deadline_start(bench_deadline *d, double limit_s)
{
    *d = (bench_deadline){.limit_s = limit_s, .start = sam_seconds(), .setup_s = -1};
}

/* The whole build's seconds, extrapolated from the last report at the rate
 * of the vertices done after setup; negative before a report at 0.5% (the
 * builder reports every 0.5%: an earlier estimate is noise). */
static inline double bench_deadline_estimate(const bench_deadline *d)
{
    if (d->fraction < 0.005 || d->setup_s < 0)
        return -1;
    return d->setup_s + (d->elapsed_s - d->setup_s) / d->fraction;
}

static inline int bench_deadline_progress(void *user, uint64_t done, uint64_t total)
{
    bench_deadline *d = user;
    d->elapsed_s = sam_seconds() - d->start;
    d->fraction = total ? (double)done / (double)total : 1;
    if (d->setup_s < 0)
        d->setup_s = d->elapsed_s;
    /* Past the limit, or bound to pass twice the limit once a quarter of
     * the limit has gone: the rate of the first few hundred vertices is
     * noise (at 0.5% of a 40k-vertex knot's cut build it read 1374 s), and
     * twice so a build whose estimate is a little high still gets its
     * measurement. */
    double estimate = bench_deadline_estimate(d);
    if (d->limit_s > 0 &&
        (d->elapsed_s > d->limit_s || (d->elapsed_s > 0.25 * d->limit_s && estimate > 2 * d->limit_s)))
        d->cancelled = 1;
    return d->cancelled;
}

/* "stopped after T s at F% of the vertices; estimated E s" (or "no estimate
 * yet") for a cancelled build, into buf. */
static inline void bench_deadline_describe(const bench_deadline *d, char *buf, size_t n)
{
    double estimate = bench_deadline_estimate(d);
    int used = snprintf(buf, n, "stopped after %.1f s at %.1f%% of the vertices; ", d->elapsed_s, 100 * d->fraction);
    if (used >= 0 && (size_t)used < n)
        snprintf(buf + used, n - (size_t)used, estimate > 0 ? "estimated %.1f s" : "no estimate yet", estimate);
}

/* A cancelled build's JSON fields: `"PREFIX_stopped_s": T,
 * "PREFIX_fraction": F, "PREFIX_estimate_s": E` (null before an estimate). */
static inline void bench_deadline_json(FILE *json, const char *prefix, const bench_deadline *d)
{
    double estimate = bench_deadline_estimate(d);
    fprintf(json, "\"%s_stopped_s\": %.1f, \"%s_fraction\": %.4f, \"%s_estimate_s\": ", prefix, d->elapsed_s, prefix,
            d->fraction, prefix);
    if (estimate > 0)
        fprintf(json, "%.1f", estimate);
    else
        fprintf(json, "null");
}

/* Opens the JSON result `path` for writing beside a temporary name, so an
 * interrupted or failed benchmark leaves the last complete results alone;
 * bench_json_commit puts it in place. Exits on failure. */
static inline void bench_json_open(const char *program, const char *path, sam_atomic_file *file)
{
    sam_error err;
    if (sam_atomic_open(file, path, &err) != SAM_OK)
        bench_die(program, path, &err);
}

static inline void bench_json_commit(const char *program, sam_atomic_file *file)
{
    sam_error err;
    if (sam_atomic_commit(file, &err) != SAM_OK)
        bench_die(program, "results", &err);
}

/* `text` as a JSON string, quotes included: a path may hold quotes,
 * backslashes or control characters. */
static inline void bench_json_string(FILE *json, const char *text)
{
    fputc('"', json);
    for (const unsigned char *c = (const unsigned char *)text; *c; ++c) {
        if (*c == '"' || *c == '\\')
            fprintf(json, "\\%c", *c);
        else if (*c < 0x20)
            fprintf(json, "\\u%04x", *c);
        else
            fputc(*c, json);
    }
    fputc('"', json);
}

/* A scene file's object on a new runtime, lit as sam_render and sam_compare
 * light it: the scene in `scene`, its map in `sam` (built from the mesh),
 * its material and scale, and in `sh` and `*has_environment` (may be NULL)
 * the environment as sam_runtime_scene_setup gives it. The caller frees
 * them (sam_runtime_destroy, samfile_free, sam_scene_destroy). Needs a
 * current GL context; exits on failure, naming the file. */
static inline sam_runtime *bench_scene_runtime(const char *program, const char *path, sam_scene *scene,
                                               samfile_data *sam, sam_profile *profile, float *mm_per_unit,
                                               float sh[9][3], int *has_environment)
{
    sam_error err;
    sam_runtime *rt;
    if (sam_scene_load(path, scene, &err) != SAM_OK ||
        sam_app_scene_object(scene, program, NULL, NULL, NULL, sam, profile, mm_per_unit, NULL, &err) != SAM_OK ||
        sam_runtime_create(sam, profile, *mm_per_unit, &rt, &err) != SAM_OK ||
        sam_runtime_scene_setup(rt, scene, sh, has_environment, NULL, 0, &err) != SAM_OK)
        bench_die(program, path, &err);
    return rt;
}

#endif
