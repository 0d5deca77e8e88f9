/*
 * bench_frame: the runtime's per-pass costs on the current GL device
 * (llvmpipe without a GPU), measured side by side in one run.
 *
 * For knots at four resolutions (about 2k, 18k "head-sized", 88k and 550k
 * "buddha-sized" vertices; skin, N = 3): the irradiance pass (one shadowed
 * point light + environment), the translucency pass and the shading pass at
 * 1920x1080, the latter with each surface-diffusion technique. For the
 * head- and buddha-sized knots, with --optimizations (minutes of close-up
 * renders), texture-space diffusion with each of Jimenez and Gutierrez's
 * optimisations (culled, clipped, depth-sized, all) against none, in a
 * close-up, a whole-object and a far view: the cost of
 * the diffusion as the render's time less the same render's without
 * diffusion, and its speed-up. Times are wall-clock medians around
 * glFinish (llvmpipe reports no timer-query time for compute); the
 * diffusion pass's GL timer query is printed too where the driver gives
 * one. The translucency pass is set against its bandwidth lower bound: the
 * bytes it must move per vertex (its own position and T, and per sample the
 * sample record, the back vertex's position, fan area and L_d) over the
 * memory bandwidth measured here with memcpy. Last, the per-frame update of
 * a bending mesh (deform pass + sample walk) per vertex, next to the
 * translucency pass.
 *
 * The whole frame of every translucency technique (sam, tsm, transmittance,
 * none) with every surface diffusion (none, screen, pre-integrated,
 * texture) at 1920x1080 on the head- and buddha-sized knots and the knot
 * scene (scenes/compare_knot.json): each pass's wall time and GL
 * timer-query time, the frame's total, SAM's share of its frame and SAM's
 * frame against tsm's, transmittance's and none's in the same run (the SAM
 * paper claims speed comparable to the shadow-map techniques).
 * Combinations the runtime cannot render (tsm without texture space, texture
 * space without usable UVs) are listed with the reason.
 *
 * Last, the builder's default cut map (its default N) against the flat map
 * (N = 3) on the same knots, the two runtimes' calls interleaved: the node and
 * translucency passes (sam_runtime_translucency) against the flat map's
 * translucency pass, target <= 2.0, and an animated frame's whole SAM work
 * (deform, walk, irradiance, node, translucency), target <= 1.5; wall-clock
 * medians, and GL timer queries where the driver's mean something. A summary
 * line per ratio says PASS or MISS. A cut build that passes --cut-limit is
 * stopped, and larger knots are not measured.
 *
 * Usage: bench_frame [--quick] [--optimizations] [--cut-only] [--cut-limit S] [--json FILE] [--scenes DIR]
 *   --cut-only   the cut study alone
 *   --cut-limit  seconds a cut build may take, 0 for no limit (default 300; 30 with --quick)
 *   --json    default bench/results/frame.json
 *   --scenes  where compare_knot.json is (default scenes)
 *   --quick   two small knots, 320x180, a 256 atlas, one or three runs
 *             per median: a check that everything runs, not a measurement
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sam/sam_args.h"
#include "sam/sam_build.h"
#include "sam/sam_deform.h"
#include "sam/sam_runtime.h"
#include "sam/sam_scene.h"
#include "sam/sam_shape.h"
#include "bench_util.h"

static void die(const char *what, const sam_error *err)
{
    bench_die("bench_frame", what, err);
}

/* Copy bandwidth in bytes per second (read + write counted), best of 5. */
static double memory_bandwidth(void)
{
    size_t n = 256u << 20;
    char *a = malloc(n), *b = malloc(n);
    if (!a || !b)
        die("bandwidth buffers", NULL);
    memset(a, 1, n);
    memset(b, 2, n);
    double best = 0;
    for (int i = 0; i < 5; ++i) {
        double t = sam_seconds();
        memcpy(b, a, n);
        t = sam_seconds() - t;
        best = fmax(best, 2.0 * (double)n / t);
        a[i] = b[n - 1 - i]; /* keep the copies observable */
    }
    free(a);
    free(b);
    return best;
}

typedef sam_status (*pass_fn)(sam_runtime *rt, void *user, sam_error *err);

static sam_status run_irradiance(sam_runtime *rt, void *user, sam_error *err)
{
    (void)user;
    return sam_runtime_irradiance(rt, err);
}

static sam_status run_translucency(sam_runtime *rt, void *user, sam_error *err)
{
    (void)user;
    return sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 0, err);
}

/* One animated frame's update: the pose at the next frame time, then the
 * sample walk (user: the frame counter). */
static sam_status run_update(sam_runtime *rt, void *user, sam_error *err)
{
    int *frame = user;
    sam_status st = sam_runtime_deform(rt, (float)++*frame / 30.0f, err);
    return st == SAM_OK ? sam_runtime_walk(rt, err) : st;
}

static sam_status run_shade(sam_runtime *rt, void *user, sam_error *err)
{
    sam_image img;
    sam_status st = sam_runtime_render(rt, user, &img, err);
    sam_image_destroy(&img);
    return st;
}

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

static const frame_config full_config = {1920, 1080, 0, 9, 3, 3, 4, {120, 400, 900, 2250}, 1, 3};
static const frame_config quick_config = {320, 180, 256, 3, 1, 1, 2, {40, 80}, 0, 1};

/* One call of `fn`, closed by glFinish: its wall time in ms, and in
 * gpu_ms[k] the GL timer-query time of passes[k] (<= 0 where the driver
 * reports none; a pass that did not run reports its last run's time, or a
 * negative value if it never ran). */
static double time_call(sam_runtime *rt, pass_fn fn, void *user, const sam_pass *passes, int pass_count,
                        double *gpu_ms)
{
    sam_error err;
    glFinish();
    double start = sam_seconds();
    if (fn(rt, user, &err) != SAM_OK)
        die("pass", &err);
    glFinish();
    double ms = 1e3 * (sam_seconds() - start);
    for (int k = 0; k < pass_count; ++k)
        gpu_ms[k] = sam_runtime_pass_ms(rt, passes[k]);
    return ms;
}

/* Median wall time (ms) of `runs` calls (at most 32), each closed by
 * glFinish, and in gpu_ms[k] the median GL timer-query time of passes[k]
 * (at most SAM_PASS_COUNT; <= 0 where the driver reports none). The caller
 * names only passes the call runs. */
static double median_ms_gpu(sam_runtime *rt, pass_fn fn, void *user, int runs, const sam_pass *passes,
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

/* median_ms_gpu on two runtimes side by side: their calls alternate
 * A B, B A, A B, ... after an untimed call of each, so a change in the
 * machine's load falls on both alike and neither always runs first.
 * ms[r] and gpu_ms[r][k] are runtime r's medians. */
static void median_ms_pair(sam_runtime *const rt[2], pass_fn fn, void *const user[2], int runs,
                           const sam_pass *passes, int pass_count, double ms[2], double gpu_ms[2][SAM_PASS_COUNT])
{
    double t[2][32], g[2][SAM_PASS_COUNT][32], call_gpu[SAM_PASS_COUNT];
    for (int i = -1; i < runs; ++i)
        for (int j = 0; j < 2; ++j) {
            int r = i % 2 ? 1 - j : j; /* the untimed round and odd rounds run B first */
            double wall = time_call(rt[r], fn, user[r], passes, pass_count, call_gpu);
            if (i < 0)
                continue;
            t[r][i] = wall;
            for (int k = 0; k < pass_count; ++k)
                g[r][k][i] = call_gpu[k];
        }
    for (int r = 0; r < 2; ++r) {
        ms[r] = bench_median(t[r], runs);
        for (int k = 0; k < pass_count; ++k)
            gpu_ms[r][k] = bench_median(g[r][k], runs);
    }
}

static double median_ms(sam_runtime *rt, pass_fn fn, void *user, int runs)
{
    return median_ms_gpu(rt, fn, user, runs, NULL, 0, NULL);
}

/* A time or ratio, or null where there is none (<= 0): a GL timer query
 * the driver did not answer, a ratio of such times, an estimate not made. */
static void json_positive(FILE *json, const char *key, double value)
{
    if (value > 0)
        fprintf(json, "\"%s\": %.4f", key, value);
    else
        fprintf(json, "\"%s\": null", key);
}

/* Texture-space diffusion with each optimisation against none, in three
 * views of the object (bounding radius r about the origin). The cost of
 * the diffusion is the render's wall time less that of the same view
 * without diffusion (llvmpipe's timer queries are not reliable for these
 * passes), so the speed-up compares what the optimisations act on. */
static void optimization_table(sam_runtime *rt, sam_render_view view, const float centre[3], float r, int runs,
                               FILE *json)
{
    static const struct {
        const char *name;
        float distance; /* in bounding radii from the centre */
    } views[3] = {{"close", 1.6f}, {"whole", 3.2f}, {"far", 16.0f}};
    static const struct {
        const char *name;
        int culled, clipped, depth_sized;
    } configs[5] = {{"none", 0, 0, 0},
                    {"culled", 1, 0, 0},
                    {"clipped", 0, 1, 0},
                    {"depth-sized", 0, 0, 1},
                    {"all", 1, 1, 1}};
    printf("          texture-space diffusion cost, ms (speed-up against no optimisation):\n");
    fprintf(json, ", \"texture_space_optimizations\": [");
    for (int v = 0; v < 3; ++v) {
        memcpy(view.target, centre, sizeof view.target);
        memcpy(view.eye, centre, sizeof view.eye);
        view.eye[2] += views[v].distance * r;
        view.eye[1] += 0.2f * r;
        view.diffusion = 0;
        double plain = median_ms(rt, run_shade, &view, runs);
        view.diffusion = 3;
        printf("            %-6s (render without diffusion %.1f ms)", views[v].name, plain);
        fprintf(json, "%s{\"view\": \"%s\", \"eye_distance_radii\": %.1f, \"render_without_diffusion_ms\": %.3f",
                v ? ", " : "", views[v].name, views[v].distance, plain);
        double base = 0;
        for (int c = 0; c < 5; ++c) {
            view.options.culled = configs[c].culled;
            view.options.clipped = configs[c].clipped;
            view.options.depth_sized = configs[c].depth_sized;
            double cost = median_ms(rt, run_shade, &view, runs) - plain;
            if (c == 0)
                base = cost;
            printf(" %s %.1f (%.2fx)", configs[c].name, cost, base / cost);
            fprintf(json, ", \"%s_ms\": %.3f, \"%s_speedup\": %.3f", configs[c].name, cost, configs[c].name,
                    base / cost);
        }
        printf("\n");
        fprintf(json, "}");
    }
    fprintf(json, "]");
}

static const char *const diffusion_names[4] = {"none", "screen", "preintegrated", "texture"};
static const struct {
    const char *name;
    sam_technique technique;
} techniques[4] = {{"sam", SAM_TECHNIQUE_SAM},
                   {"tsm", SAM_TECHNIQUE_TSM},
                   {"transmittance", SAM_TECHNIQUE_TRANSMITTANCE},
                   {"none", SAM_TECHNIQUE_NONE}};

/* Every technique with every diffusion on one scene (`view`'s camera,
 * lights set): the irradiance pass, which every technique needs (shadow
 * maps, L_d), the translucency pass, which only SAM needs, and the render
 * (shading, the diffusion, a TSM's maps, the read-back), each as a wall
 * time and a GL timer-query time; the frame is their sum. The renders run
 * in rounds, every combination once per round after an untimed round that
 * compiles the shaders, so a change in the machine's load falls on all of
 * them alike. Writes one JSON object to `json`. */
static void technique_matrix(sam_runtime *rt, sam_render_view view, const char *label, int runs, FILE *json)
{
    char uv_reason[256];
    int uv_ok = sam_runtime_uv_status(rt, uv_reason, sizeof uv_reason);
    /* It goes into a JSON string as it is. */
    for (char *c = uv_reason; *c; ++c)
        if (*c == '"' || *c == '\\')
            *c = '\'';
    sam_pass pass = SAM_PASS_IRRADIANCE;
    double irr_gpu, tra_gpu;
    double irr = median_ms_gpu(rt, run_irradiance, NULL, runs, &pass, 1, &irr_gpu);
    pass = SAM_PASS_TRANSLUCENCY;
    double tra = median_ms_gpu(rt, run_translucency, NULL, runs, &pass, 1, &tra_gpu);
    const char *skip[4][4] = {{NULL}};
    for (int t = 0; t < 4; ++t)
        for (int d = 0; d < 4; ++d) {
            if ((d == 3 || techniques[t].technique == SAM_TECHNIQUE_TSM) && !uv_ok)
                skip[t][d] = uv_reason;
            else if (techniques[t].technique == SAM_TECHNIQUE_TSM && d != 3)
                skip[t][d] = "tsm needs texture-space diffusion";
        }
    int combos[16], n = 0; /* technique * 4 + diffusion of each one rendered */
    for (int c = 0; c < 16; ++c)
        if (!skip[c / 4][c % 4])
            combos[n++] = c;
    /* [technique][diffusion][run]: wall ms, then the shading and diffusion
     * passes' timer-query ms. Each round starts at another combination, so
     * none always follows the same one (a texture-space render leaves the
     * caches full of its atlas). */
    double wall[4][4][32], shade_gpu[4][4][32], diffusion_gpu[4][4][32];
    for (int round = -1; round < runs; ++round)
        for (int i = 0; i < n; ++i) {
            int c = combos[(i + (round + 1) * n / (runs + 1)) % n], t = c / 4, d = c % 4;
            view.technique = techniques[t].technique;
            view.diffusion = d;
            sam_error err;
            glFinish();
            double start = sam_seconds();
            if (run_shade(rt, &view, &err) != SAM_OK)
                die(label, &err);
            glFinish();
            if (round < 0)
                continue;
            wall[t][d][round] = 1e3 * (sam_seconds() - start);
            shade_gpu[t][d][round] = sam_runtime_pass_ms(rt, SAM_PASS_SHADE);
            /* Only screen and texture space run a diffusion pass. */
            diffusion_gpu[t][d][round] = d == 1 || d == 3 ? sam_runtime_pass_ms(rt, SAM_PASS_DIFFUSION) : 0;
        }
    double total[4][4] = {{0}}; /* [technique][diffusion], 0: not rendered */
    printf("\n%s, %u vertices, %ux%u: frame ms by technique (render ms in brackets); irradiance pass %.1f ms, "
           "translucency pass %.2f ms (SAM only)\n",
           label, sam_runtime_vertex_count(rt), view.width, view.height, irr, tra);
    printf("%-14s %22s %22s %22s %22s\n", "", diffusion_names[0], diffusion_names[1], diffusion_names[2],
           diffusion_names[3]);
    fprintf(json, "{\"scene\": \"%s\", \"vertices\": %u, \"width\": %u, \"height\": %u, \"irradiance_ms\": %.4f, ",
            label, sam_runtime_vertex_count(rt), view.width, view.height, irr);
    json_positive(json, "irradiance_gpu_ms", irr_gpu);
    fprintf(json, ", \"translucency_ms\": %.4f, ", tra);
    json_positive(json, "translucency_gpu_ms", tra_gpu);
    fprintf(json, ", \"frames\": [");
    for (int t = 0; t < 4; ++t) {
        printf("%-14s", techniques[t].name);
        for (int d = 0; d < 4; ++d) {
            fprintf(json, "%s{\"technique\": \"%s\", \"diffusion\": \"%s\"", t || d ? ", " : "", techniques[t].name,
                    diffusion_names[d]);
            if (skip[t][d]) {
                printf(" %22s", "-");
                fprintf(json, ", \"skipped\": \"%s\"}", skip[t][d]);
                continue;
            }
            int sam = techniques[t].technique == SAM_TECHNIQUE_SAM, blurred = d == 1 || d == 3;
            double render = bench_median(wall[t][d], runs), shade = bench_median(shade_gpu[t][d], runs);
            double diffusion = bench_median(diffusion_gpu[t][d], runs);
            total[t][d] = irr + (sam ? tra : 0) + render;
            /* A TSM's maps are drawn outside every timer query, so its GPU
             * total would leave them out. */
            int gpu_complete = irr_gpu > 0 && (!sam || tra_gpu > 0) && shade > 0 && (!blurred || diffusion > 0) &&
                               techniques[t].technique != SAM_TECHNIQUE_TSM;
            char cell[64];
            snprintf(cell, sizeof cell, "%.1f (%.1f)", total[t][d], render);
            printf(" %22s", cell);
            fprintf(json, ", \"render_ms\": %.3f, \"total_ms\": %.3f, ", render, total[t][d]);
            json_positive(json, "shade_gpu_ms", shade);
            fprintf(json, ", ");
            json_positive(json, "diffusion_gpu_ms", diffusion);
            fprintf(json, ", ");
            json_positive(json, "total_gpu_ms", gpu_complete ? irr_gpu + (sam ? tra_gpu : 0) + shade + diffusion : 0);
            if (sam)
                fprintf(json, ", \"sam_share\": %.5f", tra / total[t][d]);
            fprintf(json, "}");
        }
        printf("\n");
    }
    fprintf(json, "]");
    /* SAM against each other technique on the same diffusion. */
    printf("%-14s", "SAM share");
    for (int d = 0; d < 4; ++d) {
        char cell[32];
        snprintf(cell, sizeof cell, "%.2f%%", total[0][d] > 0 ? 100 * tra / total[0][d] : 0);
        printf(" %22s", total[0][d] > 0 ? cell : "-");
    }
    printf("\n");
    for (int t = 1; t < 4; ++t) {
        printf("SAM / %-8s", techniques[t].name);
        fprintf(json, ", \"sam_over_%s\": {", techniques[t].name);
        int first = 1;
        for (int d = 0; d < 4; ++d) {
            char cell[32] = "-";
            if (total[0][d] > 0 && total[t][d] > 0) {
                snprintf(cell, sizeof cell, "%.3fx", total[0][d] / total[t][d]);
                fprintf(json, "%s\"%s\": %.4f", first ? "" : ", ", diffusion_names[d], total[0][d] / total[t][d]);
                first = 0;
            }
            printf(" %22s", cell);
        }
        fprintf(json, "}");
        printf("\n");
    }
    fprintf(json, "}");
}

/* The bending of the knot benchmarks' animated frames. */
static const sam_deformer knot_bend = {.type = SAM_DEFORM_BEND, .axis = {1, 0, 0}, .direction = {0, 1, 0},
                                       .length = 1.0f, .angle_deg = 60.0f, .period_s = 2.0f};

/* The light and environment of the knot benchmarks: one shadowed point
 * light behind the knot (translucency shows), a white environment. */
static void light_knot(sam_runtime *rt)
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
        die("lights", &err);
    sam_runtime_set_environment(rt, sh);
}

/* The technique matrix on scenes/compare_knot.json: its mesh, material,
 * lights, environment and camera, at the benchmark's frame size. */
static void knot_scene_matrix(const char *scenes, const frame_config *cfg, FILE *json)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/compare_knot.json", scenes);
    sam_scene scene;
    samfile_data d;
    sam_profile profile;
    float mm_per_unit;
    sam_runtime *rt = bench_scene_runtime("bench_frame", path, &scene, &d, &profile, &mm_per_unit, NULL, NULL);
    sam_render_view view;
    sam_runtime_scene_view(rt, &scene, &view, NULL, 0);
    view.width = cfg->width, view.height = cfg->height;
    technique_matrix(rt, view, "knot scene (compare_knot.json)", cfg->matrix_runs, json);
    sam_runtime_destroy(rt);
    samfile_free(&d);
    sam_scene_destroy(&scene);
}

/* One knot of cfg->resolutions[m]: its passes, the shading by diffusion, the
 * optimisations and technique matrix (head- and Buddha-sized knots), and
 * the animated update; a row on stdout and an object in `json`. */
/* The knot of the benchmarks with `resolution` segments along it (with
 * its UVs, for texture space), welded. */
static void knot_mesh(int resolution, sam_mesh *mesh)
{
    sam_error err;
    sam_shape_params sp;
    sam_shape_default_params("knot", &sp, NULL);
    sp.resolution = resolution;
    sam_shape_mesh s;
    if (sam_shape_generate("knot", &sp, &s, &err) != SAM_OK)
        die("knot", &err);
    sam_mesh_input in = {.name = "knot", .vertex_count = s.vertex_count, .positions = s.positions,
                         .uvs = s.uvs, .triangle_count = s.triangle_count, .triangles = s.triangles};
    if (sam_mesh_create(&in, mesh, NULL, &err) != SAM_OK)
        die("mesh", &err);
    sam_shape_mesh_destroy(&s);
}

/* The knot's map of kind `map` (its default N) in skin at 40 mm per unit,
 * into `d`, and its build seconds in `*seconds`. Returns 0, with `d` empty,
 * when `deadline` (may be NULL) cancelled the build. */
static int knot_map(const sam_mesh *mesh, const sam_profile *skin, sam_build_map map, bench_deadline *deadline,
                    samfile_data *d, double *seconds)
{
    sam_build_settings settings;
    sam_build_default_settings(&settings);
    settings.map = map;
    sam_error err;
    sam_status st = sam_build_samfile(mesh, skin, 40.0f, &settings, NULL, deadline ? bench_deadline_progress : NULL,
                                      deadline, d, seconds, &err);
    if (st != SAM_OK && !(deadline && deadline->cancelled))
        die("build", &err);
    return st == SAM_OK;
}

/* A runtime on `d`, lit by light_knot. */
static sam_runtime *knot_runtime(const samfile_data *d, const sam_profile *skin)
{
    sam_runtime *rt;
    sam_error err;
    if (sam_runtime_create(d, skin, 40.0f, &rt, &err) != SAM_OK)
        die("runtime", &err);
    light_knot(rt);
    return rt;
}

static void mesh_study(const frame_config *cfg, int m, const sam_profile *skin, double bandwidth, int optimizations,
                       FILE *json, FILE *matrix)
{
    sam_error err;
    sam_mesh mesh;
    knot_mesh(cfg->resolutions[m], &mesh);
    /* The paper's flat map, N = 3, which these tables measure
     * (docs/performance.md); the cut study below sets the builder's default
     * cut map against it. */
    samfile_data d;
    knot_map(&mesh, skin, SAM_BUILD_MAP_FLAT, NULL, &d, NULL);
    sam_runtime *rt = knot_runtime(&d, skin);
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = cfg->width, view.height = cfg->height, view.fov_deg = 40.0f, view.front = 1;
    view.options.atlas_size = cfg->atlas_size;
    view.eye[2] = 3.0f, view.up[1] = 1.0f;
    view.albedo[0] = view.albedo[1] = view.albedo[2] = 0.8f;
    double irr = median_ms(rt, run_irradiance, NULL, cfg->pass_runs);
    double tra = median_ms(rt, run_translucency, NULL, cfg->pass_runs);
    double sha = median_ms(rt, run_shade, &view, cfg->render_runs);
    /* Every surface-diffusion technique on the same frame. */
    double diffusion_ms[4], diffusion_gpu[4];
    sam_pass diffusion_pass = SAM_PASS_DIFFUSION;
    for (int t = 0; t < 4; ++t) {
        view.diffusion = t;
        diffusion_ms[t] = median_ms_gpu(rt, run_shade, &view, cfg->matrix_runs, &diffusion_pass, 1,
                                        &diffusion_gpu[t]);
    }
    view.diffusion = 0;
    /* Bytes the translucency pass must move per vertex. */
    double bytes = 16 + 16 + 16 + (double)d.samples_per_vertex * (16 + 16 + 4 + 16);
    double bound = 1e3 * bytes * d.vertex_count / bandwidth;
    double share = tra / (irr + tra + sha);
    printf("%9u %9.3f ms %11.3f ms %8.2f ms %12.1f %13.3f %9.0f%% %10.1f%%\n", d.vertex_count, irr, tra, sha,
           1e-3 * d.vertex_count / tra, bound, 100 * bound / tra, 100 * share);
    printf("          shading by diffusion: none %.1f ms, screen %.1f ms, pre-integrated %.1f ms, "
           "texture %.1f ms",
           diffusion_ms[0], diffusion_ms[1], diffusion_ms[2], diffusion_ms[3]);
    if (diffusion_gpu[1] > 0)
        printf(" (diffusion pass GPU ms: screen %.3f, texture %.3f)", diffusion_gpu[1], diffusion_gpu[3]);
    printf("\n");
    /* The "_1080p" keys keep their names in --quick, whose frames are smaller (see "width"). */
    fprintf(json,
            "    {\"vertices\": %u, \"samples_per_vertex\": %u, \"irradiance_ms\": %.4f, \"translucency_ms\": "
            "%.4f, \"shade_1080p_ms\": %.3f, \"translucency_vertices_per_s\": %.0f, \"bytes_per_vertex\": %.0f, "
            "\"bandwidth_bound_ms\": %.4f, \"fraction_of_bound\": %.4f, \"translucency_share_1080p\": %.4f, "
            "\"shade_1080p_ms_by_diffusion\": {\"%s\": %.3f, \"%s\": %.3f, \"%s\": %.3f, \"%s\": %.3f}, "
            "\"diffusion_pass_gpu_ms\": {\"screen\": %.4f, \"texture\": %.4f}",
            d.vertex_count, d.samples_per_vertex, irr, tra, sha, 1e3 * d.vertex_count / tra, bytes, bound,
            bound / tra, share, diffusion_names[0], diffusion_ms[0], diffusion_names[1], diffusion_ms[1],
            diffusion_names[2], diffusion_ms[2], diffusion_names[3], diffusion_ms[3], diffusion_gpu[1],
            diffusion_gpu[3]);
    if (m == cfg->head || m == cfg->buddha) {
        if (optimizations) {
            float centre[3], radius;
            sam_runtime_bounds(rt, centre, &radius);
            optimization_table(rt, view, centre, radius, cfg->render_runs, json);
        }
        char label[64];
        snprintf(label, sizeof label, "%s knot", m == cfg->head ? "head-sized" : "buddha-sized");
        fprintf(matrix, "%s    ", m == cfg->head ? "" : ",\n");
        technique_matrix(rt, view, label, cfg->matrix_runs, matrix);
    }
    /* Last, so the other passes ran on the rest pose: the per-frame
     * update of a bending mesh (SAM paper Sec. 3.4; its Fig. 12 says an
     * animated model's frame costs only slightly more). */
    if (sam_runtime_set_deformers(rt, &knot_bend, 1, &err) != SAM_OK)
        die("deformers", &err);
    int frame = 0;
    double upd = median_ms(rt, run_update, &frame, cfg->pass_runs);
    /* On a deformed pose the translucency pass carries K from rest by
     * the fans' quadrature (shaders/fan_form_factor.glsl): its own cost. */
    double posed_tra = median_ms(rt, run_translucency, NULL, cfg->pass_runs);
    if (sam_runtime_set_posed_k(rt, SAM_POSED_K_EQ15, &err) != SAM_OK)
        die("posed K", &err);
    double eq15_tra = median_ms(rt, run_translucency, NULL, cfg->pass_runs);
    double nv = d.vertex_count;
    printf("          animated update (deform + walk): %.3f ms, %.1f ns per vertex; translucency %.1f ns per "
           "vertex at rest, posed %.1f (K carried) or %.1f (eq. 15); SAM passes of a frame %.2fx (%.2fx) the "
           "static ones\n",
           upd, 1e6 * upd / nv, 1e6 * tra / nv, 1e6 * posed_tra / nv, 1e6 * eq15_tra / nv,
           (irr + posed_tra + upd) / (irr + tra), (irr + eq15_tra + upd) / (irr + tra));
    fprintf(json,
            ", \"update_ms\": %.4f, \"update_ns_per_vertex\": %.2f, \"translucency_ns_per_vertex\": %.2f, "
            "\"posed_translucency_ns_per_vertex\": %.2f, \"eq15_translucency_ns_per_vertex\": %.2f, "
            "\"animated_over_static\": %.4f, \"eq15_animated_over_static\": %.4f",
            upd, 1e6 * upd / nv, 1e6 * tra / nv, 1e6 * posed_tra / nv, 1e6 * eq15_tra / nv,
            (irr + posed_tra + upd) / (irr + tra), (irr + eq15_tra + upd) / (irr + tra));
    fprintf(json, "}%s\n", m < cfg->mesh_count - 1 ? "," : "");
    sam_runtime_destroy(rt);
    samfile_free(&d);
    sam_mesh_destroy(&mesh);
}

/* The cut map's cost targets against the flat map (N = 3), as ratios. */
#define CUT_TRANSLUCENCY_TARGET 2.0 /* node + translucency passes over the flat map's translucency pass */
#define CUT_ANIMATED_TARGET 1.5     /* an animated frame's deform, walk, irradiance, node and translucency */
/* Default limits on a cut build (--cut-limit): on 2 cores it took 90 s on
 * the 18k-vertex knot and grows faster than the vertex count, so the larger
 * knots' cut maps would take hours (docs/performance.md). */
#define CUT_LIMIT_S 300.0
#define CUT_LIMIT_QUICK_S 30.0

/* A whole animated frame's SAM work: the update (deform, walk), the
 * irradiance pass, then the node and translucency passes (user: as
 * run_update's). */
static sam_status run_animated_frame(sam_runtime *rt, void *user, sam_error *err)
{
    sam_status st = run_update(rt, user, err);
    if (st == SAM_OK)
        st = run_irradiance(rt, NULL, err);
    return st == SAM_OK ? run_translucency(rt, NULL, err) : st;
}

/* Samples per vertex that name something (the translucency pass skips
 * empty slots, so its cost follows these, not N). */
static double filled_samples(const samfile_data *d)
{
    size_t filled = 0, slots = (size_t)d->vertex_count * d->samples_per_vertex;
    for (size_t i = 0; i < slots; ++i)
        filled += d->sample_index[i] != SAMFILE_NO_SAMPLE;
    return (double)filled / d->vertex_count;
}

/* The largest ratio of each kind over the cut study's knots (0: none
 * measured), and which knots it could not measure. */
enum { CUT_TRANSLUCENCY, CUT_TRANSLUCENCY_GPU, CUT_ANIMATED, CUT_ANIMATED_GPU, CUT_RATIOS };
typedef struct cut_summary {
    double worst[CUT_RATIOS];
    uint32_t smallest, largest; /* vertices of the knots measured */
    int measured, unbuilt;      /* knots measured; knots whose cut map was not built, or not loaded */
    char unbuilt_list[128];     /* the vertex counts of those */
} cut_summary;

/* The sum of `count` timer-query times, or 0 where one is missing. */
static double gpu_sum(const double *ms, int count)
{
    double sum = 0;
    for (int k = 0; k < count; ++k) {
        if (!(ms[k] > 0))
            return 0;
        sum += ms[k];
    }
    return sum;
}

static double ratio_or_zero(double a, double b)
{
    return a > 0 && b > 0 ? a / b : 0;
}

/* Counts the knot of `nv` vertices as not measured; larger knots are then
 * skipped too. */
static void skip_knot(cut_summary *sum, uint32_t nv)
{
    size_t used = strlen(sum->unbuilt_list);
    snprintf(sum->unbuilt_list + used, sizeof sum->unbuilt_list - used, "%s%u", used ? ", " : "", nv);
    sum->unbuilt++;
}

/* The default cut map (its default N) against the flat map (N = 3) on the knot of
 * cfg->resolutions[m], both runtimes side by side (median_ms_pair):
 * sam_runtime_translucency, which runs a cut map's node pass before the
 * translucency pass, and an animated frame's whole SAM work. The cut build
 * stops at `limit_s` (bench_deadline): such a knot is reported with the
 * build's estimate, and larger knots, whose builds take longer still, are
 * not built. A row on stdout, an object in `json`. */
static void cut_study(const frame_config *cfg, int m, const sam_profile *skin, double limit_s, int timers,
                      cut_summary *sum, FILE *json)
{
    sam_mesh mesh;
    knot_mesh(cfg->resolutions[m], &mesh);
    const uint32_t nv = mesh.vertex_count;
    fprintf(json, "%s      {\"vertices\": %u", m ? ",\n" : "", nv);
    if (sum->unbuilt) {
        printf("%9u  not measured: a smaller knot's cut map was not built within the limit or not loaded\n", nv);
        fprintf(json, ", \"skipped\": \"a smaller knot's cut map was not built within the limit or not loaded\"}");
    }
    samfile_data d[2]; /* cut, flat */
    double build_s[2];
    bench_deadline deadline;
    bench_deadline_start(&deadline, limit_s);
    if (!sum->unbuilt) {
        knot_map(&mesh, skin, SAM_BUILD_MAP_FLAT, NULL, &d[1], &build_s[1]);
        fprintf(json, ", \"flat_build_s\": %.3f", build_s[1]);
        if (!knot_map(&mesh, skin, SAM_BUILD_MAP_CUT, &deadline, &d[0], &build_s[0])) {
            char how[128];
            bench_deadline_describe(&deadline, how, sizeof how);
            printf("%9u  not measured: the cut build passed the limit: %s (flat %.1f s)\n", nv, how, build_s[1]);
            fprintf(json, ", \"skipped\": \"the cut build passed the limit\", ");
            bench_deadline_json(json, "cut_build", &deadline);
            fprintf(json, "}");
            samfile_free(&d[1]);
        }
    }
    if (sum->unbuilt || deadline.cancelled) {
        skip_knot(sum, nv);
        sam_mesh_destroy(&mesh);
        return;
    }
    /* A GL may not hold the cut map's samples (llvmpipe: 128 MiB per
     * storage block, passed near 260k vertices at N = 32): said, and the
     * larger knots skipped, rather than the whole study lost. */
    sam_runtime *rt[2] = {NULL, NULL};
    sam_error err;
    for (int r = 0; r < 2; ++r) {
        if (sam_runtime_create(&d[r], skin, 40.0f, &rt[r], &err) != SAM_OK) {
            printf("%9u  not measured: the %s map does not load: %s\n", nv, r ? "flat" : "cut", err.message);
            fprintf(json, ", \"skipped\": \"the %s map does not load on this GL\"}", r ? "flat" : "cut");
            for (int k = 0; k < 2; ++k) {
                sam_runtime_destroy(rt[k]);
                samfile_free(&d[k]);
            }
            skip_knot(sum, nv);
            sam_mesh_destroy(&mesh);
            return;
        }
        light_knot(rt[r]);
    }
    for (int r = 0; r < 2; ++r)
        if (sam_runtime_irradiance(rt[r], &err) != SAM_OK)
            die("irradiance", &err);
    /* The node pass last: a flat map has none, so its sums take one pass fewer. */
    static const sam_pass passes[5] = {SAM_PASS_DEFORM, SAM_PASS_WALK, SAM_PASS_IRRADIANCE, SAM_PASS_TRANSLUCENCY,
                                       SAM_PASS_NODES};
    void *const no_user[2] = {NULL, NULL};
    double tra[2], tra_gpu[2][SAM_PASS_COUNT];
    median_ms_pair(rt, run_translucency, no_user, cfg->pass_runs, passes + 3, 2, tra, tra_gpu);
    for (int r = 0; r < 2; ++r)
        if (sam_runtime_set_deformers(rt[r], &knot_bend, 1, &err) != SAM_OK)
            die("deformers", &err);
    int frames[2] = {0, 0}; /* both maps see the same poses */
    void *const frame_user[2] = {&frames[0], &frames[1]};
    double ani[2], ani_gpu[2][SAM_PASS_COUNT];
    median_ms_pair(rt, run_animated_frame, frame_user, cfg->pass_runs, passes, 5, ani, ani_gpu);
    const double ratio[CUT_RATIOS] = {
        tra[0] / tra[1], timers ? ratio_or_zero(gpu_sum(tra_gpu[0], 2), gpu_sum(tra_gpu[1], 1)) : 0,
        ani[0] / ani[1], timers ? ratio_or_zero(gpu_sum(ani_gpu[0], 5), gpu_sum(ani_gpu[1], 4)) : 0};
    const double filled[2] = {filled_samples(&d[0]), filled_samples(&d[1])};
    printf("%9u %8.1f s %6.1f s %7.2f %7.2f %10.3f ms %10.3f ms %6.2fx %10.1f ms %10.1f ms %6.2fx", nv, build_s[0],
           build_s[1], filled[0], filled[1], tra[0], tra[1], ratio[CUT_TRANSLUCENCY], ani[0], ani[1],
           ratio[CUT_ANIMATED]);
    if (ratio[CUT_TRANSLUCENCY_GPU] > 0 || ratio[CUT_ANIMATED_GPU] > 0)
        printf("   GPU %.2fx, %.2fx", ratio[CUT_TRANSLUCENCY_GPU], ratio[CUT_ANIMATED_GPU]);
    printf("\n");
    fprintf(json,
            ", \"cut_build_s\": %.3f, \"cut_samples_per_vertex\": %u, \"cut_nodes\": %u, "
            "\"cut_samples_filled_per_vertex\": %.3f, "
            "\"flat_samples_filled_per_vertex\": %.3f, \"cut_translucency_ms\": %.4f, \"flat_translucency_ms\": "
            "%.4f, \"translucency_ratio\": %.4f, ",
            build_s[0], d[0].samples_per_vertex, d[0].node_count, filled[0], filled[1], tra[0], tra[1], ratio[CUT_TRANSLUCENCY]);
    json_positive(json, "cut_nodes_gpu_ms", timers ? tra_gpu[0][1] : 0);
    fprintf(json, ", ");
    json_positive(json, "cut_translucency_gpu_ms", timers ? tra_gpu[0][0] : 0);
    fprintf(json, ", ");
    json_positive(json, "flat_translucency_gpu_ms", timers ? tra_gpu[1][0] : 0);
    fprintf(json, ", ");
    json_positive(json, "translucency_gpu_ratio", ratio[CUT_TRANSLUCENCY_GPU]);
    fprintf(json, ", \"cut_animated_frame_ms\": %.4f, \"flat_animated_frame_ms\": %.4f, \"animated_ratio\": %.4f, ",
            ani[0], ani[1], ratio[CUT_ANIMATED]);
    json_positive(json, "cut_animated_frame_gpu_ms", timers ? gpu_sum(ani_gpu[0], 5) : 0);
    fprintf(json, ", ");
    json_positive(json, "flat_animated_frame_gpu_ms", timers ? gpu_sum(ani_gpu[1], 4) : 0);
    fprintf(json, ", ");
    json_positive(json, "animated_gpu_ratio", ratio[CUT_ANIMATED_GPU]);
    fprintf(json, "}");
    for (int k = 0; k < CUT_RATIOS; ++k)
        sum->worst[k] = fmax(sum->worst[k], ratio[k]);
    if (!sum->measured++)
        sum->smallest = nv;
    sum->largest = nv;
    for (int r = 0; r < 2; ++r) {
        sam_runtime_destroy(rt[r]);
        samfile_free(&d[r]);
    }
    sam_mesh_destroy(&mesh);
}

/* One ratio's summary line against its target, and its JSON fields. */
static void cut_verdict(const cut_summary *sum, int k, const char *key, const char *what, double target,
                        double limit_s, int quick, FILE *json)
{
    const double worst = sum->worst[k];
    const char *verdict = !(worst > 0) ? "NOT MEASURED" : worst <= target ? "PASS" : "MISS";
    printf("cut against flat N = 3, %s: ", what);
    if (worst > 0)
        printf("worst %.2fx on knots of %u to %u vertices", worst, sum->smallest, sum->largest);
    else if (sum->measured)
        printf("no GL timer-query times (a CPU rasteriser times submission, not execution)");
    else
        printf("no knot measured");
    printf("; target <= %.1f: %s", target, verdict);
    if (sum->unbuilt)
        printf(" (not measured at %s vertices: no cut map built within the %g s limit, or loaded by the GL)",
               sum->unbuilt_list, limit_s);
    printf("%s\n", quick ? " [--quick: not a measurement]" : "");
    fprintf(json, ",\n    ");
    json_positive(json, key, worst);
    fprintf(json, ", \"%s_target\": %.1f, \"%s_verdict\": \"%s\"", key, target, key, verdict);
}

/* The cut study on every knot of `cfg`, with its summary lines and the
 * "cut_against_flat" JSON object. */
static void cut_section(const frame_config *cfg, const sam_profile *skin, double limit_s, int timers, int quick,
                        FILE *json)
{
    sam_build_settings defaults;
    sam_build_default_settings(&defaults);
    const uint32_t cut_n = sam_build_samples(&defaults);
    defaults.map = SAM_BUILD_MAP_FLAT;
    printf("\ncut map (N = %u) against flat map (N = %u), side by side, medians of %d: sam_runtime_translucency "
           "(cut: node + translucency pass) and an animated frame (deform, walk, irradiance, node, translucency)\n",
           cut_n, sam_build_samples(&defaults), cfg->pass_runs);
    printf("%9s %10s %8s %15s %13s %13s %7s %13s %13s %7s\n", "vertices", "cut build", "flat", "filled cut/flat",
           "cut transl.", "flat transl.", "ratio", "cut frame", "flat frame", "ratio");
    fprintf(json, "  \"cut_against_flat\": {\n    \"build_limit_s\": %g, \"runs\": %d, \"knots\": [\n", limit_s,
            cfg->pass_runs);
    cut_summary sum;
    memset(&sum, 0, sizeof sum);
    for (int m = 0; m < cfg->mesh_count; ++m)
        cut_study(cfg, m, skin, limit_s, timers, &sum, json);
    fprintf(json, "\n    ]");
    cut_verdict(&sum, CUT_TRANSLUCENCY, "translucency_ratio_worst",
                "node + translucency pass / translucency pass (wall)", CUT_TRANSLUCENCY_TARGET, limit_s, quick, json);
    cut_verdict(&sum, CUT_TRANSLUCENCY_GPU, "translucency_gpu_ratio_worst",
                "node + translucency pass / translucency pass (GL timer queries)", CUT_TRANSLUCENCY_TARGET, limit_s,
                quick, json);
    cut_verdict(&sum, CUT_ANIMATED, "animated_ratio_worst",
                "animated frame's deform + walk + irradiance + node + translucency (wall)", CUT_ANIMATED_TARGET,
                limit_s, quick, json);
    cut_verdict(&sum, CUT_ANIMATED_GPU, "animated_gpu_ratio_worst",
                "animated frame's deform + walk + irradiance + node + translucency (GL timer queries)",
                CUT_ANIMATED_TARGET, limit_s, quick, json);
    fprintf(json, "\n  }\n");
}

static void usage(FILE *out)
{
    fprintf(out, "usage: bench_frame [--quick] [--optimizations] [--cut-only] [--cut-limit SECONDS] [--json FILE]\n"
                 "                   [--scenes DIR]\n"
                 "\n"
                 "Times the frame passes on knots of growing size, every technique x diffusion at 1080p, and the\n"
                 "animated update; then the default cut map against the flat N = 3 map on the same knots, with\n"
                 "the targets' PASS or MISS. Writes FILE (default bench/results/frame.json). --quick: smaller\n"
                 "frames and meshes, for the tests. --cut-only: the cut study alone. --cut-limit: stop a cut\n"
                 "build after this long, 0 for none (default 300; 30 with --quick). scripts/bench.sh runs it\n"
                 "with the other benchmarks.\n"
                 "\n"
                 "examples:\n"
                 "  bench_frame --quick --json /tmp/frame.json\n"
                 "  bench_frame --optimizations\n"
                 "  bench_frame --cut-only --json /tmp/frame_cut.json\n");
}

int main(int argc, char **argv)
{
    const char *json_path = "bench/results/frame.json", *scenes = "scenes";
    const frame_config *cfg = &full_config;
    int optimizations = 0, quick = 0, cut_only = 0;
    double cut_limit = -1;
    const sam_arg args[] = {
        {"--quick", SAM_ARG_FLAG, .target = &quick},
        {"--optimizations", SAM_ARG_FLAG, .target = &optimizations},
        {"--cut-only", SAM_ARG_FLAG, .target = &cut_only},
        {"--cut-limit", SAM_ARG_DOUBLE, &cut_limit, .lo = 0, .hi = 1e6, .value = "SECONDS"},
        {"--json", SAM_ARG_STRING, &json_path, .value = "FILE"},
        {"--scenes", SAM_ARG_STRING, &scenes, .value = "DIR"},
    };
    const sam_args_spec spec = {"bench_frame", args, sizeof args / sizeof *args, NULL, 0, 0, NULL, usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (quick)
        cfg = &quick_config;
    if (cut_limit < 0)
        cut_limit = quick ? CUT_LIMIT_QUICK_S : CUT_LIMIT_S;
    sam_gl_context *gl;
    sam_error err;
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK)
        die("GL", &err);
    const sam_gl_info *info = sam_gl_context_info(gl);
    double bandwidth = memory_bandwidth();
    sam_atomic_file out;
    bench_json_open("bench_frame", json_path, &out);
    FILE *json = out.fp;
    fprintf(json,
            "{\n  \"renderer\": \"%s\",\n  \"quick\": %s,\n  \"width\": %u,\n  \"height\": %u,\n"
            "  \"memcpy_bandwidth_gb_s\": %.2f,\n",
            info->renderer, cfg == &quick_config ? "true" : "false", cfg->width, cfg->height, bandwidth * 1e-9);
    printf("GL: %s; memcpy bandwidth %.1f GB/s; frames %ux%u\n", info->renderer, bandwidth * 1e-9, cfg->width,
           cfg->height);
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    if (!cut_only) {
        /* The technique matrices, written after the meshes. */
        char *matrix_text = NULL;
        size_t matrix_size = 0;
        FILE *matrix = open_memstream(&matrix_text, &matrix_size);
        if (!matrix)
            die("technique matrix buffer", NULL);
        printf("%9s %11s %13s %11s %12s %13s %10s %11s\n", "vertices", "irradiance", "translucency", "shade",
               "Mvertices/s", "bound (ms)", "of bound", "SAM share");
        fprintf(json, "  \"meshes\": [\n");
        for (int m = 0; m < cfg->mesh_count; ++m)
            mesh_study(cfg, m, &skin, bandwidth, optimizations, json, matrix);
        fprintf(matrix, ",\n    ");
        knot_scene_matrix(scenes, cfg, matrix);
        if (fclose(matrix) != 0)
            die("technique matrix buffer", NULL);
        fprintf(json, "  ],\n  \"frame_by_technique\": [\n%s\n  ],\n", matrix_text);
        free(matrix_text);
    }
    /* llvmpipe's and softpipe's timer queries read about 0 for compute
     * passes and time the submission of the others: no ratio of theirs. */
    const int timers = !strstr(info->renderer, "llvmpipe") && !strstr(info->renderer, "softpipe");
    cut_section(cfg, &skin, cut_limit, timers, quick, json);
    fprintf(json, "}\n");
    bench_json_commit("bench_frame", &out);
    sam_gl_context_destroy(gl);
    return 0;
}
