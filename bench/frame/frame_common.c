/* bench_frame's shared timing and knot helpers (frame_common.h). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "sam/sam_shape.h"
#include "frame_common.h"

const frame_config frame_full_config = {1920, 1080, 0, 9, 3, 3, 4, {120, 400, 900, 2250}, 1, 3};
const frame_config frame_quick_config = {320, 180, 256, 3, 1, 1, 2, {40, 80}, 0, 1};

void frame_die(const char *what, const sam_error *err)
{
    bench_die("bench_frame", what, err);
}

sam_status frame_run_irradiance(sam_runtime *rt, void *user, sam_error *err)
{
    (void)user;
    return sam_runtime_irradiance(rt, err);
}

sam_status frame_run_translucency(sam_runtime *rt, void *user, sam_error *err)
{
    (void)user;
    return sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 0, err);
}

sam_status frame_run_update(sam_runtime *rt, void *user, sam_error *err)
{
    int *frame = user;
    sam_status st = sam_runtime_deform(rt, (float)++*frame / 30.0f, err);
    return st == SAM_OK ? sam_runtime_walk(rt, err) : st;
}

/* One call of `fn`, closed by glFinish: its wall time in ms, and in
 * gpu_ms[k] the GL timer-query time of passes[k] (<= 0 where the driver
 * reports none; a pass that did not run reports its last run's time, or a
 * negative value if it never ran). */
static double time_call(sam_runtime *rt, frame_pass_fn fn, void *user, const sam_pass *passes, int pass_count,
                        double *gpu_ms)
{
    sam_error err;
    glFinish();
    double start = sam_seconds();
    if (fn(rt, user, &err) != SAM_OK)
        frame_die("pass", &err);
    glFinish();
    double ms = 1e3 * (sam_seconds() - start);
    for (int k = 0; k < pass_count; ++k)
        gpu_ms[k] = sam_runtime_pass_ms(rt, passes[k]);
    return ms;
}

double frame_median_ms_gpu(sam_runtime *rt, frame_pass_fn fn, void *user, int runs, const sam_pass *passes,
                            int pass_count, double *gpu_ms)
{
    double t[32], g[SAM_PASS_COUNT][32], call_gpu[SAM_PASS_COUNT];
    /* The first call of a pass or technique compiles its shaders and sizes
     * its targets: a median of three drops it, a shorter run must not time it. */
    if (runs < 3)
        time_call(rt, fn, user, NULL, 0, NULL);
    for (int i = 0; i < runs; ++i) {
        t[i] = time_call(rt, fn, user, passes, pass_count, call_gpu);
        for (int k = 0; k < pass_count; ++k)
            g[k][i] = call_gpu[k];
    }
    for (int k = 0; k < pass_count; ++k)
        gpu_ms[k] = bench_median(g[k], runs);
    return bench_median(t, runs);
}

void frame_median_ms_side_by_side(sam_runtime *const *rt, int count, frame_pass_fn fn, void *const *user, int runs,
                                  const sam_pass *passes, int pass_count, double *ms,
                                  double (*gpu_ms)[SAM_PASS_COUNT])
{
    double t[FRAME_SIDE_MAX][32], g[FRAME_SIDE_MAX][SAM_PASS_COUNT][32], call_gpu[SAM_PASS_COUNT];
    for (int i = -1; i < runs; ++i)
        for (int j = 0; j < count; ++j) {
            int r = (i + 1 + j) % count; /* each round starts one runtime later */
            double wall = time_call(rt[r], fn, user[r], passes, pass_count, call_gpu);
            if (i < 0)
                continue;
            t[r][i] = wall;
            for (int k = 0; k < pass_count; ++k)
                g[r][k][i] = call_gpu[k];
        }
    for (int r = 0; r < count; ++r) {
        ms[r] = bench_median(t[r], runs);
        for (int k = 0; k < pass_count; ++k)
            gpu_ms[r][k] = bench_median(g[r][k], runs);
    }
}

double frame_median_ms(sam_runtime *rt, frame_pass_fn fn, void *user, int runs)
{
    return frame_median_ms_gpu(rt, fn, user, runs, NULL, 0, NULL);
}

void frame_json_positive(FILE *json, const char *key, double value)
{
    if (value > 0)
        fprintf(json, "\"%s\": %.4f", key, value);
    else
        fprintf(json, "\"%s\": null", key);
}

/* The bending of the knot benchmarks' animated frames. */
const sam_deformer frame_knot_bend = {.type = SAM_DEFORM_BEND, .axis = {1, 0, 0}, .direction = {0, 1, 0},
                                       .length = 1.0f, .angle_deg = 60.0f, .period_s = 2.0f};

void frame_light_knot(sam_runtime *rt)
{
    sam_error err;
    sam_light light;
    memset(&light, 0, sizeof light);
    light.type = SAM_LIGHT_POINT;
    light.color[0] = light.color[1] = light.color[2] = 1.0f;
    light.intensity = 2.0f;
    light.shadow = 1;
    light.position[2] = -2.0f;
    float sh[9][3] = {{1.0f, 1.0f, 1.0f}};
    if (sam_runtime_set_lights(rt, &light, 1, &err) != SAM_OK)
        frame_die("lights", &err);
    sam_runtime_set_environment(rt, sh);
}

void frame_knot_mesh(int resolution, sam_mesh *mesh)
{
    sam_error err;
    sam_shape_params sp;
    sam_shape_default_params("knot", &sp, NULL);
    sp.resolution = resolution;
    sam_shape_mesh s;
    if (sam_shape_generate("knot", &sp, &s, &err) != SAM_OK)
        frame_die("knot", &err);
    sam_mesh_input in = {.name = "knot", .vertex_count = s.vertex_count, .positions = s.positions,
                         .uvs = s.uvs, .triangle_count = s.triangle_count, .triangles = s.triangles};
    if (sam_mesh_create(&in, mesh, NULL, &err) != SAM_OK)
        frame_die("mesh", &err);
    sam_shape_mesh_destroy(&s);
}

int frame_knot_map(const sam_mesh *mesh, const sam_profile *skin, float mm_per_unit, sam_build_map map,
                   bench_deadline *deadline, samfile_data *d, double *seconds)
{
    sam_build_settings settings;
    sam_build_default_settings(&settings);
    settings.map = map;
    sam_error err;
    sam_status st = sam_build_samfile(mesh, skin, mm_per_unit, &settings, NULL,
                                      deadline ? bench_deadline_progress : NULL, deadline, d, seconds, &err);
    if (st != SAM_OK && !(deadline && deadline->cancelled))
        frame_die("build", &err);
    return st == SAM_OK;
}

int frame_scan_mesh(const char *path, float size_mm, sam_mesh *mesh, float *mm_per_unit)
{
    sam_mesh scan, knot;
    sam_error err;
    if (sam_mesh_load(path, &scan, NULL, &err) != SAM_OK)
        return 0;
    frame_knot_mesh(64, &knot);
    float lo[3], hi[3], knot_lo[3], knot_hi[3];
    sam_mesh_bounds(&scan, lo, hi);
    sam_mesh_bounds(&knot, knot_lo, knot_hi);
    const double scale = sam_mesh_diagonal(&knot) / sam_mesh_diagonal(&scan);
    float *pos = malloc(3 * (size_t)scan.vertex_count * sizeof *pos);
    if (!pos)
        frame_die("scan positions", NULL);
    for (size_t i = 0; i < 3 * (size_t)scan.vertex_count; ++i) {
        const int c = (int)(i % 3);
        pos[i] = (float)((scan.positions[i] - 0.5 * (lo[c] + hi[c])) * scale + 0.5 * (knot_lo[c] + knot_hi[c]));
    }
    sam_mesh_input in = {.name = path, .vertex_count = scan.vertex_count, .positions = pos,
                         .triangle_count = scan.triangle_count, .triangles = scan.triangles};
    if (sam_mesh_create(&in, mesh, NULL, &err) != SAM_OK)
        frame_die("scan", &err);
    *mm_per_unit = (float)(size_mm / sam_mesh_diagonal(mesh));
    free(pos);
    sam_mesh_destroy(&knot);
    sam_mesh_destroy(&scan);
    return 1;
}

sam_runtime *frame_knot_runtime(const samfile_data *d, const sam_profile *skin)
{
    sam_runtime *rt;
    sam_error err;
    if (sam_runtime_create(d, skin, 40.0f, &rt, &err) != SAM_OK)
        frame_die("runtime", &err);
    frame_light_knot(rt);
    return rt;
}
