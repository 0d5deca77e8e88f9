/*
 * sam_app_render: sam_render's job as a library call: a scene file rendered
 * headless to an HDR EXR (and a PNG), a still picture after N frames of the
 * SAM passes or one picture per frame of its animation.
 *
 * Step by step, sam_app_render_run: loads the scene, reads or builds its map
 * (sam_app_scene_object), makes a headless GL context and a runtime, applies
 * the scene and the job's overrides, runs the frames, writes the pictures
 * (and the per-vertex CSV), and prints one summary line with the GPU times
 * on stderr. Links the runtime and the builder.
 */
#ifndef SAM_APP_RENDER_H
#define SAM_APP_RENDER_H

#include "sam/sam_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What to render and how; sam_app_render_defaults fills the defaults. A
 * field at its "from the scene" value leaves the scene's setting alone. */
typedef struct sam_app_render_job {
    const char *scene_path;  /* the scene file (required) */
    const char *out;         /* the EXR (required); with animate, OUT_0000.exr, ... */
    const char *png;         /* a tonemapped PNG beside it, or NULL */
    const char *dump;        /* per-vertex L_d and T (the thickness technique's own T with it) as CSV, or NULL */
    int technique;           /* -1: the scene's; else a sam_technique */
    int diffusion;           /* -1: the scene's; else a sam_diffusion */
    int sss_kernel;          /* -1: the scene's; else a sam_sss_kernel */
    long sss_samples;        /* 0: the scene's; else odd, 9..33 */
    long atlas_size;         /* 0: the scene's; else 64..4096 */
    const char *optimize;    /* NULL: the scene's; else "none" or culled,clipped,depth-sized */
    float texels_per_pixel;  /* 0: the scene's */
    int tonemap;             /* -1: the scene's; else a sam_tonemap */
    float exposure;          /* NAN: the scene's */
    long frames;             /* passes before a still picture, >= 1 (default 1) */
    long animate;            /* 0: a still picture; else pictures of the animation */
    float fps;               /* frames per second of the animation (default 30) */
    float dt;                /* frame time for temporal smoothing of a still (default 1/60) */
    int translucency_only;   /* 1: no front lighting */
} sam_app_render_job;

void sam_app_render_defaults(sam_app_render_job *job);

/* 1 when `list` ("none", or a comma-separated subset of culled, clipped,
 * depth-sized) names texture-space optimisations; sets the three switches
 * of `options` (may be NULL: only checks). 0 on a bad name. */
int sam_app_render_parse_optimizations(const char *list, sam_diffusion_options *options);

/* Runs `job`; progress and warnings go to stderr prefixed with `tool`. The
 * thickness technique has its local thickness measured first
 * (sam_app_thickness.h).
 * Errors: SAM_ERR_INVALID_ARGUMENT (an animation of a scene that does not
 * move, the tsm technique without texture-space diffusion), and those of
 * sam_scene_load, sam_app_scene_object, sam_app_thickness, the GL context,
 * the runtime and the writers; nothing is left half-written. */
sam_status sam_app_render_run(const sam_app_render_job *job, const char *tool, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
