/* Helpers shared by the benchmark programs. */
#ifndef BENCH_UTIL_H
#define BENCH_UTIL_H

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
        sam_app_scene_object(scene, NULL, NULL, NULL, sam, profile, mm_per_unit, NULL, &err) != SAM_OK ||
        sam_runtime_create(sam, profile, *mm_per_unit, &rt, &err) != SAM_OK ||
        sam_runtime_scene_setup(rt, scene, sh, has_environment, NULL, 0, &err) != SAM_OK)
        bench_die(program, path, &err);
    return rt;
}

#endif
