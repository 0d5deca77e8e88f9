/*
 * sam_render: renders a scene headless (EGL, no display) to an HDR EXR and
 * an optional sRGB PNG, running the SAM passes for N frames; the job itself
 * is sam_app_render_run.
 */
#include <float.h>
#include <stdio.h>

#include "sam/sam_app_render.h"
#include "sam/sam_args.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_render SCENE.json -o OUT.exr [options]\n"
            "\n"
            "Renders the scene headless (no window, no display) at its resolution and writes the\n"
            "linear HDR image (RGBA float EXR, written atomically).\n"
            "  --png OUT.png          also write a tonemapped sRGB preview (the scene's tonemap/exposure)\n"
            "  --tonemap aces|reinhard, --exposure EV\n"
            "                         the PNG's tone curve and exposure (default: the scene's)\n"
            "  --frames N             frames to run the SAM passes before the picture (default 1)\n"
            "  --animate N            render N frames of the scene's deformers and keyframes instead: OUT_0000.exr,\n"
            "                         OUT_0001.exr, ... (and PNGs likewise), the pose, the sample walk,\n"
            "                         L_d and smoothed translucency updated every frame\n"
            "  --fps F                frames per second of --animate (default 30; dt = 1/F)\n"
            "  --dt S                 frame time in seconds for temporal smoothing (default 1/60)\n"
            "  --technique sam|none|tsm|transmittance|thickness\n"
            "                         translucency technique (default: the scene's): spatial adjacency\n"
            "                         maps, none, d'Eon's translucent shadow maps (needs --diffusion\n"
            "                         texture and usable UVs), Jimenez's shadow-map transmittance, or\n"
            "                         local thickness (GDC 2011; the thickness is measured first);\n"
            "                         tsm and transmittance use the point, spot and directional lights\n"
            "                         that cast shadows, never area lights or the environment\n"
            "  --translucency-only    the translucency alone, without front lighting\n"
            "  --diffusion none|screen|texture|preintegrated\n"
            "                         surface diffusion (default: the scene's): screen-space separable\n"
            "                         SSS, texture-space sum of Gaussians (meshes without UVs, or whose\n"
            "                         UVs overlap or leave [0,1], fall back to screen space with a\n"
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
            "A scene naming a mesh builds its .sam first (N = 3, the scene's material and scale).\n"
            "Per-pass GPU times are printed to stderr.\n"
            "\n"
            "examples:\n"
            "  sam_render scenes/ear_backlit.json -o ear.exr --png ear.png\n"
            "  sam_render scenes/ear_twist.json -o twist.exr --png twist.png --animate 30\n"
            "  sam_render scenes/compare_head.json -o head.exr --technique transmittance --translucency-only\n");
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
    const sam_arg args[] = {
        {"-o", SAM_ARG_STRING, &job.out, .value = "OUT.exr", .required = 1},
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
        {"--frames", SAM_ARG_INT, &job.frames, .lo = 1, .hi = 100000, .given = &frames_given},
        {"--dt", SAM_ARG_FLOAT, &job.dt, .lo = 0, .hi = FLT_MAX, .must = "a finite number >= 0"},
        {"--translucency-only", SAM_ARG_FLAG, .target = &job.translucency_only},
    };
    const sam_args_spec spec = {"sam_render", args, sizeof args / sizeof *args, &job.scene_path, 1, 1, "SCENE.json",
                                usage};
    int r = sam_args_parse(&spec, argc, argv);
    if (r != SAM_ARGS_OK)
        return r == SAM_ARGS_EXIT ? 0 : 2;
    if (job.sss_samples && job.sss_samples % 2 == 0)
        return sam_args_fail("sam_render", "--sss-samples must be %s, got \"%ld\"", odd_taps, job.sss_samples);
    if (job.optimize && !sam_app_render_parse_optimizations(job.optimize, NULL))
        return sam_args_fail("sam_render",
                             "--optimize takes culled, clipped, depth-sized (comma-separated) or none, got \"%s\"",
                             job.optimize);
    if (job.animate && frames_given)
        return sam_args_fail("sam_render", "--frames is for still pictures; --animate renders one picture per frame");
    sam_error err;
    if (sam_app_render_run(&job, "sam_render", &err) != SAM_OK) {
        fprintf(stderr, "sam_render: %s\n", err.message);
        return 1;
    }
    return 0;
}
