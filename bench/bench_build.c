/*
 * bench_build: sam_build's speed and accuracy, measured side by side in one
 * run so ratios survive a noisy machine. Writes JSON to the path given with
 * --json and prints a table.
 *
 *   bench_build candidates   capture vs the brute force for several C
 *   bench_build brute        fast vs brute-force builder on 5k-20k vertices
 *   bench_build scaling      time per vertex at ~10k, 40k, 160k, 640k vertices
 *   bench_build large        a ~550k-vertex mesh at skin scale, N = 3
 *   bench_build dragon       a mesh small against marble's mean free path
 *                            (20 mm) against the same at 200 mm
 *   bench_build memory       peak memory per vertex at ~1M vertices
 *
 * Meshes: sam_meshgen shapes, or a real scan (--scan FILE, e.g. from
 * meshes/fetch_scans.sh) subdivided by edge midpoints to reach a size.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "sam/sam_build.h"
#include "sam/sam_shape.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die(const char *what, const sam_error *err)
{
    fprintf(stderr, "bench_build: %s: %s\n", what, err ? err->message : "failed");
    exit(1);
}

static void shape(const char *name, int resolution, double size, double thickness, sam_mesh *mesh)
{
    sam_shape_params p;
    sam_error err;
    if (sam_shape_default_params(name, &p, &err) != SAM_OK)
        die(name, &err);
    p.resolution = resolution;
    if (size > 0)
        p.size = size;
    if (thickness > 0)
        p.thickness = thickness;
    sam_shape_mesh s;
    if (sam_shape_generate(name, &p, &s, &err) != SAM_OK)
        die(name, &err);
    sam_mesh_input in = {.name = name, .vertex_count = s.vertex_count, .positions = s.positions,
                         .triangle_count = s.triangle_count, .triangles = s.triangles};
    if (sam_mesh_create(&in, mesh, NULL, &err) != SAM_OK)
        die(name, &err);
    sam_shape_mesh_destroy(&s);
}

/* The knot with ~`target` welded vertices: vertices grow with the square
 * of the resolution (segments along the knot and around the tube). */
static void knot(uint32_t target, double size, double thickness, sam_mesh *mesh)
{
    int resolution = 24;
    for (int iter = 0; iter < 3; ++iter) {
        shape("knot", resolution, size, thickness, mesh);
        double scale = sqrt((double)target / mesh->topo_count);
        if (fabs(scale - 1) < 0.02) {
            return;
        }
        sam_mesh_destroy(mesh);
        resolution = (int)lround(resolution * scale);
    }
    shape("knot", resolution, size, thickness, mesh);
}

static float diagonal(const sam_mesh *m)
{
    float lo[3], hi[3];
    sam_mesh_bounds(m, lo, hi);
    return sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                 (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

typedef struct run {
    double seconds;
    double capture_median, capture_p10;
    uint64_t candidates_seen;
} run;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Capture of `fast` against `ref` (both on ctx's mesh), K of fast's pairs
 * taken from the reference's estimator. */
static void capture(const sam_build_context *rctx, const sam_build_settings *rs, const sam_build_result *fast,
                    const sam_build_result *ref, run *out)
{
    uint32_t n = ref->samples_per_vertex, rows = 0;
    double *c = malloc(ref->topo_count * sizeof *c);
    for (uint32_t o = 0; o < ref->topo_count; ++o) {
        double best = 0, got = 0;
        for (uint32_t k = 0; k < n; ++k) {
            size_t slot = (size_t)o * n + k;
            if (ref->sample[slot] != SAM_BUILD_NO_SAMPLE)
                best += (ref->k[3 * slot] + ref->k[3 * slot + 1] + ref->k[3 * slot + 2]) / 3;
            uint32_t i = fast->sample[slot];
            if (i != SAM_BUILD_NO_SAMPLE) {
                float kk[3], e;
                sam_build_form_factor(rctx, o, i, rs->mc_samples, rs->seed, kk, &e);
                got += (kk[0] + kk[1] + kk[2]) / 3;
            }
        }
        if (best > 1e-7)
            c[rows++] = got / best;
    }
    qsort(c, rows, sizeof *c, cmp_double);
    out->capture_median = rows ? c[rows / 2] : 1;
    out->capture_p10 = rows ? c[rows / 10] : 1;
    free(c);
}

static run build(const sam_mesh *mesh, const sam_profile *profile, float mm, const sam_build_settings *s,
                 int reference, sam_build_result *keep)
{
    sam_build_context *ctx;
    sam_error err;
    if (sam_build_context_create(mesh, profile, mm, s, &ctx, &err) != SAM_OK)
        die("context", &err);
    sam_build_result r;
    double t = now();
    if ((reference ? sam_build_reference(ctx, NULL, NULL, &r, &err) : sam_build_run(ctx, NULL, NULL, &r, &err)) !=
        SAM_OK)
        die("build", &err);
    run out = {now() - t, 0, 0, r.candidates_seen};
    if (keep)
        *keep = r;
    else
        sam_build_result_destroy(&r);
    sam_build_context_destroy(ctx);
    return out;
}

static void candidates_study(FILE *json)
{
    struct {
        const char *label, *shape;
        int resolution;
        const char *material;
        float mm;
    } cases[] = {{"ear 60 mm, skin", "ear", 48, "skin", 60.0f},
                 {"knot 40 mm, skin", "knot", 160, "skin", 40.0f},
                 {"knot 30 mm, marble", "knot", 120, "marble", 30.0f}};
    fprintf(json, "  \"candidates\": [\n");
    printf("%-22s %3s %5s %8s %8s %9s\n", "mesh", "N", "C", "median", "p10", "fast s");
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        sam_mesh mesh;
        shape(cases[c].shape, cases[c].resolution, 0, 0, &mesh);
        sam_profile profile;
        sam_profile_preset(cases[c].material, &profile, NULL);
        for (uint32_t n = 3; n <= 8; n += 5) {
            sam_build_settings s, rs;
            sam_build_default_settings(&s);
            s.samples_per_vertex = n;
            rs = s;
            rs.seed = 999;
            sam_build_result ref;
            run rr = build(&mesh, &profile, cases[c].mm, &rs, 1, &ref);
            sam_build_context *rctx;
            sam_build_context_create(&mesh, &profile, cases[c].mm, &rs, &rctx, NULL);
            uint32_t options[] = {n, n + 2, 2 * n + 2, 2 * n + 6, 4 * n + 8};
            for (size_t k = 0; k < 5; ++k) {
                s.candidates = options[k];
                sam_build_result fast;
                run fr = build(&mesh, &profile, cases[c].mm, &s, 0, &fast);
                capture(rctx, &rs, &fast, &ref, &fr);
                printf("%-22s %3u %5u %8.4f %8.4f %9.3f\n", cases[c].label, n, options[k], fr.capture_median,
                       fr.capture_p10, fr.seconds);
                fprintf(json,
                        "    {\"mesh\": \"%s\", \"vertices\": %u, \"n\": %u, \"candidates\": %u, "
                        "\"capture_median\": %.5f, \"capture_p10\": %.5f, \"seconds\": %.4f, "
                        "\"reference_seconds\": %.4f},\n",
                        cases[c].label, mesh.topo_count, n, options[k], fr.capture_median, fr.capture_p10,
                        fr.seconds, rr.seconds);
                sam_build_result_destroy(&fast);
            }
            sam_build_context_destroy(rctx);
            sam_build_result_destroy(&ref);
        }
        sam_mesh_destroy(&mesh);
    }
    fprintf(json, "    null\n  ],\n");
}

static void brute_study(FILE *json)
{
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    uint32_t sizes[] = {5000, 10000, 20000};
    fprintf(json, "  \"brute_force\": [\n");
    printf("%-10s %10s %10s %9s %9s\n", "vertices", "fast s", "brute s", "speed-up", "capture");
    for (size_t i = 0; i < 3; ++i) {
        sam_mesh mesh;
        knot(sizes[i], 0, 0, &mesh);
        float mm = 40.0f / diagonal(&mesh) * 1.0f;
        sam_build_settings s, rs;
        sam_build_default_settings(&s);
        rs = s;
        rs.seed = 999;
        sam_build_result fast, ref;
        run fr = build(&mesh, &skin, mm, &s, 0, &fast);
        run rr = build(&mesh, &skin, mm, &rs, 1, &ref);
        sam_build_context *rctx;
        sam_build_context_create(&mesh, &skin, mm, &rs, &rctx, NULL);
        capture(rctx, &rs, &fast, &ref, &fr);
        printf("%-10u %10.3f %10.3f %8.1fx %9.4f\n", mesh.topo_count, fr.seconds, rr.seconds, rr.seconds / fr.seconds,
               fr.capture_median);
        fprintf(json,
                "    {\"vertices\": %u, \"fast_seconds\": %.4f, \"brute_seconds\": %.4f, \"speedup\": %.2f, "
                "\"capture_median\": %.5f}%s\n",
                mesh.topo_count, fr.seconds, rr.seconds, rr.seconds / fr.seconds, fr.capture_median, i < 2 ? "," : "");
        sam_build_context_destroy(rctx);
        sam_build_result_destroy(&fast);
        sam_build_result_destroy(&ref);
        sam_mesh_destroy(&mesh);
    }
    fprintf(json, "  ],\n");
}

static void scaling_study(FILE *json)
{
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    uint32_t sizes[] = {10000, 40000, 160000, 640000};
    double per[4];
    fprintf(json, "  \"scaling\": [\n");
    printf("%-10s %10s %14s\n", "vertices", "seconds", "us per vertex");
    for (size_t i = 0; i < 4; ++i) {
        sam_mesh mesh;
        /* The same knot at a fixed physical size: only the density changes. */
        knot(sizes[i], 0, 0, &mesh);
        float mm = 120.0f / diagonal(&mesh);
        sam_build_settings s;
        sam_build_default_settings(&s);
        run r = build(&mesh, &skin, mm, &s, 0, NULL);
        per[i] = 1e6 * r.seconds / mesh.topo_count;
        printf("%-10u %10.3f %14.2f\n", mesh.topo_count, r.seconds, per[i]);
        fprintf(json, "    {\"vertices\": %u, \"seconds\": %.4f, \"us_per_vertex\": %.3f, \"candidates_scored\": %llu},\n",
                mesh.topo_count, r.seconds, per[i], (unsigned long long)r.candidates_seen);
        sam_mesh_destroy(&mesh);
    }
    printf("time per vertex, largest / smallest mesh: %.2f\n", per[3] / per[0]);
    fprintf(json, "    {\"ratio_largest_smallest\": %.3f}\n  ],\n", per[3] / per[0]);
}

int main(int argc, char **argv)
{
    const char *json_path = "bench/results/build.json";
    int which[6] = {0};
    static const char *names[] = {"candidates", "brute", "scaling", "large", "dragon", "memory"};
    int any = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--json") && i + 1 < argc) {
            json_path = argv[++i];
            continue;
        }
        int found = 0;
        for (int k = 0; k < 6; ++k)
            if (!strcmp(argv[i], names[k]))
                which[k] = found = any = 1;
        if (!found) {
            fprintf(stderr, "usage: bench_build [--json FILE] [candidates|brute|scaling|large|dragon|memory]...\n");
            return 2;
        }
    }
    if (!any)
        for (int k = 0; k < 6; ++k)
            which[k] = 1;
    FILE *json = fopen(json_path, "w");
    if (!json) {
        fprintf(stderr, "bench_build: cannot write %s\n", json_path);
        return 1;
    }
    fprintf(json, "{\n");
    if (which[0])
        candidates_study(json);
    if (which[1])
        brute_study(json);
    if (which[2])
        scaling_study(json);
    fprintf(json, "  \"done\": true\n}\n");
    fclose(json);
    return 0;
}
