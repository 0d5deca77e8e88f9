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
 *   bench_build memory       peak memory per vertex at ~1M vertices
 *
 * Meshes: sam_shape knots, and real scans from meshes/fetch_scans.sh
 * (--scans DIR, default meshes/scans), subdivided by edge midpoints where a
 * size is needed. --quick shrinks brute and scaling to a few thousand
 * vertices (seconds instead of minutes: scripts/bench.sh --quick).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
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

static run build(const sam_mesh *mesh, const sam_profile *profile, float mm, const sam_build_settings *s,
                 int reference, sam_build_result *keep)
{
    sam_build_context *ctx;
    sam_error err;
    if (sam_build_context_create(mesh, profile, mm, s, &ctx, &err) != SAM_OK)
        die("context", &err);
    sam_build_result r;
    double t = sam_seconds();
    if ((reference ? sam_build_reference(ctx, NULL, NULL, &r, &err) : sam_build_run(ctx, NULL, NULL, &r, &err)) !=
        SAM_OK)
        die("build", &err);
    run out = {sam_seconds() - t, 0, 0, r.candidates_seen};
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

/* Peak resident memory of the whole sam_build program (load, build,
 * assemble, write) on a ~1M-vertex knot, read from the child's rusage. */
static void memory_study(FILE *json, const char *bin_dir)
{
    sam_shape_params p;
    sam_shape_default_params("knot", &p, NULL);
    p.resolution = 3000;
    sam_shape_mesh s;
    sam_error err;
    if (sam_shape_generate("knot", &p, &s, &err) != SAM_OK)
        die("knot", &err);
    char mesh_path[] = "/tmp/bench_build_1m.ply", out_path[] = "/tmp/bench_build_1m.sam";
    if (sam_shape_write_ply(mesh_path, &s, 1, &err) != SAM_OK)
        die("write", &err);
    uint32_t vertices = s.vertex_count;
    sam_shape_mesh_destroy(&s);
    char exe[1100];
    snprintf(exe, sizeof exe, "%s/sam_build", bin_dir);
    double t = sam_seconds();
    pid_t pid = fork();
    if (pid == 0) {
        execl(exe, exe, mesh_path, "-o", out_path, "--material", "skin", "--mm-per-unit", "40", "--force", "--quiet",
              (char *)NULL);
        _exit(127);
    }
    int status;
    struct rusage ru;
    /* The only child this process waits for: its rusage is the child's. */
    if (pid < 0 || waitpid(pid, &status, 0) < 0 || getrusage(RUSAGE_CHILDREN, &ru) != 0 || !WIFEXITED(status) ||
        WEXITSTATUS(status) != 0) {
        fprintf(stderr, "bench_build: %s failed\n", exe);
        exit(1);
    }
    t = sam_seconds() - t;
    double per = (double)ru.ru_maxrss * 1024.0 / vertices;
    printf("memory: %u vertices, peak %.0f MiB, %.0f bytes per vertex, %.1f s\n", vertices,
           ru.ru_maxrss / 1024.0, per, t);
    fprintf(json, "  \"memory\": {\"vertices\": %u, \"peak_mib\": %.1f, \"bytes_per_vertex\": %.1f, \"seconds\": %.2f},\n",
            vertices, ru.ru_maxrss / 1024.0, per, t);
    remove(mesh_path);
    remove(out_path);
}

static void usage(FILE *out)
{
    fprintf(out, "usage: bench_build [--quick] [--json FILE] [--scans DIR] [STUDY...]\n"
                 "\n"
                 "Times the builder; STUDY is candidates, brute, scaling, large, dragon or memory (default: all).\n"
                 "Writes FILE (default bench/results/build.json); --scans finds the real scans\n"
                 "(meshes/fetch_scans.sh). scripts/bench.sh runs it with the other benchmarks.\n"
                 "\n"
                 "examples:\n"
                 "  bench_build --quick scaling\n"
                 "  bench_build brute candidates --json /tmp/build.json\n");
}

int main(int argc, char **argv)
{
    const char *json_path = "bench/results/build.json", *scans = "meshes/scans";
    int which[6] = {0}, quick = 0;
    static const char *names[] = {"candidates", "brute", "scaling", "large", "dragon", "memory"};
    const char *studies[6] = {0};
    const sam_arg args[] = {
        {"--quick", SAM_ARG_FLAG, .target = &quick},
        {"--json", SAM_ARG_STRING, &json_path, .value = "FILE"},
        {"--scans", SAM_ARG_STRING, &scans, .value = "DIR"},
    };
    const sam_args_spec spec = {"bench_build", args, sizeof args / sizeof *args, studies, 0, 6, "STUDY", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    int any = 0;
    for (int i = 0; i < 6 && studies[i]; ++i) {
        int found = 0;
        for (int k = 0; k < 6; ++k)
            if (!strcmp(studies[i], names[k]))
                which[k] = found = any = 1;
        if (!found)
            return sam_args_fail("bench_build", "unknown study \"%s\" (candidates, brute, scaling, large, dragon or "
                                                "memory)", studies[i]);
    }
    if (!any)
        for (int k = 0; k < 6; ++k)
            which[k] = 1;
    sam_atomic_file out;
    bench_json_open("bench_build", json_path, &out);
    FILE *json = out.fp;
    fprintf(json, "{\n  \"quick\": %s,\n", quick ? "true" : "false");
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
    if (which[5]) {
        char dir[1024];
        snprintf(dir, sizeof dir, "%s", argv[0]);
        char *slash = strrchr(dir, '/');
        if (slash)
            *slash = 0;
        else
            snprintf(dir, sizeof dir, ".");
        memory_study(json, dir);
    }
    fprintf(json, "  \"done\": true\n}\n");
    bench_json_commit("bench_build", &out);
    return 0;
}
