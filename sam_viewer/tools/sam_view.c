/*
 * sam_view: the real-time viewer. A GLFW window (OpenGL 4.3 core) on the
 * runtime sam_render uses: orbit the camera, drag the lights, switch the
 * translucency technique, the diffusion, the samples per vertex and the
 * view mode, play deformations, and take screenshots that sam_render
 * reproduces. `--script FILE` drives it with timed input (sam_view_script.h).
 *
 * The program reads its options and hands over: the scene and map come from
 * sam_viewer_load.h, the window from sam_viewer_window.h, and what input does
 * from the state machine in sam_viewer.h.
 */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>

#include "sam/sam_app_cache.h"
#include "sam/sam_args.h"
#include "sam/sam_viewer_load.h"
#include "sam/sam_viewer_window.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_view SCENE.json | FILE.sam | MESH [options]\n"
            "\n"
            "Shows the object in a window with real-time SAM translucency. A bare mesh (.obj, .ply,\n"
            ".off, .stl, .gltf, .glb) or a scene naming only a mesh has its map built first, with a progress bar,\n"
            "and cached (a cached map is used again while the mesh's SHA-256, the material, the scale\n"
            "and N match; sam_render and sam_compare share the cache). A bare mesh gets sam_render's\n"
            "staging: framed, a key light in front and a back light where the most light comes\n"
            "through, each assumption printed. A .sam is lit from behind and dimly from the front.\n"
            "options:\n"
            "  --material M         material of a bare mesh (a preset or a profile file; default skin)\n"
            "  --size-mm D          a bare mesh's bounding-box diagonal in mm (default: chosen so that\n"
            "                       its thinnest parts glow, and said so)\n"
            "  --up AXIS            a bare mesh's up axis, +X, -X, +Y, -Y, +Z or -Z (default: +Z where\n"
            "                       it is clearly tallest along Z, else +Y; said either way)\n"
            "  --environment E.exr  a lat-long environment for a bare mesh or .sam\n"
            "  --truth T.exr        a ground-truth image for the difference view (same camera and size)\n"
            "  --size WxH           window size in pixels (default: the scene's resolution, at most\n"
            "                       1600x1000)\n"
            "  --shot PREFIX        screenshot names: PREFIX_0001.exr/.png/.json ... (default sam_view)\n"
            "  --cache DIR          where built maps are kept (default $XDG_CACHE_HOME/sam or\n"
            "                       ~/.cache/sam)\n"
            "  --no-cache           build without reading or writing the cache\n"
            "  --script FILE        timed key and mouse events (see docs/viewer.md)\n"
            "  --fps F              a fixed clock: every frame advances time by 1/F, however long it\n"
            "                       took (frame-exact scripts and animation); default: the wall clock\n"
            "  -h, --help           this help\n"
            "\n"
            "mouse:\n"
            "  left drag            orbit the camera about its target\n"
            "  right drag           pan (shift + left drag too)\n"
            "  wheel                zoom\n"
            "  middle drag          move the selected light around the object (ctrl + left drag too)\n"
            "keys:\n"
            "  F                    frame the whole object\n"
            "  L                    select the next light\n"
            "  = / -                selected light's intensity x1.25 / /1.25\n"
            "  C                    selected light's colour: white, warm, cool, red, green, blue\n"
            "  E                    environment on / off;  , and .  rotate it by 15 degrees\n"
            "  T                    technique: sam, none, tsm, transmittance, thickness\n"
            "  D                    diffusion: screen, texture, pre-integrated, none\n"
            "  [ and ]              fewer / more samples per vertex (of those the .sam holds)\n"
            "  S                    temporal smoothing on / off\n"
            "  SPACE                play / pause the animation (scenes with deformers or keyframes)\n"
            "  V                    view: final, translucency only, irradiance, samples under the\n"
            "                       cursor as lines, difference to --truth\n"
            "  P or F12             screenshot (EXR, PNG and a scene file sam_render reproduces)\n"
            "  H or F1              this help in the window\n"
            "  ESCAPE or Q          quit\n"
            "The title bar shows frames per second and each pass's GPU milliseconds.\n"
            "\n"
            "examples:\n"
            "  sam_view meshes/ear.obj --material skin --size-mm 60\n"
            "  sam_view scenes/ear_twist.json --fps 30 --shot shots/ear\n");
}

typedef struct options {
    const char *input, *material, *environment, *truth, *shot, *cache, *script, *size, *up;
    sam_app_stage_options stage; /* a bare mesh's size and up axis */
    float fps;
    int width, height, no_cache;
} options;

/* Returns SAM_ARGS_*: the options into `o`, their defaults where not given. */
static int parse_options(int argc, char **argv, options *o)
{
    *o = (options){.shot = "sam_view"};
    sam_app_stage_defaults(&o->stage);
    const sam_arg args[] = {
        {"--material", SAM_ARG_STRING, &o->material, .value = "M"},
        {"--size-mm", SAM_ARG_FLOAT, &o->stage.size_mm, .lo = 0, .hi = FLT_MAX, .lo_open = 1, .value = "D",
         .must = "a positive number"},
        {"--up", SAM_ARG_STRING, &o->up, .value = "AXIS"},
        {"--environment", SAM_ARG_STRING, &o->environment, .value = "E.exr"},
        {"--truth", SAM_ARG_STRING, &o->truth, .value = "T.exr"},
        {"--size", SAM_ARG_STRING, &o->size, .value = "WxH"},
        {"--shot", SAM_ARG_STRING, &o->shot, .value = "PREFIX"},
        {"--cache", SAM_ARG_STRING, &o->cache, .value = "DIR"},
        {.name = "--no-cache", .kind = SAM_ARG_FLAG, .target = &o->no_cache},
        {"--script", SAM_ARG_STRING, &o->script, .value = "FILE"},
        {"--fps", SAM_ARG_FLOAT, &o->fps, .lo = 0, .hi = 1000, .lo_open = 1, .value = "F"},
    };
    const sam_args_spec spec = {"sam_view", args, sizeof args / sizeof args[0], &o->input, 1, 1,
                                "SCENE.json | FILE.sam | MESH", usage};
    int r = sam_args_parse(&spec, argc, argv);
    uint32_t w, h;
    if (r == SAM_ARGS_OK && o->size) {
        if (!sam_args_size(o->size, &w, &h) || w < 16 || h < 16)
            return sam_args_fail("sam_view", "--size must be WxH with each in 16..16384, got \"%s\"", o->size);
        o->width = (int)w, o->height = (int)h;
    }
    if (r == SAM_ARGS_OK)
        r = sam_args_up("sam_view", o->up, &o->stage.up);
    return r;
}

int main(int argc, char **argv)
{
    options o;
    int r = parse_options(argc, argv, &o);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    sam_viewer_window w;
    sam_viewer_window_init(&w, o.shot);
    sam_error err;
    sam_view_event *events = NULL;
    size_t event_count = 0;
    sam_viewer_input kind = SAM_VIEWER_INPUT_SCENE;
    int code = 1;
    sam_status st = SAM_OK;
    if (o.script)
        st = sam_view_script_load(o.script, &events, &event_count, &err);
    if (st == SAM_OK)
        st = sam_viewer_load_scene(o.input, o.material, &o.stage, o.environment, &w.state.scene, &kind, &err);
    char cache_dir[4096];
    sam_app_cache_dir(o.cache, cache_dir, sizeof cache_dir);
    sam_profile profile;
    float mm_per_unit;
    if (st == SAM_OK)
        st = sam_app_cache_object(&w.state.scene, NULL, cache_dir, !o.no_cache, "sam_view", &w.sam, &profile,
                                  &mm_per_unit, NULL, &err);
    const sam_viewer_window_options window = {o.width, o.height, kind == SAM_VIEWER_INPUT_SAM,
                                              kind == SAM_VIEWER_INPUT_MESH, o.truth};
    if (st == SAM_OK)
        st = sam_viewer_window_open(&w, &window, &profile, mm_per_unit, &err);
    if (st == SAM_OK) {
        if (!events)
            fprintf(stderr, "sam_view: press H for help\n");
        code = sam_viewer_window_run(&w, events, event_count, o.fps);
    } else {
        fprintf(stderr, "sam_view: %s\n", err.message);
    }
    free(events);
    sam_viewer_window_destroy(&w);
    return code;
}
