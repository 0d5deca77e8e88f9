/* One scene's comparison against the ground truth (sam_comparison.h). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sam/sam_app_cache.h"
#include "sam/sam_app_scene.h"
#include "sam/sam_app_thickness.h"
#include "sam/sam_comparison.h"
#include "sam/sam_runtime_scene.h"
#include "sam/sam_truth.h"

#define TECHNIQUES SAM_TRUTH_REPORT_TECHNIQUES
/* Doublings of the truth's samples before giving up on converging: from the
 * library's smallest count to its largest. */
#define MAX_DOUBLINGS 6

typedef struct compare_state {
    const sam_comparison_settings *set;
    const char *scene_path;
    const sam_scene *scene;
    const char *dir; /* where this pose's files go: set->out, or set->out/frame_NNNN */
    samfile_data sam;
    sam_profile profile;
    float mm_per_unit;
    double build_seconds;
    sam_gl_context *gl;
    sam_runtime *rt;
    sam_render_view view;
    float sh[9][3];
    int has_environment;
    sam_truth_scene truth_scene;
    int animated; /* the scene has deformers or keyframes */
    long frame;   /* the frame compared, when animated */
    sam_truth_report_technique results[TECHNIQUES];
} compare_state;

static void say(const compare_state *s, const char *fmt, ...)
{
    if (!s->set->tool)
        return;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", s->set->tool);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* Progress every 10% on one rewritten line on a terminal; into a log, a
 * line when a stage is done. */
typedef struct progress_state {
    const char *tool; /* NULL: silent */
    const char *what;
    int last_decile;
} progress_state;

static void progress_line(progress_state *p, const char *stage, double fraction)
{
    int decile = (int)(fraction * 10.0);
    if (!p->tool || decile == p->last_decile)
        return;
    p->last_decile = decile;
    if (isatty(STDERR_FILENO))
        fprintf(stderr, "\r%s: %s%s%s %3.0f%%%s", p->tool, p->what, stage ? ": " : "", stage ? stage : "",
                100.0 * fraction, fraction >= 1.0 ? "\n" : "");
    else if (fraction >= 1.0)
        fprintf(stderr, "%s: %s%s%s done\n", p->tool, p->what, stage ? ": " : "", stage ? stage : "");
}

static void truth_progress(void *user, const char *stage, double fraction)
{
    progress_line(user, stage, fraction);
}

static int build_progress(void *user, uint64_t done, uint64_t total)
{
    progress_line(user, NULL, total ? (double)done / (double)total : 1.0);
    return 0;
}

static float rho_dt_of(const void *user, float n_dot_l)
{
    return sam_runtime_rho_dt(user, n_dot_l);
}

/* Renders `view` on `rt` with `technique`, or with `override` as the
 * translucency when not NULL: full shading and translucency only. */
static sam_status render_pair(sam_runtime *rt, const sam_render_view *view, sam_technique technique,
                              const sam_image *override, sam_image *full, sam_image *translucency, sam_error *err)
{
    sam_render_view v = *view;
    v.technique = technique;
    v.translucency = override;
    v.front = 1;
    sam_status st = sam_runtime_render(rt, &v, full, err);
    if (st != SAM_OK)
        return st;
    v.front = 0;
    st = sam_runtime_render(rt, &v, translucency, err);
    if (st != SAM_OK)
        sam_image_destroy(full);
    return st;
}

/* The truth's translucency at every covered pixel (screen) or texel
 * (atlas) of the G-buffer, as an override image for sam_runtime_render. */
static sam_status evaluate_truth(compare_state *s, const sam_image *positions, const sam_image *normals,
                                 uint64_t samples, sam_image *out, uint64_t *used_samples, double *seconds,
                                 sam_error *err)
{
    size_t n = (size_t)positions->width * positions->height, count = 0;
    for (size_t i = 0; i < n; ++i)
        count += positions->pixels[i * 4 + 3] > 0;
    float *p = malloc((count ? count : 1) * 3 * sizeof *p), *nrm = malloc((count ? count : 1) * 3 * sizeof *nrm),
          *t = malloc((count ? count : 1) * 3 * sizeof *t);
    sam_truth *truth = NULL;
    sam_status st = SAM_OK;
    if (!p || !nrm || !t) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "ground truth: out of memory for %zu query points", count);
        goto done;
    }
    for (size_t i = 0, q = 0; i < n; ++i)
        if (positions->pixels[i * 4 + 3] > 0) {
            memcpy(p + 3 * q, positions->pixels + i * 4, 3 * sizeof *p);
            memcpy(nrm + 3 * q, normals->pixels + i * 4, 3 * sizeof *nrm);
            ++q;
        }
    char what[64];
    snprintf(what, sizeof what, "ground truth (%llu samples)", (unsigned long long)samples);
    progress_state ps = {s->set->tool, what, -1};
    sam_truth_settings settings;
    sam_truth_default_settings(&settings);
    settings.sample_count = samples;
    settings.far_field_tolerance = s->set->truth_tolerance;
    settings.progress = truth_progress;
    settings.progress_user = &ps;
    if ((st = sam_truth_create(&s->truth_scene, &settings, &truth, err)) != SAM_OK)
        goto done;
    ps.last_decile = -1;
    if ((st = sam_truth_translucency(truth, count, p, nrm, t, err)) != SAM_OK)
        goto done;
    *used_samples = sam_truth_sample_count(truth);
    *seconds = sam_truth_seconds(truth);
    if ((st = sam_image_create(out, positions->width, positions->height, 4, err)) != SAM_OK)
        goto done;
    for (size_t i = 0, q = 0; i < n; ++i) {
        float *o = out->pixels + i * 4;
        if (positions->pixels[i * 4 + 3] > 0) {
            memcpy(o, t + 3 * q, 3 * sizeof *o);
            o[3] = 1;
            ++q;
        } else {
            o[0] = o[1] = o[2] = o[3] = 0;
        }
    }
done:
    sam_truth_destroy(truth);
    free(p);
    free(nrm);
    free(t);
    return st;
}

/* The truth of this pose and how it was reached. */
typedef struct truth_result {
    sam_image full, translucency; /* rendered with the truth as the translucency */
    sam_truth_report_step steps[MAX_DOUBLINGS + 1];
    int step_count, converged;
} truth_result;

/* SAM's PSNRs against the candidate truth `full`, `translucency` into
 * `step`; NAN when SAM is not rendered or the candidate has no
 * translucency. */
static sam_status score_step(const compare_state *s, const sam_image *full, const sam_image *translucency,
                             sam_truth_report_step *step, sam_error *err)
{
    const sam_truth_report_technique *sam_r = &s->results[SAM_TECHNIQUE_SAM];
    float max = sam_truth_report_max_value(translucency);
    step->sam_psnr_db = step->sam_psnr_normalised_db = NAN;
    if (!sam_r->available || !(max > 0))
        return SAM_OK;
    sam_truth_report_reference ref;
    sam_image_comparison all, norm;
    sam_status st = sam_truth_report_reference_make(s->scene->tonemap, s->scene->exposure, full, translucency, max,
                                                    &ref, err);
    if (st != SAM_OK)
        return st;
    st = sam_truth_report_score(&ref, &sam_r->full, &sam_r->translucency, &all, &norm, NULL, NULL, err);
    sam_truth_report_reference_destroy(&ref);
    if (st == SAM_OK) {
        step->sam_psnr_db = all.psnr_db;
        step->sam_psnr_normalised_db = norm.psnr_db;
    }
    return st;
}

/* Doubles the truth's samples from the first count until the SAM scores
 * move by under SAM_TRUTH_REPORT_CONVERGED_DB: the truth is then converged
 * for what the report measures. On failure `out` holds nothing. */
static sam_status converge_truth(compare_state *s, const sam_image *positions, const sam_image *normals,
                                 truth_result *out, sam_error *err)
{
    memset(out, 0, sizeof *out);
    uint64_t samples = s->set->truth_samples ? s->set->truth_samples : SAM_TRUTH_MIN_SAMPLES;
    for (;;) {
        sam_truth_report_step *step = &out->steps[out->step_count];
        sam_image override = {0}, full = {0}, translucency = {0};
        sam_status st = evaluate_truth(s, positions, normals, samples, &override, &step->samples, &step->seconds, err);
        if (st == SAM_OK)
            st = render_pair(s->rt, &s->view, SAM_TECHNIQUE_SAM, &override, &full, &translucency, err);
        sam_image_destroy(&override);
        if (st == SAM_OK)
            st = score_step(s, &full, &translucency, step, err);
        sam_image_destroy(&out->full);
        sam_image_destroy(&out->translucency);
        out->full = full;
        out->translucency = translucency;
        if (st != SAM_OK) {
            sam_image_destroy(&out->full);
            sam_image_destroy(&out->translucency);
            return st;
        }
        say(s, "ground truth with %llu samples: %.2f s; SAM PSNR %.2f dB, translucency %.2f dB",
            (unsigned long long)step->samples, step->seconds, step->sam_psnr_db, step->sam_psnr_normalised_db);
        ++out->step_count;
        if (out->step_count > 1) {
            const sam_truth_report_step *prev = &out->steps[out->step_count - 2];
            double d1 = fabs(step->sam_psnr_db - prev->sam_psnr_db);
            double d2 = fabs(step->sam_psnr_normalised_db - prev->sam_psnr_normalised_db);
            /* Without SAM in the run (or no translucency at all) there is
             * nothing to converge for: one doubling is all we check. */
            if (!(d1 >= SAM_TRUTH_REPORT_CONVERGED_DB) && !(d2 >= SAM_TRUTH_REPORT_CONVERGED_DB)) {
                out->converged = 1;
                return SAM_OK;
            }
        }
        if (out->step_count == MAX_DOUBLINGS + 1) {
            say(s, "warning: the ground truth still moves by 0.5 dB or more after %d doublings; the report says so",
                MAX_DOUBLINGS);
            return SAM_OK;
        }
        samples = 2 * step->samples;
    }
}

/* The builder's settings of a sweep's map of kind `map` with n samples
 * per vertex. */
static void sweep_settings(const compare_state *s, sam_build_map map, long n, sam_build_settings *settings)
{
    sam_build_default_settings(settings);
    settings->map = map;
    settings->samples_per_vertex = (uint32_t)n;
    if (s->set->whole_cut)
        settings->cut_budget = (uint32_t)n;
}

/* Builds the scene's map of kind `map` with n samples per vertex and
 * scores SAM with it against `ref`. */
static sam_status score_map(const compare_state *s, const sam_truth_report_reference *ref, sam_build_map map,
                            long n, double *build_seconds, sam_image_comparison *all,
                            sam_image_comparison *normalised, sam_error *err)
{
    char what[96];
    snprintf(what, sizeof what, "sweep: building the %s map with N = %ld", sam_build_map_name(map), n);
    progress_state ps = {s->set->tool, what, -1};
    sam_build_settings settings;
    sweep_settings(s, map, n, &settings);
    samfile_data sam;
    sam_profile profile;
    float mm;
    /* Built from the mesh: a scene's prebuilt map ("sam") scored the same
     * at every N and kind of a sweep. */
    sam_scene from_mesh;
    sam_app_scene_from_mesh(s->scene, &s->profile, s->mm_per_unit, &from_mesh);
    sam_status st = sam_app_scene_object(&from_mesh, s->set->tool, &settings, build_progress, &ps, &sam, &profile, &mm,
                                         build_seconds, err);
    if (st != SAM_OK)
        return st;
    sam_runtime *rt = NULL;
    sam_image full = {0}, translucency = {0};
    st = sam_runtime_create(&sam, &profile, mm, &rt, err);
    char note[512];
    /* The point then scores fewer samples than it is named for. */
    if (st == SAM_OK && sam_runtime_fitted_note(rt, note, sizeof note))
        say(s, "warning: sweep: %s map, N = %ld: %s", sam_build_map_name(map), n, note);
    if (st == SAM_OK)
        st = sam_runtime_scene_setup(rt, s->scene, NULL, NULL, NULL, 0, err);
    if (st == SAM_OK)
        st = sam_runtime_irradiance(rt, err);
    if (st == SAM_OK)
        st = sam_runtime_translucency(rt, 0, 0.0f, 1, err);
    if (st == SAM_OK)
        st = render_pair(rt, &s->view, SAM_TECHNIQUE_SAM, NULL, &full, &translucency, err);
    if (st == SAM_OK)
        st = sam_truth_report_score(ref, &full, &translucency, all, normalised, NULL, NULL, err);
    if (st == SAM_OK)
        say(s, "sweep: %s map, N = %ld: RMSE %.4f, translucency RMSE %.4f", sam_build_map_name(map), n, all->rmse,
            normalised->rmse);
    sam_image_destroy(&full);
    sam_image_destroy(&translucency);
    sam_runtime_destroy(rt);
    samfile_free(&sam);
    return st;
}

/* Rebuilds the map with N samples per vertex for each N of the settings'
 * sweep and scores SAM against `ref`; a cut map's sweep scores the flat map
 * and the flat-scaled baseline with the same N beside it. */
static sam_status run_sweep(const compare_state *s, const sam_truth_report_reference *ref,
                            sam_truth_report_sweep_point *out, sam_error *err)
{
    const sam_build_map map = (sam_build_map)s->set->map;
    for (int i = 0; i < s->set->sweep_count; ++i) {
        double baseline_seconds;
        out[i].n = s->set->sweep[i];
        out[i].has_flat = map == SAM_BUILD_MAP_CUT;
        sam_build_settings settings;
        sweep_settings(s, map, out[i].n, &settings);
        out[i].cut_budget = map == SAM_BUILD_MAP_CUT ? sam_build_cut_budget(&settings) : 0;
        sam_status st = score_map(s, ref, map, out[i].n, &out[i].build_seconds, &out[i].all, &out[i].normalised, err);
        if (st == SAM_OK && out[i].has_flat)
            st = score_map(s, ref, SAM_BUILD_MAP_FLAT, out[i].n, &baseline_seconds, &out[i].flat_all,
                           &out[i].flat_normalised, err);
        if (st == SAM_OK && out[i].has_flat)
            st = score_map(s, ref, SAM_BUILD_MAP_FLAT_SCALED, out[i].n, &baseline_seconds, &out[i].scaled_all,
                           &out[i].scaled_normalised, err);
        if (st != SAM_OK)
            return st;
    }
    return SAM_OK;
}

/* Renders every requested technique into s->results; one the runtime
 * cannot do is marked unavailable with the reason. */
static sam_status render_techniques(compare_state *s, sam_error *err)
{
    for (int t = 0; t < TECHNIQUES; ++t) {
        sam_truth_report_technique *r = &s->results[t];
        r->available = 0;
        if (!r->requested)
            continue;
        sam_status st = render_pair(s->rt, &s->view, (sam_technique)t, NULL, &r->full, &r->translucency, err);
        if (st == SAM_ERR_UNSUPPORTED) {
            snprintf(r->reason, sizeof r->reason, "%s", err->message);
            say(s, "%s unavailable: %s", sam_truth_report_technique_name(t), r->reason);
            continue;
        }
        if (st != SAM_OK)
            return st;
        r->available = 1;
    }
    return SAM_OK;
}

/* Scores and writes the images, runs the sweep and writes the reports of a
 * pose whose truth is `truth`, into s->dir (creating the output folder and
 * s->dir first). */
static sam_status write_pose(compare_state *s, const truth_result *truth, const char *space, sam_error *err)
{
    const sam_comparison_settings *set = s->set;
    sam_truth_report_reference ref = {0};
    sam_truth_report_technique self;
    memset(&self, 0, sizeof self);
    sam_truth_report_sweep_point sweep[SAM_COMPARISON_MAX_SWEEP];
    float truth_max = sam_truth_report_max_value(&truth->translucency);
    /* How much of the picture the translucency scores judge: on a thick
     * object they can differ by 10 dB between techniques whose pictures
     * do not differ visibly. */
    double light = 0, through = 0;
    for (size_t i = 0; i < (size_t)truth->full.width * truth->full.height; ++i)
        for (uint32_t c = 0; c < 3; ++c) {
            light += truth->full.pixels[i * truth->full.channels + c];
            through += truth->translucency.pixels[i * truth->translucency.channels + c];
        }
    const double share = light > 0 ? through / light : 0.0;
    if (!(truth_max > 0)) {
        say(s, "warning: the ground truth has no translucency in view; normalised scores use 1");
        truth_max = 1.0f;
    }
    say(s, "[4/5] images and scores");
    sam_status st;
    if ((st = sam_truth_report_make_dir(set->out, err)) != SAM_OK ||
        (s->dir != set->out && (st = sam_truth_report_make_dir(s->dir, err)) != SAM_OK) ||
        (st = sam_truth_report_reference_make(s->scene->tonemap, s->scene->exposure, &truth->full,
                                              &truth->translucency, truth_max, &ref, err)) != SAM_OK ||
        (st = sam_truth_report_score(&ref, &truth->full, &truth->translucency, &self.all, &self.normalised, NULL,
                                     NULL, err)) != SAM_OK ||
        (st = sam_truth_report_write_images(s->dir, s->results, &truth->full, &truth->translucency, &ref, err)) !=
            SAM_OK)
        goto done;
    for (int t = 0; t < TECHNIQUES; ++t) {
        const sam_truth_report_technique *r = &s->results[t];
        if (r->available)
            say(s, "%-13s PSNR %6.2f dB (differing pixels %6.2f dB), translucency %6.2f dB",
                sam_truth_report_technique_name(t), r->all.psnr_db, r->all.psnr_differing_db, r->normalised.psnr_db);
    }
    int monotonic = 1;
    if (set->sweep_count) {
        say(s, "[5/5] samples sweep");
        if ((st = run_sweep(s, &ref, sweep, err)) != SAM_OK)
            goto done;
        for (int i = 1; i < set->sweep_count; ++i)
            if (set->sweep[i] > set->sweep[i - 1] && sweep[i].all.rmse > sweep[i - 1].all.rmse)
                monotonic = 0;
    }
    /* The kind of map scored, as its INFO records it (a prebuilt one's too). */
    samfile_info info;
    sam_error info_err;
    if (samfile_info_read(&s->sam, NULL, &info, &info_err) != SAM_OK)
        info.map[0] = '\0';
    const sam_truth_report report = {
        .scene_path = s->scene_path, .width = s->view.width, .height = s->view.height,
        .vertex_count = s->sam.vertex_count, .samples_per_vertex = s->sam.samples_per_vertex, .map = info.map,
        .build_seconds = s->build_seconds, .diffusion = (int)s->view.diffusion, .animated = s->animated,
        .frame = s->frame, .fps = set->fps, .truth_tolerance = set->truth_tolerance, .techniques = s->results,
        .self = &self, .steps = truth->steps, .step_count = truth->step_count, .converged = truth->converged,
        .truth_max = truth_max, .translucency_share = share, .space = space, .sweep = sweep, .sweep_count = set->sweep_count,
        .monotonic = monotonic};
    if ((st = sam_truth_report_write(s->dir, &report, err)) != SAM_OK)
        goto done;
    if (set->sweep_count && (st = sam_truth_report_plot_sweep(s->dir, s->scene->mesh_path, sweep, set->sweep_count,
                                                              err)) != SAM_OK)
        goto done;
    say(s, "wrote %s/report.md", s->dir);
done:
    sam_truth_report_reference_destroy(&ref);
    return st;
}

/* Compares the runtime's current pose (L_d and T as the caller left them):
 * renders every requested technique, builds the truth from the posed
 * positions and normals the runtime holds, and writes images, scores and
 * the reports. The techniques' images are freed before it returns; their
 * scores go to `summary`. */
static sam_status compare_pose(compare_state *s, sam_truth_report_pose *summary, sam_error *err)
{
    sam_image positions = {0}, normals = {0};
    truth_result truth = {0};
    size_t nv = s->sam.vertex_count;
    float *pose = malloc(nv * 6 * sizeof *pose);
    sam_status st = SAM_OK;
    if (!pose) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the pose of %zu vertices", nv);
        goto done;
    }
    say(s, "[2/5] the techniques");
    if ((st = render_techniques(s, err)) != SAM_OK)
        goto done;
    say(s, "[3/5] the ground truth");
    sam_gbuffer_space space = s->view.diffusion == 3 ? SAM_GBUFFER_ATLAS : SAM_GBUFFER_SCREEN;
    if ((st = sam_runtime_gbuffer(s->rt, &s->view, space, &positions, &normals, err)) != SAM_OK)
        goto done;
    /* The truth samples the surface the runtime shows: its current
     * positions and normals (the deformed pose), the .sam's triangles. */
    if ((st = sam_runtime_read_positions(s->rt, pose, err)) != SAM_OK ||
        (st = sam_runtime_read_normals(s->rt, pose + 3 * nv, err)) != SAM_OK)
        goto done;
    s->truth_scene.positions = pose;
    s->truth_scene.normals = pose + 3 * nv;
    if ((st = converge_truth(s, &positions, &normals, &truth, err)) != SAM_OK ||
        (st = write_pose(s, &truth, space == SAM_GBUFFER_ATLAS ? "atlas texel" : "pixel", err)) != SAM_OK)
        goto done;
    summary->frame = s->frame;
    summary->truth_samples = truth.steps[truth.step_count - 1].samples;
    summary->converged = truth.converged;
done:
    for (int t = 0; t < TECHNIQUES; ++t) {
        sam_image_destroy(&s->results[t].full);
        sam_image_destroy(&s->results[t].translucency);
    }
    if (st == SAM_OK)
        memcpy(summary->techniques, s->results, sizeof summary->techniques);
    s->truth_scene.positions = s->truth_scene.normals = NULL;
    free(pose);
    sam_image_destroy(&positions);
    sam_image_destroy(&normals);
    sam_image_destroy(&truth.full);
    sam_image_destroy(&truth.translucency);
    return st;
}

/* The local thickness of the map on the runtime, when the thickness
 * technique is compared. */
static sam_status give_thickness(compare_state *s, sam_error *err)
{
    if (!s->results[SAM_TECHNIQUE_THICKNESS].requested)
        return SAM_OK;
    float *mm;
    sam_status st = sam_app_thickness(&s->sam, s->mm_per_unit, s->set->tool, &mm, err);
    if (st != SAM_OK)
        return st;
    st = sam_runtime_set_thickness(s->rt, mm, s->sam.vertex_count, err);
    free(mm);
    return st;
}

/* The map, a GL context, the runtime set up with the scene (and the local
 * thickness), the view every render uses, and the truth's scene on the
 * runtime's lighting. */
static sam_status setup(compare_state *s, sam_error *err)
{
    char warning[512];
    say(s, "[1/5] the map");
    sam_build_settings build;
    sam_build_default_settings(&build);
    build.map = (sam_build_map)s->set->map;
    if (s->set->map_samples)
        build.samples_per_vertex = s->set->map_samples;
    if (s->set->whole_cut)
        build.cut_budget = sam_build_samples(&build);
    /* The cache names its map in a shallow copy of the scene, so the
     * sweep's builds still start from the mesh. */
    char cache_dir[4096];
    sam_app_cache_dir(s->set->cache_dir, cache_dir, sizeof cache_dir);
    sam_scene cached = *s->scene;
    sam_status st = sam_app_cache_object(&cached, &build, cache_dir, !s->set->no_cache,
                                         s->set->tool ? s->set->tool : "sam_compare", &s->sam, &s->profile,
                                         &s->mm_per_unit, &s->build_seconds, err);
    if (cached.sam_path != s->scene->sam_path)
        free(cached.sam_path);
    if (st != SAM_OK ||
        (st = sam_gl_context_create_headless(&s->gl, err)) != SAM_OK ||
        (st = sam_runtime_create(&s->sam, &s->profile, s->mm_per_unit, &s->rt, err)) != SAM_OK ||
        (st = sam_runtime_scene_setup(s->rt, s->scene, s->sh, &s->has_environment, warning, sizeof warning, err)) !=
            SAM_OK ||
        (st = sam_runtime_scene_keyframes(s->rt, s->scene, &s->sam, err)) != SAM_OK ||
        (st = give_thickness(s, err)) != SAM_OK)
        return st;
    if (warning[0])
        say(s, "warning: %s", warning);
    if (sam_runtime_fitted_note(s->rt, warning, sizeof warning))
        say(s, "warning: %s", warning);
    sam_runtime_scene_view(s->rt, s->scene, &s->view, warning, sizeof warning);
    if (warning[0])
        say(s, "warning: %s", warning);
    /* Lossy texture-space optimisations would change the picture under comparison. */
    s->view.options.culled = 0;
    s->view.options.depth_sized = 0;
    sam_truth_scene *ts = &s->truth_scene;
    ts->vertex_count = s->sam.vertex_count;
    ts->triangle_count = s->sam.triangle_count;
    ts->triangles = s->sam.triangles;
    ts->mm_per_unit = s->mm_per_unit;
    ts->profile = &s->profile;
    ts->lights = s->scene->lights;
    ts->light_count = s->scene->light_count;
    ts->sh = s->has_environment ? (const float(*)[3])s->sh : NULL;
    ts->environment_rho_dt = sam_runtime_environment_rho_dt(s->rt);
    ts->rho_dt = rho_dt_of;
    ts->rho_dt_user = s->rt;
    return SAM_OK;
}

/* Plays every frame up to the last one compared as sam_render --animate
 * plays it: the pose at t = frame / fps, the sample walk, L_d, and T
 * smoothed with dt = 1 / fps (reset at frame 0). The walk moves samples one
 * ring per frame and T carries its history, so a frame is only what a
 * viewer sees when every frame before it has run. */
static sam_status play(compare_state *s, sam_truth_report_pose *poses, sam_error *err)
{
    const sam_comparison_settings *set = s->set;
    /* Without frames the one pose compared is frame 0 (t = 0). */
    static const long frame_zero = 0;
    const long *frames = set->frames ? set->frames : &frame_zero;
    int frame_count = set->frames ? set->frame_count : 1;
    char frame_dir[4096];
    sam_status st;
    for (long f = 0, next = 0; next < frame_count; ++f) {
        if (s->animated && ((st = sam_runtime_deform(s->rt, (float)f / set->fps, err)) != SAM_OK ||
                            (st = sam_runtime_walk(s->rt, err)) != SAM_OK))
            return st;
        if ((st = sam_runtime_irradiance(s->rt, err)) != SAM_OK ||
            (st = sam_runtime_translucency(s->rt, 0, 1.0f / set->fps, f == 0, err)) != SAM_OK)
            return st;
        if (f != frames[next])
            continue;
        s->frame = f;
        if (set->frames) {
            char name[32];
            sam_truth_report_frame_dir(name, sizeof name, f);
            if ((st = sam_truth_report_path(frame_dir, sizeof frame_dir, set->out, name, err)) != SAM_OK)
                return st;
            s->dir = frame_dir;
            say(s, "frame %ld (t = %.4g s), %d of %d", f, (double)((float)f / set->fps), (int)next + 1, frame_count);
        }
        if ((st = compare_pose(s, &poses[next], err)) != SAM_OK)
            return st;
        ++next;
    }
    return SAM_OK;
}

sam_status sam_comparison_run(const sam_scene *scene, const char *scene_path, const sam_comparison_settings *settings,
                              sam_error *err)
{
    compare_state *s = calloc(1, sizeof *s);
    sam_truth_report_pose *poses = calloc(SAM_COMPARISON_MAX_FRAMES, sizeof *poses);
    sam_status st;
    if (!(settings->fps > 0) || settings->sweep_count < 0 || settings->sweep_count > SAM_COMPARISON_MAX_SWEEP ||
        (settings->frames && (settings->frame_count < 1 || settings->frame_count > SAM_COMPARISON_MAX_FRAMES))) {
        st = sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "comparison: fps %g, %d sweep counts and %d frames: fps must "
                      "be > 0, at most %d counts and 1..%d frames", (double)settings->fps, settings->sweep_count,
                      settings->frame_count, SAM_COMPARISON_MAX_SWEEP, SAM_COMPARISON_MAX_FRAMES);
        goto done;
    }
    if (!s || !poses) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for a comparison");
        goto done;
    }
    s->set = settings;
    s->scene_path = scene_path;
    s->scene = scene;
    s->dir = settings->out;
    s->animated = scene->deformer_count || scene->keyframe_count;
    for (int t = 0; t < TECHNIQUES; ++t)
        s->results[t].requested = settings->requested[t];
    if ((st = setup(s, err)) != SAM_OK || (st = play(s, poses, err)) != SAM_OK)
        goto done;
    if (settings->frames) {
        if ((st = sam_truth_report_write_summary(settings->out, scene_path, settings->fps, poses,
                                                 settings->frame_count, err)) != SAM_OK)
            goto done;
        say(s, "wrote %s/report.md", settings->out);
    }
done:
    if (s) {
        sam_runtime_destroy(s->rt);
        sam_gl_context_destroy(s->gl);
        samfile_free(&s->sam);
    }
    free(poses);
    free(s);
    return st;
}
