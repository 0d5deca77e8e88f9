/* The shared map cache (sam_app_cache.h). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sam/sam_app.h"
#include "sam/sam_app_cache.h"
#include "sam/sam_app_scene.h"
#include "sam/sam_sha256.h"

/* Set by SIGINT/SIGTERM during a build: the progress callback cancels it.
 * The one global a signal handler needs. */
static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

void sam_app_cache_dir(const char *given, char *out, size_t n)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    if (given)
        snprintf(out, n, "%s", given);
    else if (xdg && xdg[0])
        snprintf(out, n, "%s/sam", xdg);
    else
        snprintf(out, n, "%s/.cache/sam", home && home[0] ? home : "/tmp");
}

/* mkdir -p */
static sam_status make_dirs(const char *path, sam_error *err)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "cache: path %s is too long", path);
    for (char *p = buf + 1;; ++p) {
        if (*p == '/' || !*p) {
            char c = *p;
            *p = 0;
            if (mkdir(buf, 0755) != 0 && errno != EEXIST)
                return sam_fail(err, SAM_ERR_IO, "cache: cannot create %s: %s", buf, strerror(errno));
            *p = c;
            if (!c)
                break;
        }
    }
    return SAM_OK;
}

/* Where the map of the scene's mesh built with `set` is cached (see the
 * header). */
static sam_status cache_path(const char *dir, const sam_scene *scene, const sam_build_settings *set, char *out,
                             size_t n, sam_error *err)
{
    char mesh_hash[65];
    sam_status st = sam_sha256_file(scene->mesh_path, mesh_hash, err);
    if (st != SAM_OK)
        return st;
    char key[512];
    snprintf(key, sizeof key, "%s\n%s\n%s\n%d %.9g\n%u %u %llu %d %.9g %u %.9g", SAM_BUILD_VERSION, mesh_hash,
             scene->material ? scene->material : "", (int)scene->scale_kind, scene->scale_value,
             sam_build_samples(set), set->mc_samples, (unsigned long long)set->seed, (int)set->map,
             set->cut_tolerance, set->candidates, set->radius_tolerance);
    /* A size in mm measures the mesh without its loose specks
     * (sam_mesh_diagonal) since these maps were first cached, which gives a
     * mesh with specks another scale: every size-in-mm key changed once so
     * that no such map is served at the old one. */
    if (scene->scale_kind == SAM_SCALE_SIZE_MM) {
        const size_t used = strlen(key);
        snprintf(key + used, sizeof key - used, " body");
    }
    /* A cut's budget beyond N makes another map; the keys of maps without one stay as they were. */
    if (set->map == SAM_BUILD_MAP_CUT && sam_build_cut_budget(set) > sam_build_samples(set)) {
        const size_t used = strlen(key);
        snprintf(key + used, sizeof key - used, " budget %u", sam_build_cut_budget(set));
    }
    sam_sha256 h;
    uint8_t digest[32];
    sam_sha256_init(&h);
    sam_sha256_update(&h, key, strlen(key));
    sam_sha256_final(&h, digest);
    const char *base = strrchr(scene->mesh_path, '/');
    base = base ? base + 1 : scene->mesh_path;
    int len = snprintf(out, n, "%s/%.*s-", dir, (int)strcspn(base, "."), base);
    for (int i = 0; i < 8 && len > 0 && (size_t)len + 2 < n; ++i)
        len += snprintf(out + len, n - (size_t)len, "%02x", digest[i]);
    if (len < 0 || (size_t)len + 5 > n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "cache: path in %s is too long", dir);
    strcat(out, ".sam");
    return SAM_OK;
}

/* The cached map at `cached`, if it is there and sound: 1 read, 0 to build
 * (the scene then names no .sam again). */
static int read_cached(sam_scene *s, const char *cached, const char *tool, samfile_data *sam,
                       sam_profile *profile, float *mm_per_unit, double *built_seconds, sam_error *err)
{
    struct stat info;
    if (stat(cached, &info) != 0)
        return 0;
    s->sam_path = sam_strdup(cached);
    if (!s->sam_path) {
        sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
        return -1;
    }
    sam_error cache_err;
    if (sam_app_scene_object(s, tool, NULL, NULL, NULL, sam, profile, mm_per_unit, NULL, &cache_err) == SAM_OK) {
        fprintf(stderr, "%s: using the cached map %s\n", tool, cached);
        samfile_info info;
        if (built_seconds && samfile_info_read(sam, cached, &info, &cache_err) == SAM_OK)
            *built_seconds = info.build_seconds;
        return 1;
    }
    /* A damaged or mismatched cache entry is rebuilt, not fatal. */
    fprintf(stderr, "%s: rebuilding the cached map: %s\n", tool, cache_err.message);
    free(s->sam_path);
    s->sam_path = NULL;
    return 0;
}

/* A warning where most of the map's vertices get no light, saying why. */
static void warn_if_dark(const char *tool, const sam_scene *s, const samfile_data *sam, const sam_profile *profile,
                         float mm_per_unit, const sam_build_settings *set)
{
    char why[1024];
    const char *name = s->mesh_path ? s->mesh_path : s->sam_path;
    if (sam_build_explain_empty(sam, mm_per_unit, sam_profile_radius(profile, set->radius_tolerance), name, why,
                                sizeof why) ||
        sam_build_explain_small(sam, mm_per_unit, sam_profile_radius(profile, 0.99f), name, why, sizeof why))
        fprintf(stderr, "%s: warning: %s\n", tool, why);
}

sam_status sam_app_cache_object(sam_scene *s, const sam_build_settings *settings, const char *cache_dir,
                                int use_cache, const char *tool, samfile_data *sam, sam_profile *profile,
                                float *mm_per_unit, double *built_seconds, sam_error *err)
{
    sam_build_settings defaults;
    sam_build_default_settings(&defaults);
    const sam_build_settings *set = settings ? settings : &defaults;
    char cached[4096] = "";
    if (built_seconds)
        *built_seconds = 0;
    if (s->mesh_path && !s->sam_path && use_cache) {
        sam_status st = cache_path(cache_dir, s, set, cached, sizeof cached, err);
        if (st != SAM_OK)
            return st;
        int found = read_cached(s, cached, tool, sam, profile, mm_per_unit, built_seconds, err);
        if (found > 0)
            warn_if_dark(tool, s, sam, profile, *mm_per_unit, set);
        if (found)
            return found > 0 ? SAM_OK : err->status;
    }
    sam_app_progress bar;
    sam_app_progress_init(&bar, tool, 0, &interrupted);
    double seconds;
    if (s->mesh_path && !s->sam_path)
        fprintf(stderr, "%s: building the map of %s\n", tool, s->mesh_path);
    sam_app_catch_interrupts(on_signal);
    sam_status st =
        sam_app_scene_object(s, tool, set, sam_app_progress_update, &bar, sam, profile, mm_per_unit, &seconds, err);
    sam_app_catch_interrupts(NULL);
    if (bar.open_line)
        fputc('\n', stderr);
    if (st != SAM_OK)
        return st;
    if (built_seconds)
        *built_seconds = seconds;
    warn_if_dark(tool, s, sam, profile, *mm_per_unit, set);
    if (!cached[0])
        return st;
    fprintf(stderr, "%s: built in %.1f s (%u vertices)\n", tool, seconds, sam->vertex_count);
    sam_error cache_err;
    if (make_dirs(cache_dir, &cache_err) != SAM_OK || samfile_write(cached, sam, &cache_err) != SAM_OK) {
        fprintf(stderr, "%s: warning: the map is not cached: %s\n", tool, cache_err.message);
        return SAM_OK;
    }
    /* A scene saved from this one names the cached map: no build. */
    s->sam_path = sam_strdup(cached);
    return s->sam_path ? SAM_OK : sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory");
}
