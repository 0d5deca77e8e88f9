/*
 * sam_compare: the SAM paper's evaluation (Sec. 5.1-5.2, Fig. 10-11) on any
 * scene. Renders a dense CPU ground truth of the translucency (sam_truth)
 * and every requested technique with the same front lighting and surface
 * diffusion, writes the images, their differences x4, and a report with
 * PSNR and RMSE; optionally rebuilds the map for several sample counts N
 * and plots RMSE against N with gnuplot. On an animated scene it plays the
 * animation and compares chosen frames, each against a truth of its pose.
 * The work is sam_comparison.h's; this program reads the command line and
 * the scene and checks that the options fit the scene.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_args.h"
#include "sam/sam_comparison.h"
#include "sam/sam_mesh.h"

#define TOOL "sam_compare"
/* --frames: the last frame it plays to. */
#define MAX_FRAME 100000
/* sam_render --animate's default, so the same --frames are the same poses. */
#define DEFAULT_FPS 30.0f

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_compare SCENE.json -o DIR [options]\n"
            "\n"
            "Renders a ground truth of the scene's translucency (dense surface samples, exact\n"
            "visibility by ray casting, the same front lighting and surface diffusion as the\n"
            "techniques) and each technique, and writes to DIR:\n"
            "  truth.exr/.png, TECH.exr/.png             full shading (linear HDR, tonemapped sRGB)\n"
            "  *_translucency.exr/.png                   translucency only (PNG: / the truth's maximum)\n"
            "  TECH_diff4.png, TECH_translucency_diff4.png  |TECH - truth| x 4 of the PNGs\n"
            "  row.png, translucency_row.png             the truth, then each technique, side by side\n"
            "  report.md, report.json                    PSNR and RMSE per technique\n"
            "  rmse_vs_samples.png, sweep.dat            with --samples-sweep\n"
            "With --frames, each frame's files go to DIR/frame_NNNN/ and DIR/report.md, report.json\n"
            "list every frame's scores.\n"
            "\n"
            "options:\n"
            "  --techniques LIST      comma-separated from sam, tsm, transmittance, thickness, none\n"
            "                         (default: all five; thickness measures the local thickness first)\n"
            "  --samples-sweep LIST   rebuild the map with each N in LIST (e.g. 3,5,10,20,50; each\n"
            "                         1..64) and plot SAM's RMSE against N (needs a scene with a mesh\n"
            "                         and gnuplot); a cut map's sweep scores the flat map and the\n"
            "                         flat-scaled baseline with each N beside it\n"
            "  --samples N            back-side samples per vertex of the map SAM is shown with\n"
            "                         (default 16 of a 32-entry cut for a cut map, 3 for a flat one;\n"
            "                         a scene's prebuilt .sam keeps its own)\n"
            "  --map cut|flat|flat-scaled\n"
            "                         the kind of map built for SAM and its sweep (default cut; see\n"
            "                         sam_build --help)\n"
            "  --whole-cut            a cut map stores its whole cut: the cut's budget is N, for the\n"
            "                         map shown and each point of the sweep (default: N fitted from a\n"
            "                         cut of the larger of N and 32, as sam_build does)\n"
            "  --truth-samples N      the ground truth's first surface sample count (default 65536);\n"
            "                         it is doubled (up to 6 times) until doubling changes SAM's\n"
            "                         PSNRs by under 0.5 dB\n"
            "  --truth-tolerance X    far-field tolerance of the truth's sum, in [0, 0.5): distant\n"
            "                         groups of samples count as one where that errs by about X of\n"
            "                         their share (default 0.01; 0 sums every sample)\n"
            "  --frames LIST          for a scene with deformers or keyframes: compare these frames\n"
            "                         (comma-separated, increasing, each 0..100000, at most 16), each\n"
            "                         against a ground truth of its pose. Every frame from 0 to the last\n"
            "                         is played as sam_render --animate plays it (the pose at t = frame / F,\n"
            "                         the sample walk, L_d, T smoothed with dt = 1/F), so SAM is scored as\n"
            "                         a viewer sees it. Without --frames an animated scene compares\n"
            "                         frame 0, the pose at t = 0\n"
            "  --fps F                frames per second of --frames (default 30, as sam_render --animate)\n"
            "  --force                write into a DIR that already holds a report\n"
            "  --cache DIR, --no-cache\n"
            "                         the map cache sam_render and sam_view share (default\n"
            "                         $XDG_CACHE_HOME/sam or ~/.cache/sam); the sweep's maps are built anew\n"
            "  -h, --help             this text\n"
            "PSNR is computed on the tonemapped 8-bit sRGB images over the object's pixels, over\n"
            "the pixels that differ from the truth (as the paper does), and on the translucency\n"
            "images normalised by the truth's maximum. Texture-space depth sizing and culling are\n"
            "turned off for every render: they change the picture, and the comparison should not.\n"
            "\n"
            "examples:\n"
            "  sam_compare scenes/compare_slab_area.json -o cmp_slab --samples-sweep 3,5,10,20\n"
            "  sam_compare scenes/compare_knot.json -o cmp_budget --techniques sam --samples-sweep 8,16,32,64 --whole-cut\n"
            "  sam_compare scenes/ear_twist.json -o cmp_twist --frames 0,15,30 --techniques sam,none\n");
}

static void say(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs(TOOL ": ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* The command line: the scene, --force, and the comparison's settings,
 * whose sweep and frames point into this struct. */
typedef struct options {
    const char *scene_path;
    int force;
    long sweep[SAM_COMPARISON_MAX_SWEEP], frames[SAM_COMPARISON_MAX_FRAMES];
    sam_comparison_settings set;
} options;

/* --techniques: each name of the comma-separated `text` sets requested[t]. */
static int parse_techniques(const char *text, int *requested)
{
    for (const char *p = text; *p;) {
        size_t n = strcspn(p, ",");
        int found = 0;
        for (int t = 0; t < SAM_TRUTH_REPORT_TECHNIQUES; ++t) {
            const char *name = sam_truth_report_technique_name(t);
            if (strlen(name) == n && !strncmp(p, name, n))
                requested[t] = found = 1;
        }
        if (!found)
            return sam_args_fail(TOOL, "--techniques must be sam, tsm, transmittance, thickness or none, got \"%.*s\"",
                                 (int)n, p);
        p += n + (p[n] == ',');
    }
    return SAM_ARGS_OK;
}

/* --samples-sweep and --frames, and the options that exclude each other. */
static int parse_lists(const char *sweep_list, const char *frame_list, int fps_given, options *o)
{
    sam_comparison_settings *set = &o->set;
    if (sweep_list && !sam_args_int_list(sweep_list, 1, 64, o->sweep, SAM_COMPARISON_MAX_SWEEP, &set->sweep_count))
        return sam_args_fail(TOOL,
                             "--samples-sweep must be up to %d comma-separated whole numbers in 1..64, got \"%s\"",
                             SAM_COMPARISON_MAX_SWEEP, sweep_list);
    set->sweep = set->sweep_count ? o->sweep : NULL;
    if (!frame_list)
        return fps_given ? sam_args_fail(TOOL, "--fps sets the times of --frames; give --frames too") : SAM_ARGS_OK;
    if (!sam_args_int_list(frame_list, 0, MAX_FRAME, o->frames, SAM_COMPARISON_MAX_FRAMES, &set->frame_count))
        return sam_args_fail(TOOL, "--frames must be up to %d comma-separated frame numbers in 0..%d, got \"%s\"",
                             SAM_COMPARISON_MAX_FRAMES, MAX_FRAME, frame_list);
    for (int i = 1; i < set->frame_count; ++i)
        if (o->frames[i] <= o->frames[i - 1])
            return sam_args_fail(TOOL, "--frames must increase, got %ld after %ld in \"%s\"", o->frames[i],
                                 o->frames[i - 1], frame_list);
    if (set->sweep_count)
        return sam_args_fail(TOOL, "--samples-sweep rebuilds the rest pose's map; give it without --frames");
    set->frames = o->frames;
    return SAM_ARGS_OK;
}

/* Fills `o` from the command line; returns SAM_ARGS_*. */
static int parse_options(int argc, char **argv, options *o)
{
    const char *techniques = "sam,none,tsm,transmittance,thickness", *sweep_list = NULL, *frame_list = NULL;
    long map_samples = 0, truth_samples = 0;
    int fps_given = 0;
    memset(o, 0, sizeof *o);
    sam_comparison_settings *set = &o->set;
    set->tool = TOOL;
    set->truth_tolerance = 0.01f;
    set->fps = DEFAULT_FPS;
    /* In sam_build_map's order. */
    static const char *const map_names[] = {"cut", "flat", "flat-scaled", NULL};
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &set->out, .value = "DIR", .required = 1},
        {"--out", SAM_ARG_STRING, &set->out, .value = "DIR", .now = "-o"},
        {"--techniques", SAM_ARG_STRING, &techniques, .value = "LIST"},
        {"--samples-sweep", SAM_ARG_STRING, &sweep_list, .value = "LIST"},
        {"--frames", SAM_ARG_STRING, &frame_list, .value = "LIST"},
        {"--fps", SAM_ARG_FLOAT, &set->fps, .lo = 0, .hi = 1000, .lo_open = 1, .value = "F", .given = &fps_given},
        {"--truth-tolerance", SAM_ARG_FLOAT, &set->truth_tolerance, .lo = 0, .hi = 0.5, .hi_open = 1, .value = "X"},
        {"--samples", SAM_ARG_INT, &map_samples, .lo = 1, .hi = 64, .value = "N"},
        {"--map", SAM_ARG_CHOICE, &set->map, .choices = map_names},
        {.name = "--whole-cut", .kind = SAM_ARG_FLAG, .target = &set->whole_cut},
        {"--truth-samples", SAM_ARG_INT, &truth_samples, .lo = 1, .hi = 100000000, .value = "N"},
        {.name = "--force", .kind = SAM_ARG_FLAG, .target = &o->force},
        {"--cache", SAM_ARG_STRING, &set->cache_dir, .value = "DIR"},
        {"--no-cache", SAM_ARG_FLAG, .target = &set->no_cache},
    };
    const sam_args_spec spec = {TOOL, args, sizeof args / sizeof *args, &o->scene_path, 1, 1, "SCENE.json", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r == SAM_ARGS_OK)
        r = parse_techniques(techniques, set->requested);
    if (r == SAM_ARGS_OK)
        r = parse_lists(sweep_list, frame_list, fps_given, o);
    if (r == SAM_ARGS_OK && set->whole_cut && set->map != 0)
        r = sam_args_fail(TOOL, "--whole-cut sets a cut map's budget; give it without --map %s", map_names[set->map]);
    if (r == SAM_ARGS_OK && set->cache_dir && set->no_cache)
        r = sam_args_fail(TOOL, "--cache DIR and --no-cache exclude each other");
    set->map_samples = (uint32_t)map_samples;
    set->truth_samples = (uint64_t)truth_samples;
    return r;
}

int main(int argc, char **argv)
{
    options o;
    int r = parse_options(argc, argv, &o);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    sam_scene scene;
    sam_error err;
    if (sam_mesh_is_mesh_path(o.scene_path)) {
        say("%s is a mesh; sam_compare needs a scene (lights, camera, scale): stage one with sam_render %s "
            "-o preview.png --write-scene SCENE.json and compare that",
            o.scene_path, o.scene_path);
        return 1;
    }
    if (sam_scene_load(o.scene_path, &scene, &err) != SAM_OK) {
        say("%s", err.message);
        return 1;
    }
    int animated = scene.deformer_count || scene.keyframe_count, code = 1;
    if (o.set.sweep_count && !scene.mesh_path) {
        say("%s: --samples-sweep rebuilds the map, so the scene must name a mesh", o.scene_path);
        code = 2;
    } else if (o.set.frames && !animated) {
        say("%s has no \"deformers\" or \"keyframes\": --frames compares frames of an animation (give it without "
            "--frames to compare the scene)",
            o.scene_path);
        code = 2;
    } else if (sam_truth_report_check_dir(o.set.out, o.force, &err) != SAM_OK) {
        say("%s", err.message);
    } else {
        if (animated && !o.set.frames)
            say("note: the scene is animated; comparing frame 0, the pose at t = 0 (--frames LIST [--fps F] picks "
                "the frames)");
        if (sam_comparison_run(&scene, o.scene_path, &o.set, &err) == SAM_OK)
            code = 0;
        else
            say("%s", err.message);
    }
    sam_scene_destroy(&scene);
    return code;
}
