/*
 * sam_comparison: the SAM paper's evaluation (Sec. 5.1-5.2, Fig. 10-11) of
 * one scene, as sam_compare runs it. It builds (or reads) the scene's map,
 * renders every requested technique with the GL runtime, evaluates a
 * ground truth of the pose on the CPU (sam_truth) at the pixels (or atlas
 * texels) the runtime shows, doubling its samples until SAM's scores move
 * by under SAM_TRUTH_REPORT_CONVERGED_DB, and writes the images, scores and
 * reports of sam_truth_report.h. Optionally it rebuilds the map for several
 * sample counts N and plots SAM's RMSE against N; on an animated scene it
 * plays the animation and compares chosen frames, each against a truth of
 * its pose.
 *
 * Why a library of its own (sam_comparison) rather than part of sam_truth:
 * it needs a GL context and the runtime (sam_runtime) and reads or builds a
 * scene's map (sam_app_scene.h in sam_app_build, on the builder), while
 * the truth and the scoring and reports stay a CPU library that a test or
 * another program links without GL.
 *
 * Every render turns texture-space depth sizing and culling off: they
 * change the picture, and the comparison should not.
 */
#ifndef SAM_COMPARISON_H
#define SAM_COMPARISON_H

#include <stdint.h>

#include "sam/sam_common.h"
#include "sam/sam_scene.h"
#include "sam/sam_truth_report.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most entries of sweep and frames. */
#define SAM_COMPARISON_MAX_SWEEP 16
#define SAM_COMPARISON_MAX_FRAMES 16

typedef struct sam_comparison_settings {
    const char *tool;        /* prefixes the progress and messages on stderr ("sam_compare"); NULL: silent */
    const char *out;         /* the output folder; made on the first image (sam_truth_report_check_dir first) */
    int requested[SAM_TRUTH_REPORT_TECHNIQUES]; /* 1: render and score technique t */
    uint32_t map_samples;    /* back-side samples per vertex of a map that is built; 0: the builder's default */
    int map;                 /* sam_build_map of a map that is built (and of the sweep's): 0 is the cut map */
    int whole_cut;           /* 1: a cut map that is built (and each of the sweep's) stores its whole cut, the
                              * cut's budget equal to N; 0: the builder's budget (the larger of N and 32) */
    uint64_t truth_samples;  /* the truth's first sample count; 0: SAM_TRUTH_MIN_SAMPLES */
    float truth_tolerance;   /* the truth's far-field tolerance, in [0, 0.5) */
    float fps;               /* > 0: frames are at t = frame / fps, and T is smoothed with dt = 1 / fps */
    const long *sweep;       /* sweep_count (<= SAM_COMPARISON_MAX_SWEEP) sample counts in 1..64 to rebuild
                              * the map with; needs a scene with a mesh and no frames; NULL when 0 */
    int sweep_count;
    const long *frames;      /* frame_count (1..SAM_COMPARISON_MAX_FRAMES) increasing frames to compare, each
                              * into out/frame_NNNN/, with a summary in out; NULL: frame 0 into out itself */
    int frame_count;
    const char *cache_dir;   /* where the map of a scene naming only a mesh is cached (sam_app_cache.h);
                              * NULL: the default; the sweep's maps are not cached */
    int no_cache;            /* 1: build that map without the cache */
} sam_comparison_settings;

/* Runs the comparison of `scene` (loaded from `scene_path`, which the
 * reports name) by `settings`, in a headless GL context of its own. Every
 * frame up to the last one compared is played as sam_render --animate
 * plays it (the pose at t = frame / fps, the sample walk, L_d, T smoothed
 * with dt = 1 / fps), so SAM is scored as a viewer sees it. Nothing is
 * written before the first image is ready.
 * Errors: SAM_ERR_INVALID_ARGUMENT (fps not > 0, too many sweep counts or
 * frames); those of sam_app_scene_object, the GL context, the runtime,
 * sam_truth and the writers of sam_truth_report.h; SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_comparison_run(const sam_scene *scene, const char *scene_path, const sam_comparison_settings *settings,
                              sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
