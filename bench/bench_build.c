/*
 * bench_build: sam_build's speed and accuracy, measured side by side in one
 * run so ratios survive a noisy machine. Writes JSON to the path given with
 * --json and prints a table.
 *
 *   bench_build candidates   capture vs the brute force for several C
 *   bench_build brute        fast vs brute-force builder on 2.5k-10k vertices
 *   bench_build scaling      time per vertex at ~10k, 40k, 160k, 640k vertices
 *   bench_build large        a ~550k-vertex mesh at skin scale, N = 3
 *   bench_build dragon       a mesh small against marble's mean free path
 *                            (20 mm) against the same at 200 mm
 *   bench_build cut          the default cut map's build time against the flat
 *                            N = 3 map's on 10k-550k-vertex knots (target <= 1.5)
 *   bench_build memory       sam_build's peak memory per vertex at ~1M vertices,
 *                            cut and flat map (target < 1 KB for the cut)
 *
 * Meshes: sam_shape knots, and real scans from meshes/fetch_scans.sh
 * (--scans DIR, default meshes/scans), subdivided by edge midpoints where a
 * size is needed. --quick shrinks brute, scaling, cut and memory to a few
 * thousand vertices (seconds instead of minutes: scripts/bench.sh --quick).
 * Cut builds stop at --cut-limit seconds: their time grows faster than the
 * vertex count, and the large knots' would take hours.
 */
#define _DEFAULT_SOURCE /* POSIX 2008, and wait4 */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "sam/sam_args.h"
#include "sam/sam_build.h"
#include "sam/sam_shape.h"
#include "bench_util.h"

static void die(const char *what, const sam_error *err)
{
    bench_die("bench_build", what, err);
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

typedef struct run {
    double seconds;
    double capture_median, capture_p10;
    uint64_t candidates_seen;
    int cancelled;           /* build_limited's limit stopped the build */
    bench_deadline deadline; /* how far it got, when it did */
} run;

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
    qsort(c, rows, sizeof *c, bench_cmp_double);
    out->capture_median = rows ? c[rows / 2] : 1;
    out->capture_p10 = rows ? c[rows / 10] : 1;
    free(c);
}

/* A build of `s`'s map (the O(m^2) reference with `reference`) timed alone,
 * context excluded; stopped after limit_s seconds (0: no limit; then
 * `cancelled` and `deadline` say how far it got). The result goes to
 * `keep` (may be NULL; not on a stopped build). */
static run build_limited(const sam_mesh *mesh, const sam_profile *profile, float mm, const sam_build_settings *s,
                         int reference, double limit_s, sam_build_result *keep)
{
    sam_build_context *ctx;
    sam_error err;
    if (sam_build_context_create(mesh, profile, mm, s, &ctx, &err) != SAM_OK)
        die("context", &err);
    sam_build_result r;
    run out = {0};
    bench_deadline_start(&out.deadline, limit_s);
    sam_build_progress_fn progress = limit_s > 0 ? bench_deadline_progress : NULL;
    double t = sam_seconds();
    sam_status st = reference ? sam_build_reference(ctx, progress, &out.deadline, &r, &err)
                              : sam_build_run(ctx, progress, &out.deadline, &r, &err);
    out.seconds = sam_seconds() - t;
    if (st != SAM_OK && !out.deadline.cancelled)
        die("build", &err);
    out.cancelled = st != SAM_OK;
    if (st == SAM_OK) {
        out.candidates_seen = r.candidates_seen;
        if (keep)
            *keep = r;
        else
            sam_build_result_destroy(&r);
    }
    sam_build_context_destroy(ctx);
    return out;
}

static run build(const sam_mesh *mesh, const sam_profile *profile, float mm, const sam_build_settings *s,
                 int reference, sam_build_result *keep)
{
    return build_limited(mesh, profile, mm, s, reference, 0, keep);
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
        s.map = SAM_BUILD_MAP_FLAT;
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

static void brute_study(FILE *json, int quick)
{
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    /* The brute force is O(m^2): 10k vertices take a minute, 20k four. */
    uint32_t sizes[3] = {2500, 5000, 10000};
    if (quick)
        sizes[0] = 400, sizes[1] = 800, sizes[2] = 1600;
    fprintf(json, "  \"brute_force\": [\n");
    printf("%-10s %10s %10s %9s %9s\n", "vertices", "fast s", "brute s", "speed-up", "capture");
    for (size_t i = 0; i < 3; ++i) {
        sam_mesh mesh;
        knot(sizes[i], 0, 0, &mesh);
        float mm = 40.0f / (float)sam_mesh_diagonal(&mesh);
        sam_build_settings s, rs;
        sam_build_default_settings(&s);
        s.map = SAM_BUILD_MAP_FLAT;
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

static void scaling_study(FILE *json, int quick)
{
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    uint32_t sizes[4] = {10000, 40000, 160000, 640000};
    if (quick)
        sizes[0] = 2500, sizes[1] = 5000, sizes[2] = 10000, sizes[3] = 20000;
    double per[4];
    fprintf(json, "  \"scaling\": [\n");
    printf("%-10s %10s %14s\n", "vertices", "seconds", "us per vertex");
    for (size_t i = 0; i < 4; ++i) {
        sam_mesh mesh;
        /* The same knot at a fixed physical size: only the density changes. */
        knot(sizes[i], 0, 0, &mesh);
        float mm = 120.0f / (float)sam_mesh_diagonal(&mesh);
        sam_build_settings s;
        sam_build_default_settings(&s);
        s.map = SAM_BUILD_MAP_FLAT;
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

/* Splits every triangle into four at its edge midpoints (each midpoint
 * shared by the two triangles of its edge). Replaces `mesh`. */
typedef struct edge_key {
    uint32_t a, b, slot; /* slot = 3 * triangle + corner of the edge's start */
} edge_key;

static int cmp_edge(const void *pa, const void *pb)
{
    const edge_key *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return (x->slot > y->slot) - (x->slot < y->slot);
}

static void subdivide(sam_mesh *mesh)
{
    uint32_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    edge_key *e = malloc((size_t)nt * 3 * sizeof *e);
    for (uint32_t t = 0; t < nt; ++t)
        for (int c = 0; c < 3; ++c) {
            uint32_t a = mesh->triangles[3 * t + c], b = mesh->triangles[3 * t + (c + 1) % 3];
            e[3 * t + c] = (edge_key){a < b ? a : b, a < b ? b : a, 3 * t + c};
        }
    qsort(e, (size_t)nt * 3, sizeof *e, cmp_edge);
    uint32_t *mid = malloc((size_t)nt * 3 * sizeof *mid);
    float *pos = malloc(((size_t)nv + 3 * (size_t)nt) * 3 * sizeof *pos);
    memcpy(pos, mesh->positions, (size_t)nv * 3 * sizeof *pos);
    uint32_t next = nv;
    for (size_t i = 0; i < (size_t)nt * 3; ++i) {
        if (i == 0 || e[i].a != e[i - 1].a || e[i].b != e[i - 1].b) {
            for (int c = 0; c < 3; ++c)
                pos[3 * (size_t)next + c] = 0.5f * (pos[3 * (size_t)e[i].a + c] + pos[3 * (size_t)e[i].b + c]);
            next++;
        }
        mid[e[i].slot] = next - 1;
    }
    uint32_t *tri = malloc((size_t)nt * 12 * sizeof *tri);
    for (uint32_t t = 0; t < nt; ++t) {
        const uint32_t *v = mesh->triangles + 3 * t, *m = mid + 3 * t;
        uint32_t sub[12] = {v[0], m[0], m[2], m[0], v[1], m[1], m[2], m[1], v[2], m[0], m[1], m[2]};
        memcpy(tri + 12 * (size_t)t, sub, sizeof sub);
    }
    sam_mesh_input in = {.name = "subdivided", .vertex_count = next, .positions = pos, .triangle_count = 4 * nt,
                         .triangles = tri};
    sam_mesh out;
    sam_error err;
    if (sam_mesh_create(&in, &out, NULL, &err) != SAM_OK)
        die("subdivide", &err);
    sam_mesh_destroy(mesh);
    *mesh = out;
    free(e);
    free(mid);
    free(pos);
    free(tri);
}

static void load_scan(const char *dir, const char *name, sam_mesh *mesh)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    sam_error err;
    if (sam_mesh_load(path, mesh, NULL, &err) != SAM_OK) {
        fprintf(stderr, "bench_build: %s (run meshes/fetch_scans.sh first)\n", err.message);
        exit(1);
    }
}

static void large_study(FILE *json, const char *scans)
{
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    fprintf(json, "  \"large\": [\n");
    printf("%-40s %9s %9s %12s\n", "mesh", "vertices", "seconds", "vs 20.16 min");
    for (int which = 0; which < 2; ++which) {
        sam_mesh mesh;
        const char *label;
        float mm;
        if (which == 0) {
            /* A knot the size of a finger-thick loop: every vertex has a back side in reach. */
            knot(550000, 0, 0, &mesh);
            mm = 40.0f;
            label = "knot, 40 mm, tube 7 mm, skin";
        } else {
            label = "bunny scan x16 (midpoints), 150 mm, skin";
            char path[1024];
            snprintf(path, sizeof path, "%s/bunny.off", scans);
            /* The scan comes from the network: without it the knot still
             * answers the study's question, so say so rather than fail. */
            if (access(path, R_OK) != 0) {
                printf("%-40s skipped: no %s (meshes/fetch_scans.sh)\n", label, path);
                fprintf(json, "    {\"mesh\": \"%s\", \"skipped\": \"no %s (meshes/fetch_scans.sh)\"}\n", label,
                        path);
                break;
            }
            load_scan(scans, "bunny.off", &mesh);
            subdivide(&mesh);
            subdivide(&mesh);
            mm = 150.0f / (float)sam_mesh_diagonal(&mesh);
        }
        sam_build_settings s;
        sam_build_default_settings(&s);
        s.map = SAM_BUILD_MAP_FLAT;
        run r = build(&mesh, &skin, mm, &s, 0, NULL);
        printf("%-40s %9u %9.2f %11.0fx\n", label, mesh.topo_count, r.seconds, 20.16 * 60 / r.seconds);
        fprintf(json, "    {\"mesh\": \"%s\", \"vertices\": %u, \"seconds\": %.3f, \"speedup_vs_paper\": %.1f}%s\n",
                label, mesh.topo_count, r.seconds, 20.16 * 60 / r.seconds, which ? "" : ",");
        sam_mesh_destroy(&mesh);
    }
    fprintf(json, "  ],\n");
}

static void dragon_study(FILE *json, const char *scans)
{
    sam_profile marble;
    sam_profile_preset("marble", &marble, NULL);
    sam_mesh mesh;
    load_scan(scans, "dragon.off", &mesh);
    double t[2];
    float sizes[2] = {20.0f, 200.0f};
    for (int i = 0; i < 2; ++i) {
        sam_build_settings s;
        sam_build_default_settings(&s);
        s.map = SAM_BUILD_MAP_FLAT;
        run r = build(&mesh, &marble, sizes[i] / (float)sam_mesh_diagonal(&mesh), &s, 0, NULL);
        t[i] = r.seconds;
        printf("dragon %u vertices, marble, %3.0f mm: %.3f s, %llu candidates scored\n", mesh.topo_count, sizes[i],
               r.seconds, (unsigned long long)r.candidates_seen);
    }
    printf("dragon: 20 mm takes %.2fx the time of 200 mm\n", t[0] / t[1]);
    fprintf(json, "  \"dragon\": {\"vertices\": %u, \"seconds_20mm\": %.4f, \"seconds_200mm\": %.4f, \"ratio\": %.3f},\n",
            mesh.topo_count, t[0], t[1], t[0] / t[1]);
    sam_mesh_destroy(&mesh);
}

/* The cut map's cost targets against the flat map (N = 3), as ratios. */
#define CUT_BUILD_TARGET 1.5     /* cut build time / flat build time */
#define CUT_MEMORY_TARGET 1024.0 /* sam_build's peak bytes per vertex, below */
/* Default limit on one cut build or sam_build run (--cut-limit): the cut
 * build took 90 s on an 18k-vertex knot on 2 cores and grows faster than
 * the vertex count, so the larger knots' would take hours. */
#define CUT_LIMIT_S 300.0
#define CUT_LIMIT_QUICK_S 30.0

/* The default cut map (its default N) against the flat map (N = 3) on the same
 * knots at 40 mm in skin (the large study's knot, and bench_frame's), the
 * builds in A B, B A order so a drift of the machine's load falls on both
 * alike. A cut build that passes limit_s is stopped, not repeated, and
 * reported with its estimate; its ratio is then a lower bound. */
static void cut_study(FILE *json, int quick, double limit_s)
{
    sam_profile skin;
    sam_profile_preset("skin", &skin, NULL);
    static const uint32_t full_sizes[] = {10000, 40000, 160000, 550000}, quick_sizes[] = {1000, 2500};
    const uint32_t *sizes = quick ? quick_sizes : full_sizes;
    const int count = quick ? 2 : 4, runs = quick ? 1 : 2;
    sam_build_settings s[2]; /* cut, flat */
    for (int k = 0; k < 2; ++k) {
        sam_build_default_settings(&s[k]);
        s[k].map = k ? SAM_BUILD_MAP_FLAT : SAM_BUILD_MAP_CUT;
    }
    printf("\ncut map (N = %u) against flat map (N = %u), knot at 40 mm in skin, %s of %d build%s each, limit %g s:\n",
           sam_build_samples(&s[0]), sam_build_samples(&s[1]), runs > 1 ? "means" : "times", runs, runs > 1 ? "s" : "",
           limit_s);
    printf("%-10s %10s %10s %9s\n", "vertices", "cut s", "flat s", "cut/flat");
    fprintf(json, "  \"cut_build\": {\"cut_samples_per_vertex\": %u, \"limit_s\": %g, \"runs\": %d, \"knots\": [\n",
            sam_build_samples(&s[0]), limit_s, runs);
    double worst = 0;
    int worst_bound = 0, bounds = 0; /* the worst is a stopped build's lower bound; any such */
    uint32_t smallest = 0, largest = 0;
    for (int i = 0; i < count; ++i) {
        sam_mesh mesh;
        knot(sizes[i], 0, 0, &mesh);
        double t[2][2];
        int done[2] = {0, 0};
        run stopped = {0};
        for (int round = 0; round < runs; ++round)
            for (int j = 0; j < 2; ++j) {
                const int k = round % 2 ? 1 - j : j;
                if (k == 0 && stopped.cancelled)
                    continue; /* a stopped cut build would only stop again */
                run r = build_limited(&mesh, &skin, 40.0f, &s[k], 0, k ? 0 : limit_s, NULL);
                if (r.cancelled)
                    stopped = r;
                else
                    t[k][done[k]++] = r.seconds;
            }
        const double flat = bench_median(t[1], done[1]);
        const double cut = stopped.cancelled ? stopped.deadline.elapsed_s : bench_median(t[0], done[0]);
        const double ratio = cut / flat;
        fprintf(json, "    {\"vertices\": %u, \"welded\": %u, \"flat_seconds\": %.4f, ", mesh.vertex_count,
                mesh.topo_count, flat);
        if (stopped.cancelled) {
            char how[128];
            bench_deadline_describe(&stopped.deadline, how, sizeof how);
            double estimate = bench_deadline_estimate(&stopped.deadline);
            printf("%-10u %10s %10.3f %4s%.2fx  cut build %s", mesh.vertex_count, "stopped", flat, ">= ", ratio, how);
            if (estimate > 0)
                printf(", %.0fx the flat build", estimate / flat);
            printf("\n");
            bench_deadline_json(json, "cut", &stopped.deadline);
            fprintf(json, ", \"ratio_at_least\": %.3f", ratio);
            if (estimate > 0)
                fprintf(json, ", \"ratio_estimate\": %.3f", estimate / flat);
            bounds++;
        } else {
            printf("%-10u %10.3f %10.3f %8.2fx\n", mesh.vertex_count, cut, flat, ratio);
            fprintf(json, "\"cut_seconds\": %.4f, \"ratio\": %.4f", cut, ratio);
        }
        fprintf(json, "}%s\n", i < count - 1 ? "," : "");
        if (ratio > worst)
            worst = ratio, worst_bound = stopped.cancelled;
        if (!smallest)
            smallest = mesh.vertex_count;
        largest = mesh.vertex_count;
        sam_mesh_destroy(&mesh);
    }
    /* A stopped build's ratio is a lower bound: it proves a miss, never a pass. */
    const char *verdict = worst > CUT_BUILD_TARGET ? "MISS" : bounds ? "NOT MEASURED" : "PASS";
    printf("cut against flat N = 3, build time cut / flat: worst %s%.2fx on knots of %u to %u vertices; "
           "target <= %.1f: %s%s\n",
           worst_bound ? ">= " : "", worst, smallest, largest, CUT_BUILD_TARGET, verdict,
           quick ? " [--quick: not a measurement]" : "");
    fprintf(json,
            "  ], \"ratio_worst\": %.4f, \"ratio_worst_is_lower_bound\": %s, \"target\": %.1f, \"verdict\": \"%s\"},\n",
            worst, worst_bound ? "true" : "false", CUT_BUILD_TARGET, verdict);
}

/* Runs argv (argv[0] a path) as a child and waits for it, stopping it with
 * SIGTERM after limit_s seconds (0: never), and SIGKILL 10 s later:
 * sam_build cancels at its next progress report, every 0.5% of the
 * vertices, which on a large cut build may be hours away. Its own peak resident memory
 * comes from wait4: getrusage(RUSAGE_CHILDREN) would give the largest of
 * every child so far. A child's reading is never below this process's
 * peak at the fork (Linux carries the parent's high-water mark across fork
 * and exec), so the caller forks while small. Returns the exit status, or
 * -1 when the limit stopped it. */
static int run_child(char *const argv[], double limit_s, long *peak_kib, double *seconds)
{
    double start = sam_seconds();
    pid_t pid = fork();
    if (pid == 0) {
        execv(argv[0], argv);
        _exit(127);
    }
    if (pid < 0)
        die(argv[0], NULL);
    int status, stopped = 0;
    struct rusage ru;
    for (;;) {
        pid_t got = wait4(pid, &status, WNOHANG, &ru);
        if (got == pid)
            break;
        if (got < 0)
            die(argv[0], NULL);
        const double elapsed = sam_seconds() - start;
        if (limit_s > 0 && stopped < 2 && elapsed > limit_s + (stopped ? 10 : 0))
            stopped += kill(pid, stopped ? SIGKILL : SIGTERM) == 0;
        nanosleep(&(struct timespec){0, 50000000}, NULL);
    }
    *seconds = sam_seconds() - start;
    *peak_kib = ru.ru_maxrss;
    if (WIFEXITED(status) && (WEXITSTATUS(status) == 0 || !stopped))
        return WEXITSTATUS(status); /* it may have ended just before the signal */
    return stopped ? -1 : 128 + WTERMSIG(status);
}

/* Peak resident memory of the whole sam_build program (load, build,
 * assemble, write), per vertex, for the cut and the flat map, on a knot of
 * ~1M vertices (~1.7k with --quick) that sam_meshgen writes to a temporary
 * PLY. Runs before the other studies, while this process is small (see
 * run_child); a sam_build run that passes limit_s is stopped, and its peak
 * so far is a lower bound. */
static void memory_study(FILE *json, const char *bin_dir, int quick, double limit_s)
{
    struct rusage self;
    getrusage(RUSAGE_SELF, &self);
    char dir[] = "/tmp/bench_build_XXXXXX";
    if (!mkdtemp(dir))
        die("temporary folder", NULL);
    char meshgen[1100], sam_build[1100], mesh_path[64], out_path[64], resolution[16];
    snprintf(meshgen, sizeof meshgen, "%s/sam_meshgen", bin_dir);
    snprintf(sam_build, sizeof sam_build, "%s/sam_build", bin_dir);
    snprintf(mesh_path, sizeof mesh_path, "%s/knot.ply", dir);
    snprintf(out_path, sizeof out_path, "%s/knot.sam", dir);
    /* The knot's 3000 segments make 961k vertices (120 make 1.7k). */
    snprintf(resolution, sizeof resolution, "%d", quick ? 120 : 3000);
    long peak[2];
    double seconds[2];
    int status[2];
    char *gen[] = {meshgen, "knot", "-o", mesh_path, "--resolution", resolution, NULL};
    if (run_child(gen, 0, &peak[0], &seconds[0]) != 0) {
        fprintf(stderr, "bench_build: %s failed\n", meshgen);
        exit(1);
    }
    for (int k = 0; k < 2; ++k) { /* cut, flat */
        char *argv[] = {sam_build, mesh_path, "-o", out_path, "--material", "skin", "--mm-per-unit", "40", "--force",
                        "--quiet", k ? "--flat" : NULL, NULL};
        status[k] = run_child(argv, limit_s, &peak[k], &seconds[k]);
        if (status[k] > 0) {
            fprintf(stderr, "bench_build: %s failed (exit %d)\n", sam_build, status[k]);
            exit(1);
        }
    }
    sam_mesh mesh;
    sam_error err;
    if (sam_mesh_load(mesh_path, &mesh, NULL, &err) != SAM_OK)
        die(mesh_path, &err);
    const uint32_t vertices = mesh.vertex_count, welded = mesh.topo_count;
    sam_mesh_destroy(&mesh);
    remove(mesh_path);
    remove(out_path);
    rmdir(dir);
    printf("\nsam_build's peak memory, knot of %u vertices (%u welded), skin, 40 mm; this process's own peak %.0f "
           "MiB at the forks:\n",
           vertices, welded, self.ru_maxrss / 1024.0);
    sam_build_settings cut;
    sam_build_default_settings(&cut);
    fprintf(json, "  \"memory\": {\"vertices\": %u, \"welded\": %u, \"cut_samples_per_vertex\": %u, "
                  "\"bench_peak_mib\": %.1f",
            vertices, welded, sam_build_samples(&cut), self.ru_maxrss / 1024.0);
    double per[2];
    for (int k = 0; k < 2; ++k) {
        const char *name = k ? "flat" : "cut";
        per[k] = (double)peak[k] * 1024.0 / vertices;
        printf("  %-4s map: peak %s%.0f MiB, %s%.0f bytes per vertex, %.1f s%s\n", name, status[k] ? ">= " : "",
               peak[k] / 1024.0, status[k] ? ">= " : "", per[k], seconds[k],
               status[k] ? " (stopped at the limit: the peak so far)" : "");
        fprintf(json, ", \"%s_peak_mib\": %.1f, \"%s_bytes_per_vertex\": %.1f, \"%s_seconds\": %.2f, \"%s_stopped\": %s",
                name, peak[k] / 1024.0, name, per[k], name, seconds[k], name, status[k] ? "true" : "false");
    }
    /* A stopped run's peak is a lower bound: it proves a miss, never a pass. */
    const char *verdict = per[0] >= CUT_MEMORY_TARGET ? "MISS" : status[0] ? "NOT MEASURED" : "PASS";
    printf("cut against flat N = 3, sam_build's peak memory per vertex at %u vertices: cut %s%.0f B (flat %.0f B); "
           "target < %.0f B: %s%s\n",
           vertices, status[0] ? ">= " : "", per[0], per[1], CUT_MEMORY_TARGET, verdict,
           quick ? " [--quick: not a measurement]" : "");
    fprintf(json, ", \"target_bytes_per_vertex\": %.0f, \"verdict\": \"%s\"},\n", CUT_MEMORY_TARGET, verdict);
}

static void usage(FILE *out)
{
    fprintf(out, "usage: bench_build [--quick] [--json FILE] [--scans DIR] [--cut-limit SECONDS] [STUDY...]\n"
                 "\n"
                 "Times the builder; STUDY is candidates, brute, scaling, large, dragon, cut or memory (default:\n"
                 "all). cut and memory set the default cut map against the flat N = 3 map (build time, sam_build's\n"
                 "peak memory) and print PASS or MISS against their targets; --cut-limit stops a cut build after\n"
                 "this long, 0 for no limit (default 300; 30 with --quick). Writes FILE (default\n"
                 "bench/results/build.json); --scans finds the real scans (meshes/fetch_scans.sh).\n"
                 "scripts/bench.sh runs it with the other benchmarks.\n"
                 "\n"
                 "examples:\n"
                 "  bench_build --quick scaling\n"
                 "  bench_build brute candidates --json /tmp/build.json\n"
                 "  bench_build cut memory --json /tmp/build_cut.json\n");
}

int main(int argc, char **argv)
{
    const char *json_path = "bench/results/build.json", *scans = "meshes/scans";
    enum { STUDIES = 7 };
    int which[STUDIES] = {0}, quick = 0;
    double cut_limit = -1;
    static const char *names[STUDIES] = {"candidates", "brute", "scaling", "large", "dragon", "cut", "memory"};
    const char *studies[STUDIES] = {0};
    const sam_arg args[] = {
        {"--quick", SAM_ARG_FLAG, .target = &quick},
        {"--json", SAM_ARG_STRING, &json_path, .value = "FILE"},
        {"--scans", SAM_ARG_STRING, &scans, .value = "DIR"},
        {"--cut-limit", SAM_ARG_DOUBLE, &cut_limit, .lo = 0, .hi = 1e6, .value = "SECONDS"},
    };
    const sam_args_spec spec = {"bench_build", args, sizeof args / sizeof *args, studies, 0, STUDIES, "STUDY", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    int any = 0;
    for (int i = 0; i < STUDIES && studies[i]; ++i) {
        int found = 0;
        for (int k = 0; k < STUDIES; ++k)
            if (!strcmp(studies[i], names[k]))
                which[k] = found = any = 1;
        if (!found)
            return sam_args_fail("bench_build", "unknown study \"%s\" (candidates, brute, scaling, large, dragon, cut "
                                                "or memory)", studies[i]);
    }
    if (!any)
        for (int k = 0; k < STUDIES; ++k)
            which[k] = 1;
    if (cut_limit < 0)
        cut_limit = quick ? CUT_LIMIT_QUICK_S : CUT_LIMIT_S;
    sam_atomic_file out;
    bench_json_open("bench_build", json_path, &out);
    FILE *json = out.fp;
    fprintf(json, "{\n  \"quick\": %s,\n", quick ? "true" : "false");
    /* First, while this process is small: memory_study's children inherit
     * its peak (run_child). */
    if (which[6]) {
        char dir[1024];
        snprintf(dir, sizeof dir, "%s", argv[0]);
        char *slash = strrchr(dir, '/');
        if (slash)
            *slash = 0;
        else
            snprintf(dir, sizeof dir, ".");
        memory_study(json, dir, quick, cut_limit);
    }
    if (which[0])
        candidates_study(json);
    if (which[1])
        brute_study(json, quick);
    if (which[2])
        scaling_study(json, quick);
    if (which[3])
        large_study(json, scans);
    if (which[4])
        dragon_study(json, scans);
    if (which[5])
        cut_study(json, quick, cut_limit);
    fprintf(json, "  \"done\": true\n}\n");
    bench_json_commit("bench_build", &out);
    return 0;
}
