/*
 * sam_render: renders a scene file or a bare mesh headless (EGL, no
 * display) to a PNG or an HDR EXR, running the SAM passes for N frames; the
 * job itself is sam_app_render_run.
 */
#include <float.h>
#include <stdio.h>

#include "sam/sam_app_render.h"
#include "sam/sam_scene.h"
#include "sam/sam_args.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_render MESH|SCENE.json -o OUT.png|OUT.exr [options]\n"
            "\n"
            "Renders headless (no window, no display): a tonemapped sRGB PNG or a linear HDR EXR\n"
            "(RGBA float), by the output's extension, written atomically.\n"
            "\n"
            "A bare mesh (.obj, .ply, .off, .stl, .gltf, .glb) needs no scene file: it is framed from\n"
            "the front, its own texture (an OBJ's map_Kd, a glTF's base colour) is its albedo, it is lit\n"
            "by a key light in front and a back light placed where the camera sees the most light\n"
            "come through, and exposed from the picture; each assumption is printed. Its map is built\n"
            "once and cached (shared with sam_view and sam_compare).\n"
            "  --material M           a preset (skin, marble, wholemilk, ...) or a profile file (default skin)\n"
            "  --size-mm D            the mesh's bounding-box diagonal in mm, or\n"
            "  --mm-per-unit X        millimetres per model unit (neither: a size is chosen at which\n"
            "                         the thinnest parts glow, and said loudly)\n"
            "  --up AXIS              the mesh's up axis, +X, -X, +Y, -Y, +Z or -Z (default: +Z where the\n"
            "                         mesh is clearly tallest along Z, else +Y; said either way)\n"
            "  --angle DEG            turn the camera about the up axis from the front (default 0)\n"
            "  --write-scene S.json   save the scene used (camera, lights, exposure) to edit and re-render\n"
            "  --cache DIR, --no-cache  the map cache (default $XDG_CACHE_HOME/sam or ~/.cache/sam)\n"
            "\n"
            "Either input:\n"
            "  --size WxH             picture size in pixels (default: the scene's, or 1280x720)\n"
            "  --turntable N          N pictures OUT_0000.png ... with camera and lights turned about the\n"
            "                         object, 360/N degrees apart\n"
            "  --beside TECHNIQUE     put the same view with another technique (none, to see what the\n"
            "                         translucency adds) to the right of each picture, same exposure\n"
            "  --png OUT.png          with an EXR output, also a tonemapped PNG\n"
            "  --tonemap aces|reinhard, --exposure EV\n"
            "                         the PNG's tone curve and exposure (default: the scene's; a bare\n"
            "                         mesh's is read from the picture)\n"
            "  --passes N             frames of the SAM passes run before a still picture (default 1)\n"
            "  --animate N            render N frames of the scene's deformers and keyframes instead: OUT_0000.png,\n"
            "                         OUT_0001.png, ..., the pose, the sample walk, L_d and smoothed\n"
            "                         translucency updated every frame\n"
            "  --fps F                frames per second of --animate (default 30; dt = 1/F)\n"
            "  --dt S                 frame time in seconds for temporal smoothing (default 1/60)\n"
            "  --technique sam|none|tsm|transmittance|thickness\n"
            "                         translucency technique (default: the scene's, else sam): spatial\n"
            "                         adjacency maps, none, d'Eon's translucent shadow maps (needs\n"
            "                         --diffusion texture and usable UVs), Jimenez's shadow-map\n"
            "                         transmittance, or local thickness (GDC 2011; measured first);\n"
            "                         tsm and transmittance use the point, spot and directional lights\n"
            "                         that cast shadows, never area lights or the environment\n"
            "  --translucency-only    the translucency alone, without front lighting\n"
            "  --diffusion none|screen|texture|preintegrated\n"
            "                         surface diffusion (default: the scene's, else screen): screen-space\n"
            "                         separable SSS, texture-space sum of Gaussians (meshes without UVs, or\n"
            "                         whose UVs overlap or leave [0,1], fall back to screen space with a\n"
            "                         warning), or pre-integrated skin\n"
            "  --sss-kernel fit2d|marginal|eq1\n"
            "                         screen-space kernel: the separable fit of the 2D profile (default),\n"
            "                         each channel's 1D marginal, or Jimenez's eq. 1\n"
            "  --sss-samples N        screen-space taps per pass, odd, 9..33 (default 17)\n"
            "  --atlas-size N         texture-space atlas side, 64..4096 (default 1024)\n"
            "  --optimize LIST        texture-space optimisations, comma-separated from culled, clipped,\n"
            "                         depth-sized, or none (default: the scene's, else clipped)\n"
            "  --texels-per-pixel X   depth-sized atlas density at the nearest point (default 1)\n"
            "  --dump-vertices FILE   write per-vertex L_d and T as CSV\n"
            "  --force                replace existing outputs (without it they are refused before any work)\n"
            "Per-pass GPU times are printed to stderr.\n"
            "\n"
            "examples (from the repository root; meshes/ and scenes/ are bundled):\n"
            "  sam_render meshes/ear.obj --material skin --size-mm 60 -o ear.png --beside none\n"
            "  sam_render meshes/knot.obj --material marble --size-mm 50 --turntable 8 -o turn.png \\\n"
            "      --write-scene knot.json\n"
            "  sam_render meshes/blobs.obj --material wholemilk --size-mm 40 --up -Z --angle 90 -o blobs.png\n"
            "  sam_render scenes/ear_backlit.json -o ear.exr --png ear.png\n"
            "  sam_render your_scan.ply --material skin --size-mm 250 -o scan.png   (a mesh of your own)\n");
}

int main(int argc, char **argv)
{
    static const char *const techniques[] = {"sam", "none", "tsm", "transmittance", "thickness", NULL};
    static const char *const diffusions[] = {"screen", "texture", "preintegrated", "none", NULL};
    static const char *const kernels[] = {"fit2d", "marginal", "eq1", NULL};
    static const char *const tonemaps[] = {"aces", "reinhard", NULL};
    static const char odd_taps[] = "an odd integer in 9..33";
    sam_app_render_job job;
    sam_app_render_defaults(&job);
    int frames_given = 0;
    const char *size = NULL, *up = NULL;
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &job.out, .value = "OUT.png|OUT.exr", .required = 1},
        {"--material", SAM_ARG_STRING, &job.material, .value = "M"},
        {"--size-mm", SAM_ARG_FLOAT, &job.size_mm, .lo = 0, .hi = FLT_MAX, .lo_open = 1, .value = "D"},
        {"--mm-per-unit", SAM_ARG_FLOAT, &job.mm_per_unit, .lo = 0, .hi = FLT_MAX, .lo_open = 1, .value = "X"},
        {"--angle", SAM_ARG_FLOAT, &job.angle_deg, .lo = -360, .hi = 360, .value = "DEG"},
        {"--up", SAM_ARG_STRING, &up, .value = "AXIS"},
        {"--size", SAM_ARG_STRING, &size, .value = "WxH"},
        {"--write-scene", SAM_ARG_STRING, &job.write_scene, .value = "S.json"},
        {"--beside", SAM_ARG_CHOICE, &job.beside, .choices = techniques},
        {"--turntable", SAM_ARG_INT, &job.turntable, .lo = 1, .hi = 3600, .must = "a number of pictures in 1..3600"},
        {"--cache", SAM_ARG_STRING, &job.cache_dir, .value = "DIR"},
        {"--no-cache", SAM_ARG_FLAG, .target = &job.no_cache},
        {"--force", SAM_ARG_FLAG, .target = &job.force},
        {"--png", SAM_ARG_STRING, &job.png, .value = "OUT.png"},
        {"--dump-vertices", SAM_ARG_STRING, &job.dump, .value = "FILE"},
        {"--technique", SAM_ARG_CHOICE, &job.technique, .choices = techniques},
        {"--diffusion", SAM_ARG_CHOICE, &job.diffusion, .choices = diffusions},
        {"--tonemap", SAM_ARG_CHOICE, &job.tonemap, .choices = tonemaps},
        {"--exposure", SAM_ARG_FLOAT, &job.exposure, .lo = -32, .hi = 32, .must = "a number of EV in [-32, 32]"},
        {"--sss-kernel", SAM_ARG_CHOICE, &job.sss_kernel, .choices = kernels},
        {"--sss-samples", SAM_ARG_INT, &job.sss_samples, .lo = 9, .hi = 33, .must = odd_taps},
        {"--atlas-size", SAM_ARG_INT, &job.atlas_size, .lo = 64, .hi = 4096},
        {"--optimize", SAM_ARG_STRING, &job.optimize, .value = "LIST"},
        {"--texels-per-pixel", SAM_ARG_FLOAT, &job.texels_per_pixel, .lo = 0, .hi = 16, .lo_open = 1},
        {"--animate", SAM_ARG_INT, &job.animate, .lo = 1, .hi = 100000, .must = "a number of frames in 1..100000"},
        {"--fps", SAM_ARG_FLOAT, &job.fps, .lo = 0, .hi = 1000, .lo_open = 1},
        {"--passes", SAM_ARG_INT, &job.frames, .lo = 1, .hi = 100000, .given = &frames_given},
        {"--frames", SAM_ARG_INT, &job.frames, .lo = 1, .hi = 100000, .given = &frames_given, .now = "--passes"},
        {"--dt", SAM_ARG_FLOAT, &job.dt, .lo = 0, .hi = FLT_MAX, .must = "a finite number >= 0"},
        {"--translucency-only", SAM_ARG_FLAG, .target = &job.translucency_only},
    };
    const sam_args_spec spec = {"sam_render", args, sizeof args / sizeof *args, &job.scene_path, 1, 1,
                                "MESH or SCENE.json", usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (size && !sam_args_size(size, &job.width, &job.height))
        return sam_args_fail("sam_render", "--size must be WxH with each in 1..%d, got \"%s\"",
                             SAM_SCENE_MAX_RESOLUTION, size);
    if (sam_args_up("sam_render", up, &job.up) != SAM_ARGS_OK)
        return SAM_ARGS_BAD;
    if (job.size_mm && job.mm_per_unit)
        return sam_args_fail("sam_render", "--size-mm and --mm-per-unit say the same thing: give one");
    if (job.cache_dir && job.no_cache)
        return sam_args_fail("sam_render", "--cache DIR and --no-cache exclude each other");
    if (job.sss_samples && job.sss_samples % 2 == 0)
        return sam_args_fail("sam_render", "--sss-samples must be %s, got \"%ld\"", odd_taps, job.sss_samples);
    if (job.optimize && !sam_app_render_parse_optimizations(job.optimize, NULL))
        return sam_args_fail("sam_render",
                             "--optimize takes culled, clipped, depth-sized (comma-separated) or none, got \"%s\"",
                             job.optimize);
    if (job.animate && frames_given)
        return sam_args_fail("sam_render", "--passes is for still pictures; --animate renders one picture per frame");
    sam_error err;
    if (sam_app_render_run(&job, "sam_render", &err) != SAM_OK) {
        fprintf(stderr, "sam_render: %s\n", err.message);
        return 1;
    }
    return 0;
}
