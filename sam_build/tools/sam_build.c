/*
 * sam_build: mesh + material in, .sam out (see sam_build.h for the method).
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "sam/sam_app.h"
#include "sam/sam_build.h"
#include "sam/sam_sha256.h"

/* Set by SIGINT/SIGTERM; the progress callback turns it into a clean cancel
 * so no partial .sam is left. The one global a signal handler needs. */
static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

static void usage(FILE *out)
{
    sam_build_settings d;
    sam_build_default_settings(&d);
    fprintf(out,
            "usage: sam_build MESH -o OUT.sam --material NAME|FILE (--mm-per-unit X | --size-mm D) [options]\n"
            "\n"
            "Precomputes a Spatial Adjacency Map: for every vertex, the back-side vertices that\n"
            "transport the most light to it through the material, with Monte Carlo form factors.\n"
            "\n"
            "  MESH                .obj, .ply, .off or .stl\n"
            "  -o OUT.sam          output, written atomically; an existing file needs --force\n"
            "  --material M        a preset (skin, marble, apple, chicken1, chicken2, cream, ketchup,\n"
            "                      potato, skimmilk, skin1, skin2, wholemilk) or a profile file\n"
            "  --mm-per-unit X     millimetres per model unit, or\n"
            "  --size-mm D         the bounding-box diagonal in millimetres\n"
            "options:\n"
            "  --samples N         back-side samples per vertex, 1..64 (default %u)\n"
            "  --mc-samples M      Monte Carlo point pairs per form factor, 4..65536 (default %u)\n"
            "  --candidates C      cheap-ranked candidates given Monte Carlo per vertex (default N+2)\n"
            "  --radius-tolerance E energy fraction of the profile left beyond the search radius\n"
            "                      (default %g)\n"
            "  --seed S            random seed (default %llu); the output is identical for any --threads\n"
            "  --threads T         worker threads, 0 = all cores (default 0)\n"
            "  --force             overwrite OUT.sam if it exists\n"
            "  --quiet             no progress bar\n"
            "  -h, --help          this help\n",
            d.samples_per_vertex, d.mc_samples, d.radius_tolerance, (unsigned long long)d.seed);
}

static int parse_float(const char *opt, const char *s, float *out)
{
    double v;
    if (!sam_parse_double(s, &v)) {
        fprintf(stderr, "sam_build: %s needs a number, got \"%s\"\n", opt, s);
        return 0;
    }
    *out = (float)v;
    return 1;
}

static int parse_u64(const char *opt, const char *s, unsigned long long max, unsigned long long *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (!*s || *end || errno || s[0] == '-' || v > max) {
        fprintf(stderr, "sam_build: %s needs a whole number in 0..%llu, got \"%s\"\n", opt, max, s);
        return 0;
    }
    *out = v;
    return 1;
}

int main(int argc, char **argv)
{
    const char *mesh_path = NULL, *out_path = NULL, *material = NULL;
    float mm_per_unit = NAN, size_mm = NAN;
    int force = 0, quiet = 0;
    sam_build_settings settings;
    sam_build_default_settings(&settings);
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        unsigned long long u;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--force")) {
            force = 1;
        } else if (!strcmp(a, "--quiet")) {
            quiet = 1;
        } else if (a[0] == '-' && a[1] && !v) {
            fprintf(stderr, "sam_build: %s needs a value (see --help)\n", a);
            return 2;
        } else if (!strcmp(a, "-o")) {
            out_path = argv[++i];
        } else if (!strcmp(a, "--material")) {
            material = argv[++i];
        } else if (!strcmp(a, "--mm-per-unit")) {
            if (!parse_float(a, argv[++i], &mm_per_unit))
                return 2;
        } else if (!strcmp(a, "--size-mm")) {
            if (!parse_float(a, argv[++i], &size_mm))
                return 2;
        } else if (!strcmp(a, "--samples")) {
            if (!parse_u64(a, argv[++i], 1000000, &u))
                return 2;
            settings.samples_per_vertex = (uint32_t)u;
        } else if (!strcmp(a, "--mc-samples")) {
            if (!parse_u64(a, argv[++i], 100000000, &u))
                return 2;
            settings.mc_samples = (uint32_t)u;
        } else if (!strcmp(a, "--candidates")) {
            if (!parse_u64(a, argv[++i], 1000000, &u))
                return 2;
            settings.candidates = (uint32_t)u;
        } else if (!strcmp(a, "--radius-tolerance")) {
            if (!parse_float(a, argv[++i], &settings.radius_tolerance))
                return 2;
        } else if (!strcmp(a, "--seed")) {
            if (!parse_u64(a, argv[++i], ~0ull, &u))
                return 2;
            settings.seed = u;
        } else if (!strcmp(a, "--threads")) {
            if (!parse_u64(a, argv[++i], 4096, &u))
                return 2;
            settings.threads = (int)u;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "sam_build: unknown option \"%s\" (see --help)\n", a);
            return 2;
        } else if (!mesh_path) {
            mesh_path = a;
        } else {
            fprintf(stderr, "sam_build: unexpected argument \"%s\" (one mesh per run; see --help)\n", a);
            return 2;
        }
    }
    if (!mesh_path || !out_path || !material) {
        fprintf(stderr, "sam_build: %s is required (see --help)\n",
                !mesh_path ? "a MESH" : !out_path ? "-o OUT.sam" : "--material");
        return 2;
    }
    if (isnan(mm_per_unit) == isnan(size_mm)) {
        fprintf(stderr, "sam_build: give exactly one of --mm-per-unit and --size-mm\n");
        return 2;
    }
    if (!isnan(size_mm) && !(size_mm > 0)) {
        fprintf(stderr, "sam_build: --size-mm must be > 0, got %g\n", size_mm);
        return 2;
    }
    sam_error err;
    float scale_check = isnan(mm_per_unit) ? 1.0f : mm_per_unit;
    if (sam_build_check_settings(&settings, scale_check, &err) != SAM_OK) {
        fprintf(stderr, "sam_build: %s\n", err.message);
        return 2;
    }
    sam_profile profile;
    if (sam_profile_from_spec(material, &profile, &err) != SAM_OK) {
        fprintf(stderr, "sam_build: --material: %s\n", err.message);
        return 1;
    }
    struct stat st_out;
    if (!force && stat(out_path, &st_out) == 0) {
        fprintf(stderr, "sam_build: %s exists; use --force to overwrite it\n", out_path);
        return 1;
    }
    /* Fail on an unwritable output now, not after a long build. */
    sam_atomic_file probe;
    if (sam_atomic_open(&probe, out_path, &err) != SAM_OK) {
        fprintf(stderr, "sam_build: %s\n", err.message);
        return 1;
    }
    sam_atomic_abort(&probe);

    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    sam_mesh mesh;
    sam_mesh_report report;
    if (sam_mesh_load(mesh_path, &mesh, &report, &err) != SAM_OK) {
        fprintf(stderr, "sam_build: %s\n", err.message);
        return 1;
    }
    char summary[512];
    sam_mesh_report_summary(&report, summary, sizeof summary);
    if (strcmp(summary, "no repairs"))
        fprintf(stderr, "sam_build: %s: %s\n", mesh_path, summary);
    if (!isnan(size_mm)) {
        double diag = sam_mesh_diagonal(&mesh);
        if (!(diag > 0)) {
            fprintf(stderr, "sam_build: %s: the mesh has no extent, so --size-mm cannot scale it\n", mesh_path);
            sam_mesh_destroy(&mesh);
            return 1;
        }
        mm_per_unit = (float)(size_mm / diag);
    }
    char sha[65];
    int code = 1;
    sam_app_progress view;
    sam_app_progress_init(&view, "sam_build", quiet, &interrupted);
    sam_build_context *ctx = NULL;
    sam_build_result result;
    memset(&result, 0, sizeof result);
    samfile_data data;
    memset(&data, 0, sizeof data);
    if (sam_sha256_file(mesh_path, sha, &err) != SAM_OK ||
        sam_build_context_create(&mesh, &profile, mm_per_unit, &settings, &ctx, &err) != SAM_OK)
        goto done;
    view.start = sam_seconds();
    if (!quiet)
        fprintf(stderr, "sam_build: %s: %u vertices (%u welded), %s at %g mm per unit, N=%u, search radius %.3g mm\n",
                mesh_path, mesh.vertex_count, mesh.topo_count, profile.name, mm_per_unit, settings.samples_per_vertex,
                sam_profile_radius(&profile, settings.radius_tolerance));
    if (sam_build_run(ctx, sam_app_progress_update, &view, &result, &err) != SAM_OK)
        goto done;
    sam_build_source source = {mesh_path, sha};
    if (sam_build_to_samfile(ctx, &result, &source, &data, &err) != SAM_OK ||
        samfile_write(out_path, &data, &err) != SAM_OK)
        goto done;
    uint64_t used = 0, empty = 0;
    for (uint32_t t = 0; t < result.topo_count; ++t) {
        uint32_t k = 0;
        while (k < result.samples_per_vertex &&
               result.sample[(size_t)t * result.samples_per_vertex + k] != SAM_BUILD_NO_SAMPLE)
            ++k;
        used += k;
        empty += k == 0;
    }
    fprintf(stderr,
            "sam_build: wrote %s: %u vertices, %.2f back-side samples per vertex (%.1f%% have none), "
            "%.2f s (%.2f us per vertex)\n",
            out_path, mesh.vertex_count, (double)used / result.topo_count, 100.0 * (double)empty / result.topo_count,
            result.seconds, 1e6 * result.seconds / result.topo_count);
    code = 0;
done:
    if (code)
        fprintf(stderr, "%ssam_build: %s\n", view.open_line ? "\n" : "",
                interrupted ? "interrupted; no output written" : err.message);
    samfile_free(&data);
    sam_build_result_destroy(&result);
    sam_build_context_destroy(ctx);
    sam_mesh_destroy(&mesh);
    return code;
}
