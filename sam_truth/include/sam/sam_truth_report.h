/*
 * sam_truth_report: how renders are judged against the ground truth and
 * what a comparison writes (the SAM paper's Sec. 5.2, Fig. 10-11).
 *
 * Scores. Every render is a pair: the full shading and the translucency
 * alone, both linear HDR RGBA. A reference (sam_truth_report_reference_make)
 * is the truth as every score sees it: its display image (tonemapped with
 * the scene's curve over black), its translucency divided by its maximum and
 * clamped to [0, 1], and its alpha as the object's mask.
 * sam_truth_report_score compares a pair with it through
 * sam_image_compare_srgb8: PSNR and RMSE in 8-bit sRGB levels over the
 * object's pixels, and over the pixels that differ only (as the paper does).
 *
 * Outputs, into one folder: NAME.exr/.png of the truth and each technique,
 * |TECH - truth| x 4 of the PNGs, the side-by-side rows, report.json and
 * report.md of one pose, sweep.dat and rmse_vs_samples.png (gnuplot) of a
 * samples sweep, and the summary of an animation's frames.
 *
 * This module is part of the sam_truth library and, like it, needs no GL:
 * it works on images and numbers, so it is tested without a context. The
 * renders themselves come from sam_comparison.h.
 *
 * Errors are reported as sam_status with a message in `err` (may be NULL).
 */
#ifndef SAM_TRUTH_REPORT_H
#define SAM_TRUTH_REPORT_H

#include <stdint.h>

#include "sam/sam_common.h"
#include "sam/sam_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The techniques a comparison knows, indexed by sam_technique: sam, none,
 * tsm, transmittance, thickness. */
#define SAM_TRUTH_REPORT_TECHNIQUES 5
/* Doubling the truth's samples is converged once SAM's PSNRs move by less. */
#define SAM_TRUTH_REPORT_CONVERGED_DB 0.5

/* Technique t's name as scene files write it (sam_technique_name: "sam",
 * "none", "tsm", "transmittance", "thickness"); t in
 * [0, SAM_TRUTH_REPORT_TECHNIQUES). */
const char *sam_truth_report_technique_name(int t);

/* The images and scores of one technique. */
typedef struct sam_truth_report_technique {
    int requested, available;
    char reason[SAM_ERROR_MESSAGE_SIZE]; /* why not available */
    sam_image full, translucency;        /* linear HDR RGBA; owned by whoever fills them */
    sam_image_comparison all, normalised;
} sam_truth_report_technique;

/* One truth of the doubling: its sample count and time, and SAM's PSNRs
 * against it (NAN when SAM was not rendered or the truth has no
 * translucency). */
typedef struct sam_truth_report_step {
    uint64_t samples;
    double seconds, sam_psnr_db, sam_psnr_normalised_db;
} sam_truth_report_step;

/* SAM's scores with the map rebuilt at n samples per vertex; for a cut
 * map's sweep also the flat map's and the flat-scaled baseline's with the
 * same n, to plot beside it. */
typedef struct sam_truth_report_sweep_point {
    long n;
    uint32_t cut_budget; /* the cut map's entries per vertex the n samples were fitted from; 0: not a cut map */
    double build_seconds;
    sam_image_comparison all, normalised;
    int has_flat; /* 1: flat_* and scaled_* hold scores */
    sam_image_comparison flat_all, flat_normalised;
    sam_image_comparison scaled_all, scaled_normalised;
} sam_truth_report_sweep_point;

/* What report.json and report.md of one pose say. The pointers are the
 * caller's; nothing is copied or freed. */
typedef struct sam_truth_report {
    const char *scene_path;  /* the report names its base name */
    uint32_t width, height;  /* of the view */
    uint32_t vertex_count, samples_per_vertex;
    const char *map;         /* the kind of map SAM was scored with ("cut", "flat", "flat-scaled"; "" unknown) */
    double build_seconds;    /* of the map */
    int diffusion;           /* the view's, 0..3: none, screen, preintegrated, texture */
    int animated;            /* 1: frame and fps are reported */
    long frame;
    float fps;
    float truth_tolerance;   /* the truth's far-field tolerance */
    const sam_truth_report_technique *techniques; /* SAM_TRUTH_REPORT_TECHNIQUES; scores only are read */
    const sam_truth_report_technique *self;       /* the truth scored against itself */
    const sam_truth_report_step *steps;           /* step_count >= 1; the last is the truth used */
    int step_count, converged;
    float truth_max;         /* the truth's translucency maximum the normalised images use */
    double translucency_share; /* the truth's translucency over all its light (sums of RGB over the picture) */
    const char *space;       /* where the truth was evaluated: "pixel" or "atlas texel" */
    const sam_truth_report_sweep_point *sweep;    /* sweep_count; NULL when 0 */
    int sweep_count, monotonic;
} sam_truth_report;

/* What an animation's summary keeps of one compared frame. */
typedef struct sam_truth_report_pose {
    long frame;
    uint64_t truth_samples;
    int converged;
    sam_truth_report_technique techniques[SAM_TRUTH_REPORT_TECHNIQUES]; /* scores only: images are zeroed */
} sam_truth_report_pose;

/* The truth as every score sees it; made once per truth. */
typedef struct sam_truth_report_reference {
    const sam_image *mask;   /* the truth's full render (alpha: the object); the caller's */
    float max;               /* the translucency divides by this */
    sam_tonemap tonemap;     /* the display curve and exposure (EV) of every score */
    float exposure;
    sam_image shown, norm;   /* the truth's display and normalised translucency (RGB); owned */
} sam_truth_report_reference;

/* The largest colour value over the pixels of RGBA `img` whose alpha is
 * > 0; 0 when there are none. */
float sam_truth_report_max_value(const sam_image *img);

/* Makes `ref` from the truth's RGBA pair (same size) and its translucency
 * maximum `max` > 0. `full` must outlive `ref` (it is the mask). On failure
 * `ref` holds nothing to destroy.
 * Errors: those of sam_image_tonemap and sam_image_create. */
sam_status sam_truth_report_reference_make(sam_tonemap tonemap, float exposure, const sam_image *full,
                                           const sam_image *translucency, float max,
                                           sam_truth_report_reference *ref, sam_error *err);

/* Frees what `ref` owns; a zeroed `ref` is fine. */
void sam_truth_report_reference_destroy(sam_truth_report_reference *ref);

/* Scores the RGBA pair `full`, `translucency` (the reference's size)
 * against `ref` into `all` and `normalised`. The pair's display and
 * normalised images (RGB) go to `shown` and `norm` when not NULL, and the
 * caller destroys them; on failure they are left alone.
 * Errors: those of sam_image_tonemap, sam_image_create and
 * sam_image_compare_srgb8 (no object pixel in the mask). */
sam_status sam_truth_report_score(const sam_truth_report_reference *ref, const sam_image *full,
                                  const sam_image *translucency, sam_image_comparison *all,
                                  sam_image_comparison *normalised, sam_image *shown, sam_image *norm, sam_error *err);

/* Scores every available technique of `techniques`
 * (SAM_TRUTH_REPORT_TECHNIQUES; fills their all and normalised) against
 * `ref`, made from `truth_full` and `truth_translucency`, and writes into
 * the existing folder `dir`: truth.exr/.png, truth_translucency.exr/.png,
 * and per technique TECH.exr/.png, TECH_diff4.png,
 * TECH_translucency.exr/.png, TECH_translucency_diff4.png, then row.png and
 * translucency_row.png (the truth, then the techniques in order).
 * Errors: SAM_ERR_INVALID_ARGUMENT (a path too long), those of the scores
 * and of the image writers. */
sam_status sam_truth_report_write_images(const char *dir, sam_truth_report_technique *techniques,
                                         const sam_image *truth_full, const sam_image *truth_translucency,
                                         const sam_truth_report_reference *ref, sam_error *err);

/* Writes dir/report.json and dir/report.md of `report`, each atomically.
 * Errors: SAM_ERR_INVALID_ARGUMENT (a path too long), SAM_ERR_IO. */
sam_status sam_truth_report_write(const char *dir, const sam_truth_report *report, sam_error *err);

/* Writes dir/sweep.dat and dir/sweep.gnuplot and runs gnuplot on the
 * latter for dir/rmse_vs_samples.png, titled with the base name of
 * `mesh_path` (NULL: "scene"). `sweep` has `count` points.
 * Errors: SAM_ERR_INVALID_ARGUMENT (a path too long), SAM_ERR_IO (a write,
 * gnuplot missing or failing: the message says which). */
sam_status sam_truth_report_plot_sweep(const char *dir, const char *mesh_path,
                                       const sam_truth_report_sweep_point *sweep, int count, sam_error *err);

/* The name of frame `frame`'s folder, frame_NNNN (as sam_render --animate
 * numbers frames), into `out` of `n` bytes (32 is enough). */
void sam_truth_report_frame_dir(char *out, size_t n, long frame);

/* Writes dir/report.json and dir/report.md of an animation: every frame of
 * `poses` (count >= 1, the techniques requested in poses[0] are the
 * columns) with its scores and a link to its frame folder; times are
 * frame / fps. Written last by a run, so one that stops halfway leaves no
 * report.json.
 * Errors: SAM_ERR_INVALID_ARGUMENT (a path too long), SAM_ERR_IO. */
sam_status sam_truth_report_write_summary(const char *dir, const char *scene_path, float fps,
                                          const sam_truth_report_pose *poses, int count, sam_error *err);

/* "dir/name" into `out` of `n` bytes.
 * Errors: SAM_ERR_INVALID_ARGUMENT when it does not fit. */
sam_status sam_truth_report_path(char *out, size_t n, const char *dir, const char *name, sam_error *err);

/* Checks an output folder before any work: it may be missing (it is made
 * later, by sam_truth_report_make_dir, so a run that fails early leaves
 * nothing), or a folder; one that holds a report.json is refused unless
 * `force`, so a finished comparison is not overwritten by accident.
 * Errors: SAM_ERR_IO (not a folder, unreadable, holds a report). */
sam_status sam_truth_report_check_dir(const char *dir, int force, sam_error *err);

/* Creates folder `dir` unless it exists. Errors: SAM_ERR_IO. */
sam_status sam_truth_report_make_dir(const char *dir, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
