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
 * bytes it must move per vertex (its T, and per sample the rest-K record
 * and the back vertex's L_d) over the memory bandwidth measured here with
 * memcpy. Last, the per-frame update of
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
 * stopped, and larger knots are not measured. The same study runs on the
 * skin scans (dragon, head) where meshes/fetch_scans.sh has fetched them:
 * their cut maps' rows are mostly vertices, which cost a deforming mesh
 * more than nodes do; their verdicts are printed apart.
 *
 * Usage: bench_frame [--quick] [--optimizations] [--cut-only] [--cut-limit S] [--json FILE] [--scenes DIR]
 *                    [--scans DIR]
 *   --cut-only   the cut study alone
 *   --cut-limit  seconds a cut build may take, 0 for no limit (default 300; 30 with --quick)
 *   --json    default bench/results/frame.json
 *   --scenes  where compare_knot.json is (default scenes)
 *   --scans   where the scans are (default meshes/scans)
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
#include "frame/frame_common.h"

/* Copy bandwidth in bytes per second (read + write counted), best of 5. */
static double memory_bandwidth(void)
{
    size_t n = 256u << 20;
    char *a = malloc(n), *b = malloc(n);
    if (!a || !b)
        frame_die("bandwidth buffers", NULL);
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

static sam_status run_shade(sam_runtime *rt, void *user, sam_error *err)
{
    sam_image img;
    sam_status st = sam_runtime_render(rt, user, &img, err);
    sam_image_destroy(&img);
    return st;
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
        double plain = frame_median_ms(rt, run_shade, &view, runs);
        view.diffusion = 3;
        printf("            %-6s (render without diffusion %.1f ms)", views[v].name, plain);
        fprintf(json, "%s{\"view\": \"%s\", \"eye_distance_radii\": %.1f, \"render_without_diffusion_ms\": %.3f",
                v ? ", " : "", views[v].name, views[v].distance, plain);
        double base = 0;
        for (int c = 0; c < 5; ++c) {
            view.options.culled = configs[c].culled;
            view.options.clipped = configs[c].clipped;
            view.options.depth_sized = configs[c].depth_sized;
            double cost = frame_median_ms(rt, run_shade, &view, runs) - plain;
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
    int uv_ok = sam_runtime_uv_status(rt, uv_reason, sizeof uv_reason, NULL);
    /* It goes into a JSON string as it is. */
    for (char *c = uv_reason; *c; ++c)
        if (*c == '"' || *c == '\\')
            *c = '\'';
    sam_pass pass = SAM_PASS_IRRADIANCE;
    double irr_gpu, tra_gpu;
    double irr = frame_median_ms_gpu(rt, frame_run_irradiance, NULL, runs, &pass, 1, &irr_gpu);
    pass = SAM_PASS_TRANSLUCENCY;
    double tra = frame_median_ms_gpu(rt, frame_run_translucency, NULL, runs, &pass, 1, &tra_gpu);
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
                frame_die(label, &err);
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
    frame_json_positive(json, "irradiance_gpu_ms", irr_gpu);
    fprintf(json, ", \"translucency_ms\": %.4f, ", tra);
    frame_json_positive(json, "translucency_gpu_ms", tra_gpu);
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
            frame_json_positive(json, "shade_gpu_ms", shade);
            fprintf(json, ", ");
            frame_json_positive(json, "diffusion_gpu_ms", diffusion);
            fprintf(json, ", ");
            frame_json_positive(json, "total_gpu_ms",
                                gpu_complete ? irr_gpu + (sam ? tra_gpu : 0) + shade + diffusion : 0);
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
static void mesh_study(const frame_config *cfg, int m, const sam_profile *skin, double bandwidth, int optimizations,
                       FILE *json, FILE *matrix)
{
    sam_error err;
    sam_mesh mesh;
    frame_knot_mesh(cfg->resolutions[m], &mesh);
    /* The paper's flat map, N = 3, which these tables measure
     * (docs/performance.md); the cut study below sets the builder's default
     * cut map against it. */
    samfile_data d;
    frame_knot_map(&mesh, skin, 40.0f, SAM_BUILD_MAP_FLAT, NULL, &d, NULL);
    sam_runtime *rt = frame_knot_runtime(&d, skin);
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = cfg->width, view.height = cfg->height, view.fov_deg = 40.0f, view.front = 1;
    view.options.atlas_size = cfg->atlas_size;
    view.eye[2] = 3.0f, view.up[1] = 1.0f;
    view.albedo[0] = view.albedo[1] = view.albedo[2] = 0.8f;
    double irr = frame_median_ms(rt, frame_run_irradiance, NULL, cfg->pass_runs);
    double tra = frame_median_ms(rt, frame_run_translucency, NULL, cfg->pass_runs);
    double sha = frame_median_ms(rt, run_shade, &view, cfg->render_runs);
    /* Every surface-diffusion technique on the same frame. */
    double diffusion_ms[4], diffusion_gpu[4];
    sam_pass diffusion_pass = SAM_PASS_DIFFUSION;
    for (int t = 0; t < 4; ++t) {
        view.diffusion = t;
        diffusion_ms[t] = frame_median_ms_gpu(rt, run_shade, &view, cfg->matrix_runs, &diffusion_pass, 1,
                                              &diffusion_gpu[t]);
    }
    view.diffusion = 0;
    /* Bytes the rest pose's translucency pass must move per vertex, its
     * rest K cached (the default): its T read and written, and per sample
     * the rest-K record and the L_d it names. */
    double bytes = 16 + 16 + (double)d.samples_per_vertex * (16 + 16);
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
    if (sam_runtime_set_deformers(rt, &frame_knot_bend, 1, &err) != SAM_OK)
        frame_die("deformers", &err);
    int frame = 0;
    double upd = frame_median_ms(rt, frame_run_update, &frame, cfg->pass_runs);
    /* On a deformed pose the translucency pass carries K from rest by
     * the fans' quadrature (shaders/fan_form_factor.glsl): its own cost. */
    double posed_tra = frame_median_ms(rt, frame_run_translucency, NULL, cfg->pass_runs);
    if (sam_runtime_set_posed_k(rt, SAM_POSED_K_EQ15, &err) != SAM_OK)
        frame_die("posed K", &err);
    double eq15_tra = frame_median_ms(rt, frame_run_translucency, NULL, cfg->pass_runs);
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

static void usage(FILE *out)
{
    fprintf(out, "usage: bench_frame [--quick] [--optimizations] [--cut-only] [--cut-limit SECONDS] [--json FILE]\n"
                 "                   [--scenes DIR] [--scans DIR]\n"
                 "\n"
                 "Times the frame passes on knots of growing size, every technique x diffusion at 1080p, and the\n"
                 "animated update; then the default cut map against the flat N = 3 map on the same knots, with\n"
                 "the targets' PASS or MISS, and on the skin scans in DIR (default meshes/scans, fetched by\n"
                 "meshes/fetch_scans.sh) where they are. Writes FILE (default bench/results/frame.json).\n"
                 "--quick: smaller frames and meshes, no scans, for the tests. --cut-only: the cut study alone.\n"
                 "--cut-limit: stop a cut build after this long, 0 for none (default 300; 30 with --quick).\n"
                 "scripts/bench.sh runs it with the other benchmarks.\n"
                 "\n"
                 "examples:\n"
                 "  bench_frame --quick --json /tmp/frame.json\n"
                 "  bench_frame --optimizations\n"
                 "  bench_frame --cut-only --json /tmp/frame_cut.json\n");
}

int main(int argc, char **argv)
{
    const char *json_path = "bench/results/frame.json", *scenes = "scenes", *scans = "meshes/scans";
    const frame_config *cfg = &frame_full_config;
    int optimizations = 0, quick = 0, cut_only = 0;
    double cut_limit = -1;
    const sam_arg args[] = {
        {"--quick", SAM_ARG_FLAG, .target = &quick},
        {"--optimizations", SAM_ARG_FLAG, .target = &optimizations},
        {"--cut-only", SAM_ARG_FLAG, .target = &cut_only},
        {"--cut-limit", SAM_ARG_DOUBLE, &cut_limit, .lo = 0, .hi = 1e6, .value = "SECONDS"},
        {"--json", SAM_ARG_STRING, &json_path, .value = "FILE"},
        {"--scenes", SAM_ARG_STRING, &scenes, .value = "DIR"},
        {"--scans", SAM_ARG_STRING, &scans, .value = "DIR"},
    };
    const sam_args_spec spec = {"bench_frame", args, sizeof args / sizeof *args, NULL, 0, 0, NULL, usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (quick)
        cfg = &frame_quick_config;
    if (cut_limit < 0)
        cut_limit = quick ? CUT_LIMIT_QUICK_S : CUT_LIMIT_S;
    sam_gl_context *gl;
    sam_error err;
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK)
        frame_die("GL", &err);
    const sam_gl_info *info = sam_gl_context_info(gl);
    double bandwidth = memory_bandwidth();
    sam_atomic_file out;
    bench_json_open("bench_frame", json_path, &out);
    FILE *json = out.fp;
    fprintf(json,
            "{\n  \"renderer\": \"%s\",\n  \"quick\": %s,\n  \"width\": %u,\n  \"height\": %u,\n"
            "  \"memcpy_bandwidth_gb_s\": %.2f,\n",
            info->renderer, cfg == &frame_quick_config ? "true" : "false", cfg->width, cfg->height, bandwidth * 1e-9);
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
            frame_die("technique matrix buffer", NULL);
        printf("%9s %11s %13s %11s %12s %13s %10s %11s\n", "vertices", "irradiance", "translucency", "shade",
               "Mvertices/s", "bound (ms)", "of bound", "SAM share");
        fprintf(json, "  \"meshes\": [\n");
        for (int m = 0; m < cfg->mesh_count; ++m)
            mesh_study(cfg, m, &skin, bandwidth, optimizations, json, matrix);
        fprintf(matrix, ",\n    ");
        knot_scene_matrix(scenes, cfg, matrix);
        if (fclose(matrix) != 0)
            frame_die("technique matrix buffer", NULL);
        fprintf(json, "  ],\n  \"frame_by_technique\": [\n%s\n  ],\n", matrix_text);
        free(matrix_text);
    }
    /* llvmpipe's and softpipe's timer queries read about 0 for compute
     * passes and time the submission of the others: no ratio of theirs. */
    const int timers = !strstr(info->renderer, "llvmpipe") && !strstr(info->renderer, "softpipe");
    frame_cut_section(cfg, &skin, scans, cut_limit, timers, quick, json);
    fprintf(json, "}\n");
    bench_json_commit("bench_frame", &out);
    sam_gl_context_destroy(gl);
    return 0;
}

