/*
 * sam_app_render: sam_render's job as a library call: a scene file, or a
 * bare mesh staged by sam_app_stage, rendered headless to a PNG or an HDR
 * EXR: a still picture after N frames of the SAM passes, one picture per
 * frame of its animation, or a turntable around the object.
 *
 * Step by step, sam_app_render_run: checks the outputs can be written,
 * loads the scene (or stages the mesh, printing each assumption), reads or
 * builds its map (the shared cache, sam_app_cache.h), makes a headless GL
 * context and a runtime, applies the scene and the job's overrides, runs
 * the frames, writes the pictures (and the per-vertex CSV and the scene
 * used), and prints one summary line with the GPU times on stderr. Links
 * the runtime and the builder.
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
    const char *scene_path;  /* the scene file, or a bare mesh (.obj, .ply, .off, .stl, .gltf, .glb) to stage (required) */
    const char *out;         /* the picture (required): .png (tonemapped sRGB) or .exr (linear HDR); with
                              * animate or turntable, OUT_0000.png, ... */
    const char *png;         /* a tonemapped PNG beside an EXR, or NULL */
    const char *material;    /* a bare mesh's material (NULL: skin); not with a scene file */
    float size_mm;           /* a bare mesh's bounding-box diagonal in mm; 0: not given */
    float mm_per_unit;       /* a bare mesh's scale; 0: not given (neither: chosen, sam_app_stage.h) */
    float angle_deg;         /* a bare mesh's camera turn about up from the front */
    int up;                  /* a bare mesh's up axis: -1 guessed (sam_app_stage.h); else a sam_up_axis */
    uint32_t width, height;  /* the picture in pixels; 0: the scene's */
    const char *write_scene; /* the scene rendered (with the exposure used) saved here, or NULL */
    long turntable;          /* 0: none; else this many pictures with camera and lights turned about the
                              * vertical through the camera's target, 360 / turntable degrees apart */
    int beside;              /* -1: none; else a sam_technique rendered of the same frame and put to the
                              * right of each picture, at the same exposure */
    const char *cache_dir;   /* the map cache (NULL: sam_app_cache_dir's default) */
    int force;               /* 1: replace existing outputs (else they are refused before any work) */
    int no_cache;            /* 1: build a bare mesh's map without the cache */
    const char *dump;        /* per-vertex L_d and T (the thickness technique's own T with it) as CSV, or NULL */
    int technique;           /* -1: the scene's; else a sam_technique */
    int diffusion;           /* -1: the scene's; else a sam_diffusion */
    int sss_kernel;          /* -1: the scene's; else a sam_sss_kernel */
    long sss_samples;        /* 0: the scene's; else odd, 9..33 */
    long atlas_size;         /* 0: the scene's; else 64..4096 */
    const char *optimize;    /* NULL: the scene's; else "none" or culled,clipped,depth-sized */
    float texels_per_pixel;  /* 0: the scene's */
    int tonemap;             /* -1: the scene's; else a sam_tonemap */
    float exposure;          /* NAN: the scene's, or for a bare mesh read from the first picture */
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
 * Errors: SAM_ERR_INVALID_ARGUMENT (an output that cannot be written or
 * whose extension is not .png or .exr, checked before any work; a
 * material or size given with a scene file; an animation of a scene that
 * does not move; animate with turntable; the tsm technique without
 * texture-space diffusion), and those of sam_scene_load,
 * sam_app_stage_scene, sam_app_cache_object, sam_app_thickness, the GL
 * context, the runtime and the writers; nothing is left half-written. */
sam_status sam_app_render_run(const sam_app_render_job *job, const char *tool, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
