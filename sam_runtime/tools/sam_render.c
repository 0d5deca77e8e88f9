/*
 * sam_render: renders a scene headless (EGL, no display) to an HDR EXR and
 * an optional sRGB PNG, running the SAM passes for N frames.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#include "sam/sam_app.h"
#include "sam/sam_app_scene.h"
#include "sam/sam_runtime_scene.h"

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
            "  --technique sam|none|tsm|transmittance\n"
            "                         translucency technique (default: the scene's): spatial adjacency\n"
            "                         maps, none, d'Eon's translucent shadow maps (needs --diffusion\n"
            "                         texture and usable UVs), or Jimenez's shadow-map transmittance;\n"
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
            "Per-pass GPU times are printed to stderr.\n");
}

/* "culled,clipped,depth-sized" or "none" into the three switches; 0 on a bad name. */
static int parse_optimizations(const char *list, sam_diffusion_options *o)
{
    o->culled = o->clipped = o->depth_sized = 0;
    if (!strcmp(list, "none"))
        return 1;
    const char *p = list;
    while (*p) {
        size_t n = strcspn(p, ",");
        if (n == 6 && !strncmp(p, "culled", n))
            o->culled = 1;
        else if (n == 7 && !strncmp(p, "clipped", n))
            o->clipped = 1;
        else if (n == 11 && !strncmp(p, "depth-sized", n))
            o->depth_sized = 1;
        else
            return 0;
        p += n + (p[n] == ',');
    }
    return 1;
}

/* A whole-string unsigned integer in [lo, hi], else -1. */
static long parse_count(const char *text, long lo, long hi)
{
    char *end;
    long v = strtol(text, &end, 10);
    return *end || end == text || v < lo || v > hi ? -1 : v;
}

static int fail(const char *message)
{
    fprintf(stderr, "sam_render: %s\n", message);
    return 1;
}

static sam_status write_vertices(const char *path, const float *ld, const float *t, uint32_t n, sam_error *err)
{
    sam_atomic_file f;
    sam_status st = sam_atomic_open(&f, path, err);
    if (st != SAM_OK)
        return st;
    fprintf(f.fp, "vertex,ld_r,ld_g,ld_b,t_r,t_g,t_b\n");
    for (uint32_t v = 0; v < n; ++v)
        fprintf(f.fp, "%u,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", v, ld[3 * v], ld[3 * v + 1], ld[3 * v + 2], t[3 * v],
                t[3 * v + 1], t[3 * v + 2]);
    return sam_atomic_commit(&f, err);
}

/* `path` with "_NNNN" before its extension for frame `index` of an
 * animation; `path` itself when index < 0. */
static sam_status numbered(const char *path, long index, char *out, size_t n, sam_error *err)
{
    int len;
    if (index < 0) {
        len = snprintf(out, n, "%s", path);
    } else {
        const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
        if (!dot || (slash && dot < slash))
            dot = path + strlen(path);
        len = snprintf(out, n, "%.*s_%04ld%s", (int)(dot - path), path, index, dot);
    }
    if (len < 0 || (size_t)len >= n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "output path %s is too long", path);
    return SAM_OK;
}

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *out = NULL, *png = NULL, *dump = NULL, *technique = NULL, *diffusion = NULL,
               *kernel = NULL, *optimize = NULL, *tonemap = NULL;
    float exposure = NAN;
    long sss_samples = 0, atlas_size = 0;
    float texels_per_pixel = 0;
    long frames = 1, animate = 0;
    int frames_given = 0;
    float fps = 30.0f;
    float dt = 1.0f / 60.0f;
    int translucency_only = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--translucency-only")) {
            translucency_only = 1;
        } else if (a[0] == '-' && a[1] && !v) {
            fprintf(stderr, "sam_render: %s needs a value (see --help)\n", a);
            return 2;
        } else if (!strcmp(a, "-o")) {
            out = argv[++i];
        } else if (!strcmp(a, "--png")) {
            png = argv[++i];
        } else if (!strcmp(a, "--dump-vertices")) {
            dump = argv[++i];
        } else if (!strcmp(a, "--technique")) {
            technique = argv[++i];
        } else if (!strcmp(a, "--diffusion")) {
            diffusion = argv[++i];
            if (strcmp(diffusion, "none") && strcmp(diffusion, "screen") && strcmp(diffusion, "texture") &&
                strcmp(diffusion, "preintegrated")) {
                fprintf(stderr,
                        "sam_render: --diffusion must be none, screen, texture or preintegrated, got \"%s\"\n",
                        diffusion);
                return 2;
            }
        } else if (!strcmp(a, "--tonemap")) {
            tonemap = argv[++i];
            if (strcmp(tonemap, "aces") && strcmp(tonemap, "reinhard")) {
                fprintf(stderr, "sam_render: --tonemap must be aces or reinhard, got \"%s\"\n", tonemap);
                return 2;
            }
        } else if (!strcmp(a, "--exposure")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !(v >= -32 && v <= 32)) {
                fprintf(stderr, "sam_render: --exposure must be a number of EV in [-32, 32], got \"%s\"\n", argv[i]);
                return 2;
            }
            exposure = (float)v;
        } else if (!strcmp(a, "--sss-kernel")) {
            kernel = argv[++i];
            if (strcmp(kernel, "fit2d") && strcmp(kernel, "marginal") && strcmp(kernel, "eq1")) {
                fprintf(stderr, "sam_render: --sss-kernel must be fit2d, marginal or eq1, got \"%s\"\n", kernel);
                return 2;
            }
        } else if (!strcmp(a, "--sss-samples")) {
            sss_samples = parse_count(argv[++i], 9, 33);
            if (sss_samples < 0 || sss_samples % 2 == 0) {
                fprintf(stderr, "sam_render: --sss-samples must be an odd integer in 9..33, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--atlas-size")) {
            atlas_size = parse_count(argv[++i], 64, 4096);
            if (atlas_size < 0) {
                fprintf(stderr, "sam_render: --atlas-size must be an integer in 64..4096, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--optimize")) {
            optimize = argv[++i];
            sam_diffusion_options probe;
            if (!parse_optimizations(optimize, &probe)) {
                fprintf(stderr,
                        "sam_render: --optimize takes culled, clipped, depth-sized (comma-separated) or none, "
                        "got \"%s\"\n",
                        optimize);
                return 2;
            }
        } else if (!strcmp(a, "--texels-per-pixel")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !(v > 0 && v <= 16)) {
                fprintf(stderr, "sam_render: --texels-per-pixel must be a number in (0, 16], got \"%s\"\n",
                        argv[i]);
                return 2;
            }
            texels_per_pixel = (float)v;
        } else if (!strcmp(a, "--animate")) {
            animate = parse_count(argv[++i], 1, 100000);
            if (animate < 0) {
                fprintf(stderr, "sam_render: --animate must be a number of frames in 1..100000, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--fps")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !(v > 0 && v <= 1000)) {
                fprintf(stderr, "sam_render: --fps must be a number in (0, 1000], got \"%s\"\n", argv[i]);
                return 2;
            }
            fps = (float)v;
        } else if (!strcmp(a, "--frames")) {
            char *end;
            frames = strtol(argv[++i], &end, 10);
            frames_given = 1;
            if (*end || frames < 1 || frames > 100000) {
                fprintf(stderr, "sam_render: --frames must be in 1..100000, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(a, "--dt")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !(v >= 0 && isfinite((float)v))) {
                fprintf(stderr, "sam_render: --dt must be a finite number >= 0, got \"%s\"\n", argv[i]);
                return 2;
            }
            dt = (float)v;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "sam_render: unknown option \"%s\" (see --help)\n", a);
            return 2;
        } else if (!scene_path) {
            scene_path = a;
        } else {
            fprintf(stderr, "sam_render: unexpected argument \"%s\"\n", a);
            return 2;
        }
    }
    if (!scene_path || !out) {
        usage(stderr);
        return 2;
    }
    if (animate && frames_given) {
        fprintf(stderr, "sam_render: --frames is for still pictures; --animate renders one picture per frame\n");
        return 2;
    }
    static const char *const techniques[] = {"sam", "none", "tsm", "transmittance"};
    int use_technique = -1;
    for (int k = 0; technique && k < 4; ++k)
        if (!strcmp(technique, techniques[k]))
            use_technique = k;
    if (technique && use_technique < 0) {
        fprintf(stderr, "sam_render: --technique must be sam, none, tsm or transmittance, got \"%s\"\n", technique);
        return 2;
    }
    sam_error err;
    sam_scene scene;
    if (sam_scene_load(scene_path, &scene, &err) != SAM_OK)
        return fail(err.message);
    const int posed = scene.deformer_count || scene.keyframe_count;
    if (animate && !posed) {
        sam_scene_destroy(&scene);
        fprintf(stderr, "sam_render: %s has no \"deformers\" or \"keyframes\" to animate\n", scene_path);
        return 1;
    }
    /* techniques[] follows sam_technique's order. */
    sam_technique chosen = technique ? (sam_technique)use_technique : scene.technique;
    int use_sam = chosen == SAM_TECHNIQUE_SAM;
    if (diffusion)
        scene.diffusion = !strcmp(diffusion, "screen")          ? SAM_DIFFUSION_SCREEN
                          : !strcmp(diffusion, "preintegrated") ? SAM_DIFFUSION_PREINTEGRATED
                          : !strcmp(diffusion, "none")          ? SAM_DIFFUSION_NONE
                                                                : SAM_DIFFUSION_TEXTURE;
    if (chosen == SAM_TECHNIQUE_TSM && scene.diffusion != SAM_DIFFUSION_TEXTURE) {
        sam_scene_destroy(&scene);
        return fail("the tsm technique needs texture-space diffusion (--diffusion texture or the scene's "
                    "\"diffusion\": \"texture\")");
    }
    samfile_data sam;
    sam_profile profile;
    float mm_per_unit;
    double built_seconds;
    if (sam_app_scene_object(&scene, NULL, NULL, NULL, &sam, &profile, &mm_per_unit, &built_seconds, &err) !=
        SAM_OK) {
        sam_scene_destroy(&scene);
        return fail(err.message);
    }
    if (!scene.sam_path)
        fprintf(stderr, "sam_render: built the map of %s (%u vertices) in %.2f s\n", scene.mesh_path,
                sam.vertex_count, built_seconds);
    int code = 1;
    sam_gl_context *gl = NULL;
    sam_runtime *rt = NULL;
    sam_image img = {0};
    float *ld = NULL, *t = NULL;
    char warning[512];
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK ||
        sam_runtime_create(&sam, &profile, mm_per_unit, &rt, &err) != SAM_OK ||
        sam_runtime_scene_setup(rt, &scene, NULL, NULL, warning, sizeof warning, &err) != SAM_OK ||
        sam_runtime_scene_keyframes(rt, &scene, &sam, &err) != SAM_OK)
        goto done;
    if (warning[0])
        fprintf(stderr, "sam_render: warning: %s\n", warning);
    sam_render_view view;
    sam_runtime_scene_view(rt, &scene, &view, warning, sizeof warning);
    if (chosen == SAM_TECHNIQUE_TSM && view.diffusion != 3) {
        char reason[160];
        sam_runtime_uv_status(rt, reason, sizeof reason);
        sam_fail(&err, SAM_ERR_UNSUPPORTED, "the tsm technique needs texture-space diffusion, which cannot run: %s",
                 reason);
        goto done;
    }
    if (warning[0])
        fprintf(stderr, "sam_render: warning: %s\n", warning);
    view.front = !translucency_only;
    view.technique = chosen;
    if (kernel)
        view.options.sss_kernel = !strcmp(kernel, "eq1")        ? SAM_SSS_KERNEL_EQ1
                                  : !strcmp(kernel, "marginal") ? SAM_SSS_KERNEL_MARGINAL
                                                                : SAM_SSS_KERNEL_FIT2D;
    if (sss_samples)
        view.options.sss_samples = (uint32_t)sss_samples;
    if (atlas_size)
        view.options.atlas_size = (uint32_t)atlas_size;
    if (optimize)
        parse_optimizations(optimize, &view.options);
    if (texels_per_pixel > 0)
        view.options.texels_per_pixel = texels_per_pixel;
    sam_tonemap curve = tonemap ? (!strcmp(tonemap, "reinhard") ? SAM_TONEMAP_REINHARD : SAM_TONEMAP_ACES)
                                : scene.tonemap;
    /* A still picture is the pose at time 0 after `frames` passes; an
     * animation one picture per frame, each frame a new pose. */
    long pictures = animate ? animate : 1, passes = animate ? 1 : frames;
    float step = animate ? 1.0f / fps : dt;
    for (long picture = 0; picture < pictures; ++picture) {
        for (long f = 0; f < passes; ++f) {
            long frame = animate ? picture : f;
            if (posed && (frame == 0 || animate) &&
                (sam_runtime_deform(rt, (float)picture / fps, &err) != SAM_OK || sam_runtime_walk(rt, &err) != SAM_OK))
                goto done;
            if (sam_runtime_irradiance(rt, &err) != SAM_OK)
                goto done;
            if (use_sam && sam_runtime_translucency(rt, scene.samples_per_vertex, step, frame == 0, &err) != SAM_OK)
                goto done;
        }
        char exr_path[4096], png_path[4096];
        if (numbered(out, animate ? picture : -1, exr_path, sizeof exr_path, &err) != SAM_OK ||
            (png && numbered(png, animate ? picture : -1, png_path, sizeof png_path, &err) != SAM_OK))
            goto done;
        sam_image_destroy(&img);
        if (sam_runtime_render(rt, &view, &img, &err) != SAM_OK ||
            sam_image_write_picture(&img, exr_path, png ? png_path : NULL, curve,
                                    isnan(exposure) ? scene.exposure : exposure, &err) != SAM_OK)
            goto done;
        if (animate)
            fprintf(stderr, "\rsam_render: frame %ld of %ld%s", picture + 1, animate, picture + 1 == animate ? "\n" : "");
    }
    if (dump) {
        ld = malloc((size_t)sam.vertex_count * 3 * sizeof *ld);
        t = malloc((size_t)sam.vertex_count * 3 * sizeof *t);
        if (!ld || !t) {
            sam_fail(&err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the vertex dump");
            goto done;
        }
        if (sam_runtime_read_irradiance(rt, ld, &err) != SAM_OK || sam_runtime_read_translucency(rt, t, &err) != SAM_OK ||
            write_vertices(dump, ld, t, sam.vertex_count, &err) != SAM_OK)
            goto done;
    }
    double diffusion_ms = sam_runtime_pass_ms(rt, SAM_PASS_DIFFUSION);
    fprintf(stderr, "sam_render: %s: %ux%u, %u vertices, %ld frame%s; GPU ms: irradiance %.3f, translucency %.3f, "
                    "shade %.3f, diffusion %.3f (%s)\n",
            out, scene.width, scene.height, sam.vertex_count, animate ? animate : frames,
            (animate ? animate : frames) == 1 ? "" : "s",
            sam_runtime_pass_ms(rt, SAM_PASS_IRRADIANCE), use_sam ? sam_runtime_pass_ms(rt, SAM_PASS_TRANSLUCENCY) : 0.0,
            sam_runtime_pass_ms(rt, SAM_PASS_SHADE), diffusion_ms > 0 ? diffusion_ms : 0.0,
            sam_gl_context_info(gl)->renderer);
    code = 0;
done:
    if (code)
        fprintf(stderr, "sam_render: %s\n", err.message);
    free(ld);
    free(t);
    sam_image_destroy(&img);
    sam_runtime_destroy(rt);
    sam_gl_context_destroy(gl);
    samfile_free(&sam);
    sam_scene_destroy(&scene);
    return code;
}
