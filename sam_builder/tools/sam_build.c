/*
 * sam_build: mesh + material in, .sam out (see sam_build.h for the method);
 * the job itself is sam_app_build_run.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <float.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>

#include "sam/sam_app.h"
#include "sam/sam_app_build.h"
#include "sam/sam_args.h"

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
            "Precomputes a Spatial Adjacency Map: for every vertex, N patches of its back side\n"
            "that together carry the light transported to it through the material: a cut\n"
            "through a tree of surface clusters, fine where the profile changes fast, coarse\n"
            "where it does not, with Monte Carlo form factors.\n"
            "\n"
            "  MESH                .obj, .ply, .off, .stl, .gltf or .glb\n"
            "  -o OUT.sam          output, written atomically; an existing file needs --force\n"
            "  --material M        a preset (skin, marble, apple, chicken1, chicken2, cream, ketchup,\n"
            "                      potato, skimmilk, skin1, skin2, wholemilk) or a profile file\n"
            "  --mm-per-unit X     millimetres per model unit, or\n"
            "  --size-mm D         the bounding-box diagonal in millimetres\n"
            "options:\n"
            "  --samples N         back-side samples per vertex, 1..64 (default %u; %u with --flat)\n"
            "  --flat              the paper's map: the N back-side vertices with the most transport\n"
            "  --flat-scaled       a baseline: the flat map with K scaled to the vertex's total transport\n"
            "  --cut-tolerance E   refine a cut while a node's R_d bound exceeds E of its total\n"
            "                      (default %g)\n"
            "  --cut-budget B      cut B entries per vertex, N..64, and fit them to N: siblings merged\n"
            "                      into their parent, the rest folded into the nearest kept (default:\n"
            "                      the larger of N and %u)\n"
            "  --mc-samples M      Monte Carlo point pairs per form factor, 4..65536 (default %u; four\n"
            "                      times as many where R_d falls steeply across the two fans)\n"
            "  --candidates C      flat maps: cheap-ranked candidates given Monte Carlo (default N+2)\n"
            "  --radius-tolerance E energy fraction of the profile left beyond the search radius\n"
            "                      (default %g)\n"
            "  --seed S            random seed (default %llu); the output is identical for any --threads\n"
            "  --threads T         worker threads, 0 = all cores (default 0)\n"
            "  --keep-orientation  keep a closed mesh whose normals point inward as it is (by default it\n"
            "                      is turned outside out, with a warning: inward, it renders black)\n"
            "  --force             overwrite OUT.sam if it exists\n"
            "  --quiet             no progress bar\n"
            "  -h, --help          this help;  --version  the version\n"
            "\n"
            "examples (from the repository root; meshes/ is bundled):\n"
            "  sam_build meshes/ear.obj -o ear.sam --material skin --mm-per-unit 60\n"
            "  sam_build meshes/knot.obj -o knot32.sam --material marble --size-mm 50 --samples 32\n"
            "  sam_build meshes/knot.obj -o knot_flat.sam --material marble --size-mm 50 --flat\n",
            SAM_BUILD_CUT_DEFAULT_SAMPLES, SAM_BUILD_FLAT_DEFAULT_SAMPLES, d.cut_tolerance, SAM_BUILD_CUT_DEFAULT_BUDGET, d.mc_samples, d.radius_tolerance, (unsigned long long)d.seed);
}

int main(int argc, char **argv)
{
    sam_app_build_job job;
    sam_app_build_defaults(&job);
    sam_build_settings *s = &job.settings;
    long samples = s->samples_per_vertex, budget = s->cut_budget, mc = s->mc_samples, candidates = s->candidates,
         threads = s->threads;
    const char *seed = NULL;
    int flat = 0, flat_scaled = 0;
    const char *finite = "a finite number that fits a 32-bit float";
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &job.out_path, .value = "OUT.sam", .required = 1},
        {"--material", SAM_ARG_STRING, &job.material, .value = "NAME|FILE", .required = 1},
        {"--mm-per-unit", SAM_ARG_FLOAT, &job.mm_per_unit, .lo = -FLT_MAX, .hi = FLT_MAX,
         .must = finite},
        {"--size-mm", SAM_ARG_FLOAT, &job.size_mm, .lo = -FLT_MAX, .hi = FLT_MAX,
         .must = finite},
        {"--samples", SAM_ARG_INT, &samples, .lo = 1, .hi = SAMFILE_MAX_SAMPLES_PER_VERTEX},
        {"--flat", SAM_ARG_FLAG, .target = &flat},
        {"--flat-scaled", SAM_ARG_FLAG, .target = &flat_scaled},
        {"--cut-tolerance", SAM_ARG_FLOAT, &s->cut_tolerance, .lo = -FLT_MAX, .hi = FLT_MAX,
         .must = finite},
        {"--cut-budget", SAM_ARG_INT, &budget, .lo = 0, .hi = SAMFILE_MAX_SAMPLES_PER_VERTEX},
        {"--mc-samples", SAM_ARG_INT, &mc, .lo = 4, .hi = 65536},
        {"--candidates", SAM_ARG_INT, &candidates, .lo = 0, .hi = 4096},
        {"--radius-tolerance", SAM_ARG_FLOAT, &s->radius_tolerance, .lo = -FLT_MAX, .hi = FLT_MAX,
         .must = finite},
        {"--seed", SAM_ARG_STRING, &seed, .value = "S"},
        {"--threads", SAM_ARG_INT, &threads, .lo = 0, .hi = 4096},
        {"--force", SAM_ARG_FLAG, .target = &job.force},
        {"--keep-orientation", SAM_ARG_FLAG, .target = &job.keep_orientation},
        {"--quiet", SAM_ARG_FLAG, .target = &job.quiet},
    };
    const sam_args_spec spec = {"sam_build", args, sizeof args / sizeof *args, &job.mesh_path, 1, 1, "MESH", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (seed) {
        char *end;
        errno = 0;
        s->seed = strtoull(seed, &end, 10);
        if (!*seed || *end || errno || seed[0] == '-')
            return sam_args_fail("sam_build", "--seed must be a whole number in 0..%llu, got \"%s\"", ~0ull, seed);
    }
    if (flat && flat_scaled)
        return sam_args_fail("sam_build", "--flat and --flat-scaled exclude each other");
    s->map = flat ? SAM_BUILD_MAP_FLAT : flat_scaled ? SAM_BUILD_MAP_FLAT_SCALED : SAM_BUILD_MAP_CUT;
    s->samples_per_vertex = (uint32_t)samples;
    s->cut_budget = (uint32_t)budget;
    s->mc_samples = (uint32_t)mc;
    s->candidates = (uint32_t)candidates;
    s->threads = (int)threads;
    sam_app_catch_interrupts(on_signal);
    job.cancel = &interrupted;
    return sam_app_build_run(&job, "sam_build");
}
