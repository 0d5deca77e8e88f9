/* bench_frame's cut study: the default cut map against the flat N = 3 map
 * on the same knots, side by side (frame_common.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "frame_common.h"

/* The cut map's cost targets against the flat map (N = 3), as ratios. The
 * translucency target is against the flat pass as it was when the target
 * was set, its K evaluated per sample every frame (SAM_REST_K_EVALUATED);
 * the ratio against the flat map with its rest K cached too is printed
 * beside it. */
#define CUT_TRANSLUCENCY_TARGET 2.0 /* node + translucency passes over the flat map's translucency pass */
#define CUT_ANIMATED_TARGET 1.5     /* an animated frame's deform, walk, irradiance, node and translucency */

/* A whole animated frame's SAM work: the update (deform, walk), the
 * irradiance pass, then the node and translucency passes (user: as
 * frame_run_update's). */
static sam_status run_animated_frame(sam_runtime *rt, void *user, sam_error *err)
{
    sam_status st = frame_run_update(rt, user, err);
    if (st == SAM_OK)
        st = frame_run_irradiance(rt, NULL, err);
    return st == SAM_OK ? frame_run_translucency(rt, NULL, err) : st;
}

/* An animated frame's SAM work pass by pass, on `count` runtimes side by
 * side (the rounds of frame_median_ms_side_by_side): each pass closed by
 * glFinish, so that ms[r][p] is runtime r's median wall time of deform,
 * walk, irradiance, and the node and translucency passes (p = 0..3). Its
 * sum exceeds the whole frame's time by the three waits. */
enum { SPLIT_DEFORM, SPLIT_WALK, SPLIT_IRRADIANCE, SPLIT_TRANSLUCENCY, SPLIT_PASSES };
static void animated_frame_split(sam_runtime *const *rt, int count, int *frames, int runs,
                                 double (*ms)[SPLIT_PASSES])
{
    double t[FRAME_SIDE_MAX][SPLIT_PASSES][32];
    sam_error err;
    for (int i = 0; i < runs; ++i)
        for (int j = 0; j < count; ++j) {
            const int r = (i + j) % count;
            double mark[SPLIT_PASSES + 1];
            glFinish();
            mark[0] = sam_seconds();
            sam_status st = sam_runtime_deform(rt[r], (float)++frames[r] / 30.0f, &err);
            glFinish();
            mark[1] = sam_seconds();
            if (st == SAM_OK)
                st = sam_runtime_walk(rt[r], &err);
            glFinish();
            mark[2] = sam_seconds();
            if (st == SAM_OK)
                st = frame_run_irradiance(rt[r], NULL, &err);
            glFinish();
            mark[3] = sam_seconds();
            if (st == SAM_OK)
                st = frame_run_translucency(rt[r], NULL, &err);
            glFinish();
            mark[4] = sam_seconds();
            if (st != SAM_OK)
                frame_die("animated frame", &err);
            for (int p = 0; p < SPLIT_PASSES; ++p)
                t[r][p][i] = 1e3 * (mark[p + 1] - mark[p]);
        }
    for (int r = 0; r < count; ++r)
        for (int p = 0; p < SPLIT_PASSES; ++p)
            ms[r][p] = bench_median(t[r][p], runs);
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
enum {
    CUT_TRANSLUCENCY,
    CUT_TRANSLUCENCY_CACHED,
    CUT_TRANSLUCENCY_GPU,
    CUT_ANIMATED,
    CUT_ANIMATED_GPU,
    CUT_TRANSLUCENCY_FITTED,
    CUT_RATIOS
};
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

/* The samples per vertex the default cut map is fitted to beside it, half
 * its own: what `sam_build --samples 8` stores, for an engine that wants
 * a lighter frame still. */
#define CUT_FITTED_SAMPLES (SAM_BUILD_CUT_DEFAULT_SAMPLES / 2)

/* The default cut map (its default N) against the flat map (N = 3) on
 * `mesh` (destroyed here) in skin at `mm_per_unit`, side by side (frame_median_ms_side_by_side):
 * sam_runtime_translucency, which runs a cut map's node pass before the
 * translucency pass, on the cut map, on the cut map fitted to its best
 * CUT_FITTED_SAMPLES (sam_runtime_create_fitted) and on the flat map with
 * its rest K cached and evaluated, and an animated frame's whole SAM work on the cut
 * and the flat map (whose posed vertex samples do not use the cache). The cut build
 * stops at `limit_s` (bench_deadline): such a knot is reported with the
 * build's estimate, and larger knots, whose builds take longer still, are
 * not built. A row on stdout, an object in `json`. */
static void cut_study(const frame_config *cfg, const char *label, sam_mesh *mesh, float mm_per_unit, int first,
                      const sam_profile *skin, double limit_s, int timers, cut_summary *sum, FILE *json)
{
    const uint32_t nv = mesh->vertex_count;
    fprintf(json, "%s      {\"mesh\": \"%s\", \"vertices\": %u", first ? "" : ",\n", label, nv);
    if (sum->unbuilt) {
        printf("%9u  not measured: a smaller knot's cut map was not built within the limit or not loaded\n", nv);
        fprintf(json, ", \"skipped\": \"a smaller knot's cut map was not built within the limit or not loaded\"}");
    }
    samfile_data d[2]; /* cut, flat */
    double build_s[2];
    bench_deadline deadline;
    bench_deadline_start(&deadline, limit_s);
    if (!sum->unbuilt) {
        frame_knot_map(mesh, skin, mm_per_unit, SAM_BUILD_MAP_FLAT, NULL, &d[1], &build_s[1]);
        fprintf(json, ", \"flat_build_s\": %.3f", build_s[1]);
        if (!frame_knot_map(mesh, skin, mm_per_unit, SAM_BUILD_MAP_CUT, &deadline, &d[0], &build_s[0])) {
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
        sam_mesh_destroy(mesh);
        return;
    }
    /* A GL may not hold the cut map's samples (llvmpipe: 128 MiB per
     * storage block, passed near 350k vertices at N = 32): said, and the
     * larger knots skipped, rather than the whole study lost. */
    /* cut, flat, flat with its rest K evaluated, the cut fitted */
    sam_runtime *rt[4] = {NULL, NULL, NULL, NULL};
    sam_error err;
    for (int r = 0; r < 4; ++r) {
        const samfile_data *map = &d[r == 1 || r == 2 ? 1 : 0];
        const size_t fitted = r == 3 ? (size_t)nv * 12 * CUT_FITTED_SAMPLES : 0;
        if (sam_runtime_create_fitted(map, skin, mm_per_unit, fitted, &rt[r], &err) != SAM_OK) {
            const char *which = r == 1 || r == 2 ? "flat" : "cut";
            printf("%9u  not measured: the %s map does not load: %s\n", nv, which, err.message);
            fprintf(json, ", \"skipped\": \"the %s map does not load on this GL\"}", which);
            for (int k = 0; k < 4; ++k)
                sam_runtime_destroy(rt[k]);
            for (int k = 0; k < 2; ++k)
                samfile_free(&d[k]);
            skip_knot(sum, nv);
            sam_mesh_destroy(mesh);
            return;
        }
        frame_light_knot(rt[r]);
        if (sam_runtime_rest_k_mode(rt[r]) != (r == 2 ? SAM_REST_K_EVALUATED : SAM_REST_K_CACHED) &&
            sam_runtime_set_rest_k(rt[r], r == 2 ? SAM_REST_K_EVALUATED : SAM_REST_K_CACHED, &err) != SAM_OK)
            frame_die("rest K", &err);
    }
    for (int r = 0; r < 4; ++r)
        if (sam_runtime_irradiance(rt[r], &err) != SAM_OK)
            frame_die("irradiance", &err);
    /* The node pass last: a flat map has none, so its sums take one pass fewer. */
    static const sam_pass passes[5] = {SAM_PASS_DEFORM, SAM_PASS_WALK, SAM_PASS_IRRADIANCE, SAM_PASS_TRANSLUCENCY,
                                       SAM_PASS_NODES};
    void *const no_user[4] = {NULL, NULL, NULL, NULL};
    double tra[4], tra_gpu[4][SAM_PASS_COUNT];
    frame_median_ms_side_by_side(rt, 4, frame_run_translucency, no_user, cfg->pass_runs, passes + 3, 2, tra,
                                 tra_gpu);
    for (int r = 0; r < 2; ++r)
        if (sam_runtime_set_deformers(rt[r], &frame_knot_bend, 1, &err) != SAM_OK)
            frame_die("deformers", &err);
    int frames[2] = {0, 0}; /* both maps see the same poses */
    void *const frame_user[2] = {&frames[0], &frames[1]};
    double ani[2], ani_gpu[2][SAM_PASS_COUNT];
    frame_median_ms_side_by_side(rt, 2, run_animated_frame, frame_user, cfg->pass_runs, passes, 5, ani, ani_gpu);
    double split[2][SPLIT_PASSES];
    animated_frame_split(rt, 2, frames, cfg->pass_runs, split);
    const double ratio[CUT_RATIOS] = {
        tra[0] / tra[2], tra[0] / tra[1], timers ? ratio_or_zero(gpu_sum(tra_gpu[0], 2), gpu_sum(tra_gpu[2], 1)) : 0,
        ani[0] / ani[1], timers ? ratio_or_zero(gpu_sum(ani_gpu[0], 5), gpu_sum(ani_gpu[1], 4)) : 0,
        tra[3] / tra[2]};
    const double filled[2] = {filled_samples(&d[0]), filled_samples(&d[1])};
    printf("%9u %8.1f s %6.1f s %7.2f %7.2f %10.3f ms %10.3f ms %10.3f ms %6.2fx %6.2fx %10.3f ms %6.2fx %10.1f ms "
           "%10.1f ms %6.2fx",
           nv, build_s[0], build_s[1], filled[0], filled[1], tra[0], tra[2], tra[1], ratio[CUT_TRANSLUCENCY],
           ratio[CUT_TRANSLUCENCY_CACHED], tra[3], ratio[CUT_TRANSLUCENCY_FITTED], ani[0], ani[1], ratio[CUT_ANIMATED]);
    if (ratio[CUT_TRANSLUCENCY_GPU] > 0 || ratio[CUT_ANIMATED_GPU] > 0)
        printf("   GPU %.2fx, %.2fx", ratio[CUT_TRANSLUCENCY_GPU], ratio[CUT_ANIMATED_GPU]);
    printf("   %s\n", label);
    printf("%9s  animated frame by pass, cut | flat: deform %.1f | %.1f, walk %.1f | %.1f, irradiance %.1f | %.1f, "
           "node + translucency %.1f | %.1f ms\n",
           "", split[0][SPLIT_DEFORM], split[1][SPLIT_DEFORM], split[0][SPLIT_WALK], split[1][SPLIT_WALK],
           split[0][SPLIT_IRRADIANCE], split[1][SPLIT_IRRADIANCE], split[0][SPLIT_TRANSLUCENCY],
           split[1][SPLIT_TRANSLUCENCY]);
    fprintf(json,
            ", \"cut_build_s\": %.3f, \"cut_samples_per_vertex\": %u, \"cut_nodes\": %u, "
            "\"cut_samples_filled_per_vertex\": %.3f, "
            "\"flat_samples_filled_per_vertex\": %.3f, \"cut_translucency_ms\": %.4f, "
            "\"flat_evaluated_translucency_ms\": %.4f, \"flat_translucency_ms\": %.4f, \"translucency_ratio\": "
            "%.4f, \"translucency_ratio_cached\": %.4f, \"fitted_samples_per_vertex\": %u, "
            "\"fitted_translucency_ms\": %.4f, \"fitted_translucency_ratio\": %.4f, ",
            build_s[0], d[0].samples_per_vertex, d[0].node_count, filled[0], filled[1], tra[0], tra[2], tra[1],
            ratio[CUT_TRANSLUCENCY], ratio[CUT_TRANSLUCENCY_CACHED], sam_runtime_samples_per_vertex(rt[3]), tra[3],
            ratio[CUT_TRANSLUCENCY_FITTED]);
    frame_json_positive(json, "cut_nodes_gpu_ms", timers ? tra_gpu[0][1] : 0);
    fprintf(json, ", ");
    frame_json_positive(json, "cut_translucency_gpu_ms", timers ? tra_gpu[0][0] : 0);
    fprintf(json, ", ");
    frame_json_positive(json, "flat_evaluated_translucency_gpu_ms", timers ? tra_gpu[2][0] : 0);
    fprintf(json, ", ");
    frame_json_positive(json, "translucency_gpu_ratio", ratio[CUT_TRANSLUCENCY_GPU]);
    fprintf(json, ", \"cut_animated_frame_ms\": %.4f, \"flat_animated_frame_ms\": %.4f, \"animated_ratio\": %.4f, ",
            ani[0], ani[1], ratio[CUT_ANIMATED]);
    frame_json_positive(json, "cut_animated_frame_gpu_ms", timers ? gpu_sum(ani_gpu[0], 5) : 0);
    fprintf(json, ", ");
    frame_json_positive(json, "flat_animated_frame_gpu_ms", timers ? gpu_sum(ani_gpu[1], 4) : 0);
    fprintf(json, ", ");
    frame_json_positive(json, "animated_gpu_ratio", ratio[CUT_ANIMATED_GPU]);
    static const char *const split_names[SPLIT_PASSES] = {"deform", "walk", "irradiance", "translucency"};
    for (int r = 0; r < 2; ++r)
        for (int p = 0; p < SPLIT_PASSES; ++p)
            fprintf(json, ", \"%s_animated_%s_ms\": %.4f", r ? "flat" : "cut", split_names[p], split[r][p]);
    fprintf(json, "}");
    for (int k = 0; k < CUT_RATIOS; ++k)
        sum->worst[k] = fmax(sum->worst[k], ratio[k]);
    if (!sum->measured++)
        sum->smallest = nv;
    sum->largest = nv;
    for (int r = 0; r < 4; ++r)
        sam_runtime_destroy(rt[r]);
    for (int r = 0; r < 2; ++r)
        samfile_free(&d[r]);
    sam_mesh_destroy(mesh);
}

/* One ratio's summary line against its target over the meshes of `sum`
 * (`meshes`: what they are, plural), and its JSON fields. */
static void cut_verdict(const cut_summary *sum, const char *meshes, int k, const char *key, const char *what,
                        double target, double limit_s, int quick, FILE *json)
{
    const double worst = sum->worst[k];
    const char *verdict = !(worst > 0) ? "NOT MEASURED" : worst <= target ? "PASS" : "MISS";
    printf("cut against flat N = 3, %s: ", what);
    if (worst > 0)
        printf("worst %.2fx on %s of %u to %u vertices", worst, meshes, sum->smallest, sum->largest);
    else if (sum->measured)
        printf("no GL timer-query times (a CPU rasteriser times submission, not execution)");
    else
        printf("no %s measured", meshes);
    printf("; target <= %.1f: %s", target, verdict);
    if (sum->unbuilt)
        printf(" (not measured at %s vertices: no cut map built within the %g s limit, or loaded by the GL)",
               sum->unbuilt_list, limit_s);
    printf("%s\n", quick ? " [--quick: not a measurement]" : "");
    fprintf(json, ",\n    ");
    frame_json_positive(json, key, worst);
    fprintf(json, ", \"%s_target\": %.1f, \"%s_verdict\": \"%s\"", key, target, key, verdict);
}

/* The five verdict lines of `sum`; JSON keys start with `prefix`. */
static void cut_verdicts(const cut_summary *sum, const char *meshes, const char *prefix, double limit_s, int quick,
                         FILE *json)
{
    static const struct {
        int k;
        const char *key, *what;
    } lines[] = {
        {CUT_TRANSLUCENCY, "translucency_ratio_worst",
         "node + translucency pass / translucency pass with K evaluated per sample (wall)"},
        {CUT_TRANSLUCENCY_CACHED, "translucency_ratio_cached_worst",
         "node + translucency pass / translucency pass with its rest K cached too (wall)"},
        {CUT_TRANSLUCENCY_GPU, "translucency_gpu_ratio_worst",
         "node + translucency pass / translucency pass with K evaluated (GL timer queries)"},
        {CUT_ANIMATED, "animated_ratio_worst",
         "animated frame's deform + walk + irradiance + node + translucency (wall)"},
        {CUT_ANIMATED_GPU, "animated_gpu_ratio_worst",
         "animated frame's deform + walk + irradiance + node + translucency (GL timer queries)"},
        {CUT_TRANSLUCENCY_FITTED, "fitted_translucency_ratio_worst",
         "the cut map fitted to 8 of its 16 (--samples 8): node + translucency pass / "
         "translucency pass with K evaluated per sample (wall)"},
    };
    for (size_t i = 0; i < sizeof lines / sizeof *lines; ++i) {
        char key[96];
        snprintf(key, sizeof key, "%s%s", prefix, lines[i].key);
        const double target =
            lines[i].k == CUT_ANIMATED || lines[i].k == CUT_ANIMATED_GPU ? CUT_ANIMATED_TARGET : CUT_TRANSLUCENCY_TARGET;
        cut_verdict(sum, meshes, lines[i].k, key, lines[i].what, target, limit_s, quick, json);
    }
}

/* The skin scans of the study, at the sizes of their comparison scenes:
 * where a few vertices carry nearly all of a receiver's light, a cut map's
 * row is those vertices (sam_build_cut.c), and on a deforming mesh a
 * vertex sample costs more than a node. */
static const struct {
    const char *file, *label;
    float size_mm;
} cut_scans[] = {{"dragon.off", "dragon scan, skin", 89.7f}, {"head.off", "head scan, skin", 280.0f}};

/* The cut study on every knot of `cfg` and, but with `quick`, on the skin
 * scans found in `scans`, with their summary lines and the
 * "cut_against_flat" JSON object. */
void frame_cut_section(const frame_config *cfg, const sam_profile *skin, const char *scans, double limit_s,
                       int timers, int quick, FILE *json)
{
    sam_build_settings defaults;
    sam_build_default_settings(&defaults);
    const uint32_t cut_n = sam_build_samples(&defaults);
    defaults.map = SAM_BUILD_MAP_FLAT;
    printf("\ncut map (N = %u) against flat map (N = %u), side by side, medians of %d: sam_runtime_translucency "
           "(cut: node + translucency pass; the flat map's rest K evaluated per sample as the paper does, and "
           "cached as both maps do by default) and an animated frame (deform, walk, irradiance, node, "
           "translucency)\n",
           cut_n, sam_build_samples(&defaults), cfg->pass_runs);
    printf("%9s %10s %8s %15s %13s %13s %13s %7s %7s %13s %7s %13s %13s %7s\n", "vertices", "cut build", "flat",
           "filled cut/flat", "cut transl.", "flat eval.", "flat cached", "/eval.", "/cached", "fit to 8", "/eval.",
           "cut frame", "flat frame", "ratio");
    fprintf(json, "  \"cut_against_flat\": {\n    \"build_limit_s\": %g, \"runs\": %d, \"knots\": [\n", limit_s,
            cfg->pass_runs);
    cut_summary knots, scanned;
    memset(&knots, 0, sizeof knots);
    memset(&scanned, 0, sizeof scanned);
    for (int m = 0; m < cfg->mesh_count; ++m) {
        sam_mesh mesh;
        frame_knot_mesh(cfg->resolutions[m], &mesh);
        cut_study(cfg, "knot", &mesh, 40.0f, m == 0, skin, limit_s, timers, &knots, json);
    }
    fprintf(json, "\n    ],\n    \"scans\": [\n");
    int first = 1;
    for (size_t i = 0; !quick && i < sizeof cut_scans / sizeof *cut_scans; ++i) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", scans, cut_scans[i].file);
        sam_mesh mesh;
        float mm_per_unit;
        if (!frame_scan_mesh(path, cut_scans[i].size_mm, &mesh, &mm_per_unit)) {
            printf("%9s  not measured: no %s (meshes/fetch_scans.sh)   %s\n", "-", path, cut_scans[i].label);
            continue;
        }
        cut_study(cfg, cut_scans[i].label, &mesh, mm_per_unit, first, skin, limit_s, timers, &scanned, json);
        first = 0;
    }
    fprintf(json, "\n    ]");
    cut_verdicts(&knots, "knots", "", limit_s, quick, json);
    if (scanned.measured)
        cut_verdicts(&scanned, "skin scans", "scans_", limit_s, quick, json);
    fprintf(json, "\n  }\n");
}
