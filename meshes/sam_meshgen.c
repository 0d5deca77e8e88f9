/*
 * sam_meshgen: writes a procedural test mesh (sam_shape) as OBJ or PLY.
 *
 *   sam_meshgen SHAPE -o OUT.obj|OUT.ply [--resolution N] [--extent S]
 *               [--depth D] [--thickness T] [--count N] [--seed S]
 *               [--ascii] [--force]
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sam/sam_args.h"
#include "sam/sam_shape.h"

static void usage(FILE *out)
{
    size_t n;
    const char *const *names = sam_shape_names(&n);
    fprintf(out,
            "usage: sam_meshgen SHAPE -o OUT.obj|OUT.ply [options]\n"
            "Writes a closed triangle mesh with UVs (seam vertices split, positions\n"
            "bit-identical across seams). OBJ stores each position once; PLY stores\n"
            "render vertices (x y z u v). Output is written atomically.\n\n"
            "shapes (units are arbitrary; mm/unit is a suggested scale for sam_build):\n");
    for (size_t k = 0; k < n; ++k) {
        const sam_shape_info *info = sam_shape_find(names[k]);
        fprintf(out, "  %-10s %s\n             resolution = %s (min %d); mm/unit %g\n", info->name,
                info->summary, info->resolution_means, info->min_resolution,
                info->suggested_mm_per_unit);
    }
    fprintf(out, "\noptions (defaults per shape in brackets):\n"
                 "  -o, --output PATH   .obj or .ply (required)\n");
    static const struct {
        const char *option, *text;
        unsigned uses;
    } rows[] = {{"--resolution N", "segments along the main direction", 0},
                {"--extent S", "overall size in model units, > 0", 0},
                {"--depth D", "slab depth, > 0", SAM_SHAPE_USES_DEPTH},
                {"--thickness T", "shell thickness or tube diameter", SAM_SHAPE_USES_THICKNESS},
                {"--count N", "number of blobs, or holes along each side", SAM_SHAPE_USES_COUNT},
                {"--seed S", "blobs' random seed (unsigned 64-bit)", SAM_SHAPE_USES_SEED}};
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; ++r) {
        fprintf(out, "  %-19s %s [", rows[r].option, rows[r].text);
        int first = 1;
        for (size_t k = 0; k < n; ++k) {
            const sam_shape_info *info = sam_shape_find(names[k]);
            if (rows[r].uses && !(info->uses & rows[r].uses))
                continue;
            sam_shape_params p;
            sam_shape_default_params(names[k], &p, NULL);
            fprintf(out, "%s%s ", first ? "" : ", ", names[k]);
            first = 0;
            switch (r) {
            case 0: fprintf(out, "%d", p.resolution); break;
            case 1: fprintf(out, "%g", p.size); break;
            case 2: fprintf(out, "%g", p.depth); break;
            case 3: fprintf(out, "%.4g", p.thickness); break;
            case 4: fprintf(out, "%d", p.count); break;
            default: fprintf(out, "%llu", (unsigned long long)p.seed); break;
            }
        }
        fprintf(out, "]\n");
    }
    fprintf(out, "  --ascii             ASCII PLY instead of binary little-endian\n"
                 "  --force             overwrite OUT if it exists\n"
                 "  -h, --help          this text;  --version  the version\n"
                 "\n"
                 "examples:\n"
                 "  sam_meshgen ear -o ear.obj\n"
                 "  sam_meshgen knot -o knot.ply --resolution 256 --force\n");
}

/* Usage errors: one line, exit status 2. */
static int fail(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

static int fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "sam_meshgen: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (try --help)\n");
    va_end(ap);
    return 2;
}

static int parse_int(const char *opt, const char *text, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (!text[0] || *end || errno || v < INT_MIN || v > INT_MAX)
        return fail("%s: \"%s\" is not an integer", opt, text);
    *out = (int)v;
    return 0;
}

static int parse_double(const char *opt, const char *text, double *out)
{
    if (!sam_parse_double(text, out))
        return fail("%s: \"%s\" is not a finite number", opt, text);
    return 0;
}

static int parse_u64(const char *opt, const char *text, uint64_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(text, &end, 10);
    if (!text[0] || text[0] == '-' || *end || errno)
        return fail("%s: \"%s\" is not an unsigned integer", opt, text);
    *out = (uint64_t)v;
    return 0;
}

static const char *const value_options[6] = {"--resolution", "--extent", "--depth", "--thickness", "--count", "--seed"};

/* The options given (values[k] for value_options[k], NULL when absent)
 * into `p`, with a note for each the shape does not use. Returns 0, or the
 * exit code of a bad value. */
static int apply_values(const char *shape, const sam_shape_info *info, const char *const values[6],
                        sam_shape_params *p)
{
    static const unsigned slot_uses[6] = {0, 0, SAM_SHAPE_USES_DEPTH, SAM_SHAPE_USES_THICKNESS,
                                          SAM_SHAPE_USES_COUNT, SAM_SHAPE_USES_SEED};
    for (int k = 0; k < 6; ++k) {
        if (!values[k])
            continue;
        if (slot_uses[k] && !(info->uses & slot_uses[k]))
            fprintf(stderr, "sam_meshgen: note: %s is not used by %s, ignored\n",
                    value_options[k], shape);
        int bad = 0;
        switch (k) {
        case 0: bad = parse_int(value_options[k], values[k], &p->resolution); break;
        case 1: bad = parse_double(value_options[k], values[k], &p->size); break;
        case 2: bad = parse_double(value_options[k], values[k], &p->depth); break;
        case 3: bad = parse_double(value_options[k], values[k], &p->thickness); break;
        case 4: bad = parse_int(value_options[k], values[k], &p->count); break;
        default: bad = parse_u64(value_options[k], values[k], &p->seed); break;
        }
        if (bad)
            return bad;
    }
    return 0;
}

/* Generates the shape, writes it as OBJ or PLY and prints a summary. */
static int write_mesh(const char *shape, const sam_shape_info *info, const sam_shape_params *params,
                      const char *output, int ply, int ascii)
{
    sam_shape_mesh mesh;
    sam_error err;
    const sam_status made = sam_shape_generate(shape, params, &mesh, &err);
    if (made != SAM_OK) {
        /* A value out of the shape's range is a bad option: usage, exit 2. */
        fprintf(stderr, "sam_meshgen: %s%s\n", err.message, made == SAM_ERR_INVALID_ARGUMENT ? " (try --help)" : "");
        return made == SAM_ERR_INVALID_ARGUMENT ? 2 : 1;
    }
    sam_status s = ply ? sam_shape_write_ply(output, &mesh, !ascii, &err)
                       : sam_shape_write_obj(output, &mesh, &err);
    if (s != SAM_OK) {
        fprintf(stderr, "sam_meshgen: %s\n", err.message);
        sam_shape_mesh_destroy(&mesh);
        return 1;
    }
    /* Positions are counted for the summary only; skip them if memory is short. */
    char positions[64] = "";
    uint32_t *ids = malloc((size_t)mesh.vertex_count * sizeof *ids);
    uint32_t unique = 0;
    if (ids && sam_shape_weld(&mesh, ids, &unique, NULL) == SAM_OK)
        snprintf(positions, sizeof positions, " (%u positions)", unique);
    free(ids);
    fprintf(stderr,
            "sam_meshgen: wrote %s: %s, %u vertices%s, %u triangles; suggested mm per unit %g\n",
            output, shape, mesh.vertex_count, positions, mesh.triangle_count,
            info->suggested_mm_per_unit);
    sam_shape_mesh_destroy(&mesh);
    return 0;
}

int main(int argc, char **argv)
{
    const char *shape = NULL, *output = NULL;
    const char *values[6] = {0}; /* resolution size depth thickness count seed */
    int ascii = 0, force = 0;
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &output, .value = "OUT.obj|OUT.ply"},
        {"--output", SAM_ARG_STRING, &output, .value = "OUT.obj|OUT.ply"},
        {"--resolution", SAM_ARG_STRING, &values[0], .value = "N"},
        {"--extent", SAM_ARG_STRING, &values[1], .value = "S"},
        {"--size", SAM_ARG_STRING, &values[1], .value = "S", .now = "--extent"},
        {"--depth", SAM_ARG_STRING, &values[2], .value = "D"},
        {"--thickness", SAM_ARG_STRING, &values[3], .value = "T"},
        {"--count", SAM_ARG_STRING, &values[4], .value = "C"},
        {"--seed", SAM_ARG_STRING, &values[5], .value = "S"},
        {"--ascii", SAM_ARG_FLAG, .target = &ascii},
        {"--force", SAM_ARG_FLAG, .target = &force},
    };
    const sam_args_spec spec = {"sam_meshgen", args, sizeof args / sizeof *args, &shape, 0, 1, "SHAPE", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (!shape)
        return fail("no shape given");
    const sam_shape_info *info = sam_shape_find(shape);
    if (!info)
        return fail("unknown shape \"%s\"", shape);
    if (!output)
        return fail("no output given: -o OUT.obj or OUT.ply");
    int ply = sam_path_has_extension(output, ".ply");
    if (!ply && !sam_path_has_extension(output, ".obj"))
        return fail("output \"%s\" must end in .obj or .ply", output);

    sam_shape_params p;
    sam_shape_default_params(shape, &p, NULL);
    int bad = apply_values(shape, info, values, &p);
    if (bad)
        return bad;
    if (ascii && !ply)
        fprintf(stderr, "sam_meshgen: note: --ascii applies to PLY only, ignored\n");
    struct stat st;
    if (!force && stat(output, &st) == 0)
        return fail("%s exists; pass --force to overwrite it", output);

    return write_mesh(shape, info, &p, output, ply, ascii);
}
