/*
 * bench_limit: does a map converge on what per-vertex transport can carry,
 * and how far is that from the ground truth?
 *
 * For one scene, at up to --queries (topo) vertices spread evenly over the
 * vertex order, the maps' translucency T (RGB) as the runtime computes it
 * at rest (read back), of the cut map at every N of --samples and of the
 * flat map at the largest, each built from the scene's mesh (a prebuilt
 * map the scene names gives only its material and scale), against three
 * references:
 *   - the vertex-sum limit: the sum over every back-side vertex i of the
 *     receiver (eq. 13-14) of K_oi (eq. 11, Monte Carlo with --pairs point
 *     pairs, another seed than the maps') times the runtime's L_d at i:
 *     what a map holding every back-side vertex exactly would give;
 *   - the point-pair limit: the same sum over every other vertex, with K
 *     from the pairs of points that pass eq. 13-14 themselves
 *     (sam_build_form_factor_pointwise): where the per-vertex test alone
 *     leaves a vertex map, seen apart from L_d's;
 *   - the ground truth's eq. 7 at the same vertices (sam_truth: L_d and the
 *     back-side test per surface point, --truth-samples points).
 * Prints each map's error against the limit and against the truth (RMSE
 * over the three channels as a share of the reference's RMS, and the mean
 * bias), and both limits' against the truth. A map whose error against the
 * limit falls with N converges; the limit's error against the truth is
 * what no budget removes (the mesh's vertices cannot carry it).
 *
 * Usage: bench_limit SCENE [--samples LIST] [--pairs P] [--queries Q]
 *                          [--truth-samples S] [--json FILE] [--csv FILE]
 * --csv writes every receiver: its vertex, position, both limits', the
 * truth's and each map's T, to see where the errors lie.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_args.h"
#include "sam/sam_build.h"
#include "sam/sam_mesh.h"
#include "sam/sam_scene.h"
#include "sam/sam_truth.h"
#include "bench_util.h"

#define PROGRAM "bench_limit"
#define MAX_SAMPLE_COUNTS 12
/* The limit's Monte Carlo seed: independent of the maps' (default 1). */
#define LIMIT_SEED 7777

static void die(const char *what, const sam_error *err)
{
    bench_die(PROGRAM, what, err);
}

static float rho_dt_of(const void *user, float n_dot_l)
{
    return sam_runtime_rho_dt(user, n_dot_l);
}

/* The receivers and the two references. */
typedef struct limit_refs {
    uint32_t count;
    uint32_t *topo;   /* count topo vertices */
    uint32_t *render; /* count: the render vertex standing for each */
    double *limit;    /* 3 * count */
    double *point;    /* 3 * count: the point-pair limit */
    double *truth;    /* 3 * count */
} limit_refs;

/* An error against a reference: RMSE / RMS of the reference, and
 * sum(a - ref) / sum(ref). */
typedef struct limit_error {
    double rmse, bias;
} limit_error;

static limit_error error_of(const double *a, const double *ref, uint32_t count)
{
    double se = 0, sr = 0, diff = 0, sum = 0;
    for (size_t i = 0; i < 3 * (size_t)count; ++i) {
        se += (a[i] - ref[i]) * (a[i] - ref[i]);
        sr += ref[i] * ref[i];
        diff += a[i] - ref[i];
        sum += ref[i];
    }
    return (limit_error){sr > 0 ? sqrt(se / sr) : 0, sum > 0 ? diff / sum : 0};
}

/* The scene's map of kind `map` with N samples on a new runtime, lit as
 * sam_compare lights it, its rest T at the receivers in `t` (3 * count).
 * The map's vertices must be `mesh`'s, over which the limits are summed.
 * The first call (ld != NULL) also reads L_d (3 per render vertex) and
 * computes the truth at the receivers. */
static void map_translucency(const sam_scene *scene, const sam_mesh *mesh, sam_build_map map, long n,
                             limit_refs *refs, double *t, float *ld, uint64_t truth_samples, sam_profile *profile,
                             float *mm_per_unit)
{
    sam_build_settings settings;
    sam_build_default_settings(&settings);
    settings.map = map;
    settings.samples_per_vertex = (uint32_t)n;
    /* A cut of N entries, not N of the default budget's: the study is how
     * a cut nears the limit as it is refined. */
    settings.cut_budget = (uint32_t)n;
    samfile_data sam;
    sam_runtime *rt;
    float sh[9][3];
    int has_environment;
    sam_error err;
    fprintf(stderr, "%s: building the %s map, N = %ld\n", PROGRAM, sam_build_map_name(map), n);
    if (sam_app_scene_object(scene, PROGRAM, &settings, NULL, NULL, &sam, profile, mm_per_unit, NULL, &err) != SAM_OK)
        die(scene->mesh_path, &err);
    if (sam.vertex_count != mesh->vertex_count ||
        memcmp(sam.positions, mesh->positions, 3 * sizeof(float) * mesh->vertex_count)) {
        fprintf(stderr, "%s: %s: the map's %u vertices are not the mesh's %u as loaded here\n", PROGRAM,
                scene->mesh_path, sam.vertex_count, mesh->vertex_count);
        exit(1);
    }
    if (sam_runtime_create(&sam, profile, *mm_per_unit, &rt, &err) != SAM_OK ||
        sam_runtime_scene_setup(rt, scene, sh, &has_environment, NULL, 0, &err) != SAM_OK ||
        sam_runtime_irradiance(rt, &err) != SAM_OK || sam_runtime_translucency(rt, 0, 0.0f, 1, &err) != SAM_OK)
        die(scene->mesh_path, &err);
    float *rgb = malloc(3 * sizeof *rgb * sam.vertex_count);
    if (!rgb || sam_runtime_read_translucency(rt, rgb, &err) != SAM_OK ||
        (ld && sam_runtime_read_irradiance(rt, ld, &err) != SAM_OK))
        die("reading back T and L_d", rgb ? &err : NULL);
    for (uint32_t q = 0; q < refs->count; ++q)
        for (int c = 0; c < 3; ++c)
            t[3 * q + c] = rgb[3 * (size_t)refs->render[q] + c];
    if (ld) {
        sam_truth_scene ts = {.vertex_count = sam.vertex_count, .positions = sam.positions,
                              .normals = sam.normals, .triangle_count = sam.triangle_count,
                              .triangles = sam.triangles, .mm_per_unit = *mm_per_unit, .profile = profile,
                              .lights = scene->lights, .light_count = scene->light_count,
                              .sh = has_environment ? (const float(*)[3])sh : NULL,
                              .environment_rho_dt = sam_runtime_environment_rho_dt(rt), .rho_dt = rho_dt_of,
                              .rho_dt_user = rt};
        sam_truth_settings ts_set;
        sam_truth_default_settings(&ts_set);
        ts_set.sample_count = truth_samples;
        float *qp = malloc(3 * sizeof *qp * refs->count), *qn = malloc(3 * sizeof *qn * refs->count);
        float *out = malloc(3 * sizeof *out * refs->count);
        if (!qp || !qn || !out)
            die("queries", NULL);
        for (uint32_t q = 0; q < refs->count; ++q)
            for (int c = 0; c < 3; ++c) {
                qp[3 * q + c] = sam.positions[3 * (size_t)refs->render[q] + c];
                qn[3 * q + c] = sam.normals[3 * (size_t)refs->render[q] + c];
            }
        fprintf(stderr, "%s: the ground truth at %u vertices\n", PROGRAM, refs->count);
        sam_truth *truth;
        if (sam_truth_create(&ts, &ts_set, &truth, &err) != SAM_OK ||
            sam_truth_translucency(truth, refs->count, qp, qn, out, &err) != SAM_OK)
            die("truth", &err);
        for (size_t i = 0; i < 3 * (size_t)refs->count; ++i)
            refs->truth[i] = out[i];
        sam_truth_destroy(truth);
        free(qp);
        free(qn);
        free(out);
    }
    free(rgb);
    sam_runtime_destroy(rt);
    samfile_free(&sam);
}

/* Both limits at every receiver, from the runtime's L_d. */
static void vertex_limit(const sam_mesh *mesh, const sam_profile *profile, float mm_per_unit, const float *ld,
                         uint32_t pairs, limit_refs *refs)
{
    sam_build_settings settings;
    sam_build_default_settings(&settings);
    sam_build_context *ctx;
    sam_error err;
    if (sam_build_context_create(mesh, profile, mm_per_unit, &settings, &ctx, &err) != SAM_OK)
        die("build context", &err);
    fprintf(stderr, "%s: the limits at %u vertices, %u pairs per form factor\n", PROGRAM, refs->count, pairs);
    const long count = (long)refs->count;
#pragma omp parallel for schedule(dynamic)
    for (long q = 0; q < count; ++q) {
        const uint32_t o = refs->topo[q];
        double sum[3] = {0, 0, 0}, point[3] = {0, 0, 0};
        for (uint32_t i = 0; i < mesh->topo_count; ++i) {
            if (i == o)
                continue;
            float k[3], k_error;
            const float *l = ld + 3 * (size_t)mesh->topo_rep[i];
            sam_build_form_factor_pointwise(ctx, o, i, pairs, LIMIT_SEED, k, &k_error);
            for (int c = 0; c < 3; ++c)
                point[c] += (double)k[c] * l[c];
            if (!sam_build_is_back_side(ctx, o, i))
                continue;
            sam_build_form_factor(ctx, o, i, pairs, LIMIT_SEED, k, &k_error);
            for (int c = 0; c < 3; ++c)
                sum[c] += (double)k[c] * l[c];
        }
        for (int c = 0; c < 3; ++c) {
            refs->limit[3 * q + c] = sum[c];
            refs->point[3 * q + c] = point[c];
        }
    }
    sam_build_context_destroy(ctx);
}

/* Every receiver's values: vertex, x, y, z (model units), then R, G, B of
 * the limit, the point-pair limit, the truth and each map (the cut's at
 * each N, the flat map). */
static void write_csv(const char *path, const sam_mesh *mesh, const limit_refs *refs, const double *t,
                      const long *n, int n_count, long n_max)
{
    sam_atomic_file out;
    bench_json_open(PROGRAM, path, &out);
    fprintf(out.fp, "vertex,x,y,z");
    static const char rgb[] = "rgb";
    static const char *const refs_names[3] = {"limit", "point_limit", "truth"};
    for (int m = -3; m <= n_count; ++m)
        for (int c = 0; c < 3; ++c) {
            if (m < 0)
                fprintf(out.fp, ",%s_%c", refs_names[m + 3], rgb[c]);
            else
                fprintf(out.fp, ",%s%ld_%c", m == n_count ? "flat" : "cut", m < n_count ? n[m] : n_max, rgb[c]);
        }
    fprintf(out.fp, "\n");
    for (uint32_t q = 0; q < refs->count; ++q) {
        const float *p = mesh->positions + 3 * (size_t)refs->render[q];
        fprintf(out.fp, "%u,%.7g,%.7g,%.7g", refs->render[q], p[0], p[1], p[2]);
        for (int m = -3; m <= n_count; ++m)
            for (int c = 0; c < 3; ++c)
                fprintf(out.fp, ",%.7g",
                        m == -3   ? refs->limit[3 * q + c]
                        : m == -2 ? refs->point[3 * q + c]
                        : m == -1 ? refs->truth[3 * q + c]
                                  : t[3 * (size_t)refs->count * m + 3 * q + c]);
        fprintf(out.fp, "\n");
    }
    bench_json_commit(PROGRAM, &out);
}

static void usage(FILE *out)
{
    fprintf(out, "usage: bench_limit SCENE [--samples LIST] [--pairs P] [--queries Q] [--truth-samples S]\n"
                 "                   [--json FILE] [--csv FILE]\n"
                 "\n"
                 "Compares the per-vertex translucency of the scene's cut map at each N of LIST (default\n"
                 "3,16,32,64; each N once) and of the flat map at the largest N, built from the scene's mesh,\n"
                 "with what every back-side vertex would give\n"
                 "(the vertex-sum limit, P Monte Carlo pairs per form factor, default 256), with the same sum\n"
                 "over point pairs that pass eq. 13-14 themselves (the point-pair limit), and with the ground\n"
                 "truth's eq. 7 (S surface samples, default 1048576), at up to Q vertices (default 256), spread\n"
                 "evenly over the vertex order.\n"
                 "The scene must name its mesh. --json writes the table, --csv every vertex's values.\n"
                 "\n"
                 "examples:\n"
                 "  bench_limit scenes/compare_slab_environment.json --samples 16,32,64\n"
                 "  bench_limit scenes/compare_knot.json --queries 128 --json /tmp/knot_limit.json\n");
}

int main(int argc, char **argv)
{
    const char *scene_path, *list = "3,16,32,64", *json_path = NULL, *csv_path = NULL;
    long pairs = 256, queries = 256;
    long truth_samples = 1 << 20;
    const sam_arg args[] = {
        {"--samples", SAM_ARG_STRING, &list, .value = "LIST"},
        {"--pairs", SAM_ARG_INT, &pairs, .value = "P", .lo = 4, .hi = 65536},
        {"--queries", SAM_ARG_INT, &queries, .value = "Q", .lo = 1, .hi = 1 << 20},
        {"--truth-samples", SAM_ARG_INT, &truth_samples, .value = "S", .lo = SAM_TRUTH_MIN_SAMPLES,
         .hi = SAM_TRUTH_MAX_SAMPLES},
        {"--json", SAM_ARG_STRING, &json_path, .value = "FILE"},
        {"--csv", SAM_ARG_STRING, &csv_path, .value = "FILE"},
    };
    const char *positional[1] = {NULL};
    const sam_args_spec spec = {PROGRAM, args, sizeof args / sizeof *args, positional, 1, 1, "SCENE", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    scene_path = positional[0];
    long n[MAX_SAMPLE_COUNTS];
    int n_count;
    if (!sam_args_int_list(list, 1, 64, n, MAX_SAMPLE_COUNTS, &n_count))
        return sam_args_fail(PROGRAM, "--samples must be up to %d comma-separated whole numbers in 1..64, got \"%s\"",
                             MAX_SAMPLE_COUNTS, list);
    long n_max = 0;
    for (int i = 0; i < n_count; ++i) {
        for (int j = 0; j < i; ++j)
            if (n[j] == n[i])
                return sam_args_fail(PROGRAM, "--samples gives N = %ld twice in \"%s\"", n[i], list);
        n_max = n[i] > n_max ? n[i] : n_max;
    }
    sam_error err;
    sam_scene scene;
    if (sam_scene_load(scene_path, &scene, &err) != SAM_OK)
        die("scene", &err);
    if (!scene.mesh_path)
        return sam_args_fail(PROGRAM, "%s names no mesh: the limit is summed over the mesh's vertices", scene_path);
    sam_mesh mesh;
    if (sam_mesh_load(scene.mesh_path, &mesh, NULL, &err) != SAM_OK)
        die(scene.mesh_path, &err);
    sam_mesh_orient_outward(&mesh); /* as the map's builder loads it */
    sam_gl_context *gl;
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK)
        die("GL", &err);

    limit_refs refs = {0};
    const uint32_t stride = (mesh.topo_count + (uint32_t)queries - 1) / (uint32_t)queries;
    refs.count = (mesh.topo_count + stride - 1) / stride;
    refs.topo = malloc(refs.count * sizeof *refs.topo);
    refs.render = malloc(refs.count * sizeof *refs.render);
    refs.limit = malloc(3 * sizeof *refs.limit * refs.count);
    refs.point = malloc(3 * sizeof *refs.point * refs.count);
    refs.truth = malloc(3 * sizeof *refs.truth * refs.count);
    const int map_count = n_count + 1;
    double *t = malloc(3 * sizeof *t * refs.count * (size_t)map_count);
    float *ld = malloc(3 * sizeof *ld * mesh.vertex_count);
    if (!refs.topo || !refs.render || !refs.limit || !refs.point || !refs.truth || !t || !ld)
        die("memory", NULL);
    for (uint32_t q = 0; q < refs.count; ++q) {
        refs.topo[q] = q * stride;
        refs.render[q] = mesh.topo_rep[q * stride];
    }

    /* Every map is built from the mesh, at each N and kind; a prebuilt map
     * gives its material and scale. */
    sam_profile profile;
    float mm_per_unit;
    sam_scene built = scene;
    if (scene.sam_path) {
        samfile_data prebuilt;
        if (sam_app_scene_object(&scene, PROGRAM, NULL, NULL, NULL, &prebuilt, &profile, &mm_per_unit, NULL, &err) !=
            SAM_OK)
            die("scene", &err);
        samfile_free(&prebuilt);
        sam_app_scene_from_mesh(&scene, &profile, mm_per_unit, &built);
    }
    for (int m = 0; m < map_count; ++m) {
        const int flat = m == n_count;
        map_translucency(&built, &mesh, flat ? SAM_BUILD_MAP_FLAT : SAM_BUILD_MAP_CUT, flat ? n_max : n[m], &refs,
                         t + 3 * (size_t)refs.count * m, m == 0 ? ld : NULL, (uint64_t)truth_samples, &profile,
                         &mm_per_unit);
    }
    vertex_limit(&mesh, &profile, mm_per_unit, ld, (uint32_t)pairs, &refs);

    sam_atomic_file out = {0};
    if (json_path) {
        bench_json_open(PROGRAM, json_path, &out);
        fprintf(out.fp, "{\n  \"scene\": ");
        bench_json_string(out.fp, scene_path);
        fprintf(out.fp, ", \"queries\": %u, \"pairs\": %ld, \"truth_samples\": %ld,\n", refs.count, pairs,
                truth_samples);
    }
    limit_error lt = error_of(refs.limit, refs.truth, refs.count), pt = error_of(refs.point, refs.truth, refs.count);
    printf("%s: %u of %u vertices, limits with %ld pairs, truth with %ld samples\n", scene_path, refs.count,
           mesh.topo_count, pairs, truth_samples);
    printf("| map | N | RMSE vs limit | bias vs limit | RMSE vs truth | bias vs truth |\n"
           "| --- | --- | --- | --- | --- | --- |\n");
    printf("| vertex-sum limit | all | | | %.2f%% | %+.2f%% |\n", 100 * lt.rmse, 100 * lt.bias);
    printf("| point-pair limit | all | | | %.2f%% | %+.2f%% |\n", 100 * pt.rmse, 100 * pt.bias);
    if (json_path)
        fprintf(out.fp,
                "  \"limit_vs_truth\": {\"rmse\": %.6f, \"bias\": %.6f},\n"
                "  \"point_limit_vs_truth\": {\"rmse\": %.6f, \"bias\": %.6f},\n  \"maps\": [\n",
                lt.rmse, lt.bias, pt.rmse, pt.bias);
    for (int m = 0; m < map_count; ++m) {
        const int flat = m == n_count;
        const long nm = flat ? n_max : n[m];
        const double *tm = t + 3 * (size_t)refs.count * m;
        limit_error el = error_of(tm, refs.limit, refs.count), et = error_of(tm, refs.truth, refs.count);
        printf("| %s | %ld | %.2f%% | %+.2f%% | %.2f%% | %+.2f%% |\n", flat ? "flat" : "cut", nm, 100 * el.rmse,
               100 * el.bias, 100 * et.rmse, 100 * et.bias);
        if (json_path)
            fprintf(out.fp,
                    "    {\"map\": \"%s\", \"n\": %ld, \"vs_limit\": {\"rmse\": %.6f, \"bias\": %.6f}, "
                    "\"vs_truth\": {\"rmse\": %.6f, \"bias\": %.6f}}%s\n",
                    flat ? "flat" : "cut", nm, el.rmse, el.bias, et.rmse, et.bias, m + 1 < map_count ? "," : "");
    }
    if (json_path) {
        fprintf(out.fp, "  ]\n}\n");
        bench_json_commit(PROGRAM, &out);
    }
    if (csv_path)
        write_csv(csv_path, &mesh, &refs, t, n, n_count, n_max);
    sam_gl_context_destroy(gl);
    free(refs.topo);
    free(refs.render);
    free(refs.limit);
    free(refs.point);
    free(refs.truth);
    free(t);
    free(ld);
    sam_mesh_destroy(&mesh);
    sam_scene_destroy(&scene);
    return 0;
}
