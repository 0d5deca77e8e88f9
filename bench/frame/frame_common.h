/* What bench_frame's studies share: the run's sizes, the passes they time,
 * side-by-side medians, and the knot every study measures (its mesh, map,
 * light and bending). bench_frame.c has the pass and technique tables,
 * frame_cut.c the cut map against the flat one. */
#ifndef BENCH_FRAME_COMMON_H
#define BENCH_FRAME_COMMON_H

#include <stdio.h>

#include "sam/sam_build.h"
#include "sam/sam_deform.h"
#include "sam/sam_runtime.h"
#include "bench_util.h"

/* How much a run measures: the full benchmark, or --quick's check that
 * every measurement runs. */
typedef struct frame_config {
    uint32_t width, height;                  /* the shaded frame */
    uint32_t atlas_size;                     /* texture space; 0: the runtime's 1024 */
    int pass_runs, render_runs, matrix_runs; /* calls per median: passes, renders, technique matrix */
    int mesh_count;
    int resolutions[4]; /* knot resolutions */
    int head, buddha;   /* which of them stand for a head and the Happy Buddha */
} frame_config;

extern const frame_config frame_full_config, frame_quick_config;

/* Default limits on a cut build (--cut-limit): on 2 cores it took 90 s on
 * the 18k-vertex knot and grows faster than the vertex count, so the larger
 * knots' cut maps would take hours (docs/performance.md). */
#define CUT_LIMIT_S 300.0
#define CUT_LIMIT_QUICK_S 30.0

/* "bench_frame: <what>: <message>", exit status 1. err may be NULL. */
_Noreturn void frame_die(const char *what, const sam_error *err);

/* A timed call: one pass or frame on `rt`; user is the call's own. */
typedef sam_status (*frame_pass_fn)(sam_runtime *rt, void *user, sam_error *err);

sam_status frame_run_irradiance(sam_runtime *rt, void *user, sam_error *err);   /* user unused */
sam_status frame_run_translucency(sam_runtime *rt, void *user, sam_error *err); /* user unused; a cut map's node
                                                                                  * pass included */
/* One animated frame's update: the pose at the next frame time, then the
 * sample walk (user: an int frame counter, advanced). */
sam_status frame_run_update(sam_runtime *rt, void *user, sam_error *err);

/* Median wall time (ms) of `runs` calls (at most 32), each closed by
 * glFinish, and in gpu_ms[k] the median GL timer-query time of passes[k]
 * (pass_count at most SAM_PASS_COUNT; <= 0 where the driver reports none;
 * passes and gpu_ms may be NULL when pass_count is 0). The caller names
 * only passes the call runs. */
double frame_median_ms_gpu(sam_runtime *rt, frame_pass_fn fn, void *user, int runs, const sam_pass *passes,
                           int pass_count, double *gpu_ms);
double frame_median_ms(sam_runtime *rt, frame_pass_fn fn, void *user, int runs);

/* frame_median_ms_gpu on `count` runtimes (at most FRAME_SIDE_MAX) side
 * by side: after an untimed call of each, their calls run in rounds, each
 * round starting one runtime later (A B C, B C A, C A B, ...), so a change
 * in the machine's load falls on all alike and none always runs first.
 * ms[r] and gpu_ms[r][k] are runtime r's medians. */
#define FRAME_SIDE_MAX 4
void frame_median_ms_side_by_side(sam_runtime *const *rt, int count, frame_pass_fn fn, void *const *user, int runs,
                                  const sam_pass *passes, int pass_count, double *ms,
                                  double (*gpu_ms)[SAM_PASS_COUNT]);

/* `"key": value`, or `"key": null` where value <= 0 (a timer query the
 * driver did not answer, a ratio of such times, an estimate not made). */
void frame_json_positive(FILE *json, const char *key, double value);

/* The bending of the knot benchmarks' animated frames. */
extern const sam_deformer frame_knot_bend;

/* The knot with `resolution` segments along it (with its UVs, for texture
 * space), welded, into `mesh` (caller destroys). */
void frame_knot_mesh(int resolution, sam_mesh *mesh);

/* The mesh's map of kind `map` (its default N) in skin at `mm_per_unit`
 * (the knots: 40), into `d` (caller frees), and its build seconds in
 * `*seconds` (may be NULL). Returns 0, with `d` empty, when `deadline` (may
 * be NULL) cancelled the build; dies on any other failure. */
int frame_knot_map(const sam_mesh *mesh, const sam_profile *skin, float mm_per_unit, sam_build_map map,
                   bench_deadline *deadline, samfile_data *d, double *seconds);

/* The scan at `path` moved and scaled onto the knots' box (centre and
 * diagonal), so that their light and bend fit it, into `mesh` (caller
 * destroys), and the scale that keeps its diagonal `size_mm` into
 * *mm_per_unit. Returns 0 when the file does not load (a scan not fetched:
 * meshes/fetch_scans.sh); dies on any other failure. */
int frame_scan_mesh(const char *path, float size_mm, sam_mesh *mesh, float *mm_per_unit);

/* One shadowed point light behind the knot (translucency shows) and a
 * white environment, on `rt`. */
void frame_light_knot(sam_runtime *rt);

/* A runtime on `d` (caller destroys), lit by frame_light_knot. */
sam_runtime *frame_knot_runtime(const samfile_data *d, const sam_profile *skin);

/* The default cut map against the flat N = 3 map on every knot of `cfg`
 * and, but with `quick`, on the skin scans (dragon, head) in the folder
 * `scans` where they are: a table on stdout with PASS or MISS against the
 * cost targets, the knots' and the scans' apart, and the
 * "cut_against_flat" member of the JSON object being written to `json`.
 * A cut build stops after limit_s seconds (0: none); timers says whether
 * the GL's timer queries mean something. */
void frame_cut_section(const frame_config *cfg, const sam_profile *skin, const char *scans, double limit_s,
                       int timers, int quick, FILE *json);

#endif
