/*
 * bench_truth: the ground truth's (sam_truth) time against its sample
 * count, measured side by side in one run.
 *
 * For three scenes (the back-lit ear in skin, the knot in ketchup with a
 * point and a spot light and an environment, the slab in marble under an
 * area light, whose visibility costs 16 rays per sample), lit exactly as
 * sam_compare lights them (sam_runtime_scene_setup's lights, environment and
 * rho_dt), at several sample counts: the time to place the samples and
 * compute their L_d (sam_truth_create) and samples per second; the time of
 * the exact back-side sum (eq. 7) at up to 1024 evenly spread vertices of the object and queries
 * per second; the same with the far field at 1% (sam_compare's default)
 * and its speed-up and relative difference against the exact sum; and the
 * exact sum's relative difference against the largest count's (how far
 * the smaller counts are from converged).
 *
 * Usage: bench_truth [--quick] [--json FILE] [--scenes DIR]
 *   --json    default bench/results/truth.json
 *   --scenes  where the scene files are (default scenes)
 *   --quick   4k and 16k samples, 64 queries: a check that it runs
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_args.h"
#include "sam/sam_scene.h"
#include "sam/sam_truth.h"
#include "bench_util.h"

static void die(const char *what, const sam_error *err)
{
    bench_die("bench_truth", what, err);
}

static float rho_dt_of(const void *user, float n_dot_l)
{
    return sam_runtime_rho_dt(user, n_dot_l);
}

/* sum |a - b| / sum |b| over 3 * count values. */
static double relative_l1(const float *a, const float *b, size_t count)
{
    double diff = 0, sum = 0;
    for (size_t i = 0; i < 3 * count; ++i) {
        diff += fabs((double)a[i] - b[i]);
        sum += fabs((double)b[i]);
    }
    return sum > 0 ? diff / sum : 0;
}

/* One scene at every sample count; writes one JSON object. */
static void truth_scene(const char *scenes, const char *file, const uint64_t *counts, int count_n,
                        uint32_t max_queries, FILE *json)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", scenes, file);
    /* The runtime gives the scene's environment SH and rho_dt exactly as
     * sam_compare's truth gets them. */
    sam_scene scene;
    samfile_data sam;
    sam_profile profile;
    float mm_per_unit, sh[9][3];
    int has_environment;
    sam_runtime *rt = bench_scene_runtime("bench_truth", path, &scene, &sam, &profile, &mm_per_unit, sh,
                                          &has_environment);
    sam_error err;
    sam_truth_scene ts = {.vertex_count = sam.vertex_count, .positions = sam.positions, .normals = sam.normals,
                          .triangle_count = sam.triangle_count, .triangles = sam.triangles,
                          .mm_per_unit = mm_per_unit, .profile = &profile, .lights = scene.lights,
                          .light_count = scene.light_count, .sh = has_environment ? (const float(*)[3])sh : NULL,
                          .environment_rho_dt = sam_runtime_environment_rho_dt(rt), .rho_dt = rho_dt_of,
                          .rho_dt_user = rt};
    /* Queries at evenly spread vertices, at most max_queries. */
    uint32_t stride = (sam.vertex_count + max_queries - 1) / max_queries;
    size_t queries = (sam.vertex_count + stride - 1) / stride;
    float *qp = malloc(queries * 3 * sizeof *qp), *qn = malloc(queries * 3 * sizeof *qn);
    float *exact = malloc((size_t)count_n * queries * 3 * sizeof *exact), *far = malloc(queries * 3 * sizeof *far);
    if (!qp || !qn || !exact || !far)
        die(path, NULL);
    for (size_t q = 0; q < queries; ++q) {
        memcpy(qp + 3 * q, sam.positions + 3 * q * stride, 3 * sizeof *qp);
        memcpy(qn + 3 * q, sam.normals + 3 * q * stride, 3 * sizeof *qn);
    }
    printf("\n%s (%s, %u vertices, %zu lights%s), %zu queries\n", file, scene.material, sam.vertex_count,
           scene.light_count, has_environment ? ", environment" : "", queries);
    printf("%10s %10s %9s %12s %10s %10s %11s %9s %11s %12s\n", "samples", "lit", "create s", "samples/s",
           "exact s", "queries/s", "far field s", "speed-up", "far vs exact", "vs largest");
    fprintf(json, "    {\"scene\": \"%s\", \"material\": \"%s\", \"vertices\": %u, \"lights\": %zu, "
                  "\"environment\": %s, \"queries\": %zu, \"far_field_tolerance\": 0.01, \"counts\": [",
            file, scene.material, sam.vertex_count, scene.light_count, has_environment ? "true" : "false", queries);
    double rows[8][6];
    uint64_t lit[8];
    for (int c = 0; c < count_n; ++c) {
        sam_truth_settings set;
        sam_truth_default_settings(&set);
        set.sample_count = counts[c];
        sam_truth *truth;
        if (sam_truth_create(&ts, &set, &truth, &err) != SAM_OK)
            die(path, &err);
        double create = sam_truth_seconds(truth);
        lit[c] = sam_truth_lit_sample_count(truth);
        float *ex = exact + (size_t)c * queries * 3;
        double t = sam_seconds();
        if (sam_truth_translucency(truth, queries, qp, qn, ex, &err) != SAM_OK)
            die(path, &err);
        double exact_s = sam_seconds() - t;
        sam_truth_destroy(truth);
        /* The far field is a setting of create: a second truth of the same
         * samples (same seed and count) gives the same L_d. */
        set.far_field_tolerance = 0.01f;
        if (sam_truth_create(&ts, &set, &truth, &err) != SAM_OK)
            die(path, &err);
        t = sam_seconds();
        if (sam_truth_translucency(truth, queries, qp, qn, far, &err) != SAM_OK)
            die(path, &err);
        double far_s = sam_seconds() - t;
        sam_truth_destroy(truth);
        rows[c][0] = create, rows[c][1] = exact_s, rows[c][2] = far_s;
        rows[c][3] = relative_l1(far, ex, queries);
    }
    const float *largest = exact + (size_t)(count_n - 1) * queries * 3;
    for (int c = 0; c < count_n; ++c) {
        double vs_largest = relative_l1(exact + (size_t)c * queries * 3, largest, queries);
        printf("%10llu %10llu %9.3f %12.3g %10.3f %10.0f %11.3f %8.1fx %11.3f%% %11.3f%%\n",
               (unsigned long long)counts[c], (unsigned long long)lit[c], rows[c][0], counts[c] / rows[c][0],
               rows[c][1], queries / rows[c][1], rows[c][2], rows[c][1] / rows[c][2], 100 * rows[c][3],
               100 * vs_largest);
        fprintf(json,
                "%s{\"samples\": %llu, \"lit_samples\": %llu, \"create_seconds\": %.4f, \"samples_per_second\": %.0f, "
                "\"exact_seconds\": %.4f, \"exact_queries_per_second\": %.1f, \"far_field_seconds\": %.4f, "
                "\"far_field_speedup\": %.3f, \"far_field_relative_difference\": %.6f, "
                "\"relative_difference_to_largest\": %.6f}",
                c ? ", " : "", (unsigned long long)counts[c], (unsigned long long)lit[c], rows[c][0],
                counts[c] / rows[c][0], rows[c][1], queries / rows[c][1], rows[c][2], rows[c][1] / rows[c][2],
                rows[c][3], vs_largest);
    }
    fprintf(json, "]}");
    free(qp);
    free(qn);
    free(exact);
    free(far);
    sam_runtime_destroy(rt);
    samfile_free(&sam);
    sam_scene_destroy(&scene);
}

static void usage(FILE *out)
{
    fprintf(out, "usage: bench_truth [--quick] [--json FILE] [--scenes DIR]\n"
                 "\n"
                 "Times the ground truth (sam_truth) on three scenes at growing sample counts, with and without\n"
                 "its far field; writes FILE (default bench/results/truth.json).\n"
                 "\n"
                 "examples:\n"
                 "  bench_truth --quick --json /tmp/truth.json\n");
}

int main(int argc, char **argv)
{
    const char *json_path = "bench/results/truth.json", *scenes = "scenes";
    int quick = 0;
    const sam_arg args[] = {
        {"--quick", SAM_ARG_FLAG, .target = &quick},
        {"--json", SAM_ARG_STRING, &json_path, .value = "FILE"},
        {"--scenes", SAM_ARG_STRING, &scenes, .value = "DIR"},
    };
    const sam_args_spec spec = {"bench_truth", args, sizeof args / sizeof *args, NULL, 0, 0, NULL, usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    static const char *const files[3] = {"ear_backlit.json", "compare_knot.json", "compare_slab_area.json"};
    /* Up to the automatic count's upper bound, SAM_TRUTH_MAX_SAMPLES. */
    static const uint64_t full_counts[4] = {1u << 16, 1u << 18, 1u << 20, SAM_TRUTH_MAX_SAMPLES};
    static const uint64_t quick_counts[2] = {1u << 12, 1u << 14};
    sam_gl_context *gl;
    sam_error err;
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK)
        die("GL", &err);
    sam_atomic_file out;
    bench_json_open("bench_truth", json_path, &out);
    fprintf(out.fp, "{\n  \"quick\": %s,\n  \"scenes\": [\n", quick ? "true" : "false");
    for (int s = 0; s < 3; ++s) {
        truth_scene(scenes, files[s], quick ? quick_counts : full_counts, quick ? 2 : 4, quick ? 64 : 1024, out.fp);
        fprintf(out.fp, "%s\n", s < 2 ? "," : "");
    }
    fprintf(out.fp, "  ]\n}\n");
    bench_json_commit("bench_truth", &out);
    sam_gl_context_destroy(gl);
    return 0;
}
