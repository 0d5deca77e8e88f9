/*
 * sam_compare: the SAM paper's evaluation (Sec. 5.1-5.2, Fig. 10-11) on any
 * scene. Renders a dense CPU ground truth of the translucency (sam_truth)
 * and every requested technique with the same front lighting and surface
 * diffusion, writes the images, their differences x4, and a report with
 * PSNR and RMSE; optionally rebuilds the map for several sample counts N
 * and plots RMSE against N with gnuplot. On an animated scene it plays the
 * animation and compares chosen frames, each against a truth of its pose.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sam/sam_app.h"
#include "sam/sam_app_scene.h"
#include "sam/sam_runtime_scene.h"
#include "sam/sam_truth.h"

#define MAX_TECHNIQUES 4
#define MAX_SWEEP 16
/* --frames: how many frames one run compares, and the last frame it plays to. */
#define MAX_FRAMES 16
#define MAX_FRAME 100000
/* sam_render --animate's default, so the same --frames are the same poses. */
#define DEFAULT_FPS 30.0f
/* Doublings of the truth's samples before giving up on 0.5 dB: from the
 * library's smallest count to its largest. */
#define MAX_DOUBLINGS 6
#define CONVERGED_DB 0.5

static const char *const technique_names[MAX_TECHNIQUES] = {"sam", "none", "tsm", "transmittance"};

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_compare SCENE.json --out DIR [options]\n"
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
            "  --techniques LIST      comma-separated from sam, tsm, transmittance, none\n"
            "                         (default: all four)\n"
            "  --samples-sweep LIST   rebuild the map with each N in LIST (e.g. 3,5,10,20,50; each\n"
            "                         1..64) and plot SAM's RMSE against N (needs a scene with a mesh\n"
            "                         and gnuplot)\n"
            "  --samples N            back-side samples per vertex of the map SAM is shown with\n"
            "                         (default 3; a scene's prebuilt .sam keeps its own)\n"
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
            "  -h, --help             this text\n"
            "PSNR is computed on the tonemapped 8-bit sRGB images over the object's pixels, over\n"
            "the pixels that differ from the truth (as the paper does), and on the translucency\n"
            "images normalised by the truth's maximum. Texture-space depth sizing and culling are\n"
            "turned off for every render: they change the picture, and the comparison should not.\n");
}

static void say(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("sam_compare: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* Progress every 10% on one rewritten line on a terminal; into a log, a
 * line when a stage is done. */
typedef struct progress_state {
    const char *what;
    int last_decile;
} progress_state;

static void progress_line(progress_state *p, const char *stage, double fraction)
{
    int decile = (int)(fraction * 10.0);
    if (decile == p->last_decile)
        return;
    p->last_decile = decile;
    if (isatty(STDERR_FILENO))
        fprintf(stderr, "\rsam_compare: %s%s%s %3.0f%%%s", p->what, stage ? ": " : "", stage ? stage : "",
                100.0 * fraction, fraction >= 1.0 ? "\n" : "");
    else if (fraction >= 1.0)
        fprintf(stderr, "sam_compare: %s%s%s done\n", p->what, stage ? ": " : "", stage ? stage : "");
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

/* A comma-separated list of integers in [lo, hi]; 0 on a bad entry. */
static int parse_int_list(const char *text, long lo, long hi, long *out, int max, int *count)
{
    *count = 0;
    const char *p = text;
    while (*p) {
        char *end;
        long v = strtol(p, &end, 10);
        if (end == p || (*end && *end != ',') || v < lo || v > hi || *count == max)
            return 0;
        out[(*count)++] = v;
        p = *end ? end + 1 : end;
    }
    return *count > 0;
}

/* The images and scores of one technique. */
typedef struct technique_result {
    int requested, available;
    char reason[SAM_ERROR_MESSAGE_SIZE];
    sam_image full, translucency; /* linear HDR RGBA */
    sam_image_comparison all, normalised;
} technique_result;

typedef struct compare_state {
    const char *root; /* --out */
    const char *dir;  /* where this pose's files go: root, or root/frame_NNNN */
    sam_scene scene;
    samfile_data sam;
    sam_profile profile;
    float mm_per_unit;
    double build_seconds;
    float truth_tolerance;
    sam_runtime *rt;
    sam_render_view view;
    float sh[9][3];
    int has_environment;
    sam_truth_scene truth_scene;
    int animated;     /* the scene has deformers or keyframes */
    long frame;       /* the frame compared, when animated */
    float fps;
} compare_state;

static float rho_dt_of(const void *user, float n_dot_l)
{
    return sam_runtime_rho_dt(user, n_dot_l);
}

static sam_status join_path(char *out, size_t n, const char *dir, const char *name, sam_error *err)
{
    int len = snprintf(out, n, "%s/%s", dir, name);
    if (len < 0 || (size_t)len >= n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "output path %s/%s is too long", dir, name);
    return SAM_OK;
}

/* The display image of a render: tonemapped with the scene's curve over black. */
static sam_status display(const compare_state *s, const sam_image *hdr, sam_image *out, sam_error *err)
{
    static const float black[3] = {0, 0, 0};
    return sam_image_tonemap(hdr, s->scene.tonemap, s->scene.exposure, black, out, err);
}

/* A translucency image divided by `scale` (the truth's maximum) and clamped
 * to [0, 1]: the normalised pictures the paper's detail images show. */
static sam_status normalised(const sam_image *hdr, float scale, sam_image *out, sam_error *err)
{
    sam_status st = sam_image_create(out, hdr->width, hdr->height, 3, err);
    if (st != SAM_OK)
        return st;
    size_t n = (size_t)hdr->width * hdr->height;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float v = hdr->pixels[i * hdr->channels + (size_t)c] / scale;
            out->pixels[i * 3 + (size_t)c] = v > 0 ? (v < 1 ? v : 1) : 0;
        }
    return SAM_OK;
}

/* The largest colour value over the object's pixels (alpha > 0). */
static float max_value(const sam_image *img)
{
    float m = 0;
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; ++i)
        if (img->pixels[i * 4 + 3] > 0)
            for (int c = 0; c < 3; ++c)
                m = fmaxf(m, img->pixels[i * 4 + (size_t)c]);
    return m;
}

/* Writes NAME.exr and NAME.png (the display image `shown`). */
static sam_status write_pair(const compare_state *s, const char *name, const sam_image *hdr, const sam_image *shown,
                             sam_error *err)
{
    char path[4096], file[256];
    snprintf(file, sizeof file, "%s.exr", name);
    sam_status st = join_path(path, sizeof path, s->dir, file, err);
    if (st == SAM_OK)
        st = sam_image_write_exr(path, hdr, SAM_EXR_FLOAT, err);
    snprintf(file, sizeof file, "%s.png", name);
    if (st == SAM_OK)
        st = join_path(path, sizeof path, s->dir, file, err);
    if (st == SAM_OK)
        st = sam_image_write_png(path, shown, SAM_PNG_SRGB, err);
    return st;
}

/* |a - b| x 4 of two display images as they look in 8-bit sRGB (the
 * paper's enhanced difference images). */
static sam_status write_difference(const compare_state *s, const char *name, const sam_image *a, const sam_image *b,
                                   sam_error *err)
{
    sam_image d;
    sam_status st = sam_image_create(&d, a->width, a->height, 3, err);
    if (st != SAM_OK)
        return st;
    size_t n = (size_t)a->width * a->height;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            float x = roundf(255.0f * sam_linear_to_srgb(a->pixels[i * a->channels + (size_t)c])) / 255.0f;
            float y = roundf(255.0f * sam_linear_to_srgb(b->pixels[i * b->channels + (size_t)c])) / 255.0f;
            d.pixels[i * 3 + (size_t)c] = fminf(1.0f, 4.0f * fabsf(x - y));
        }
    char path[4096], file[256];
    snprintf(file, sizeof file, "%s.png", name);
    st = join_path(path, sizeof path, s->dir, file, err);
    if (st == SAM_OK)
        st = sam_image_write_png(path, &d, SAM_PNG_LINEAR, err);
    sam_image_destroy(&d);
    return st;
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
    progress_state ps = {what, -1};
    sam_truth_settings settings;
    sam_truth_default_settings(&settings);
    settings.sample_count = samples;
    settings.far_field_tolerance = s->truth_tolerance;
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

/* The truth as every score sees it, made once per truth: its display
 * image, its translucency normalised by its maximum, and its alpha as the
 * object's mask. */
typedef struct reference {
    const sam_image *mask;
    float max;
    sam_image shown, norm;
} reference;

static void reference_destroy(reference *ref)
{
    sam_image_destroy(&ref->shown);
    sam_image_destroy(&ref->norm);
}

static sam_status reference_make(const compare_state *s, const sam_image *full, const sam_image *translucency,
                                 float max, reference *ref, sam_error *err)
{
    memset(ref, 0, sizeof *ref);
    ref->mask = full;
    ref->max = max;
    sam_status st = display(s, full, &ref->shown, err);
    if (st == SAM_OK)
        st = normalised(translucency, max, &ref->norm, err);
    if (st != SAM_OK)
        reference_destroy(ref);
    return st;
}

/* Scores a render pair against `ref`. Its display and normalised images go
 * to `shown` and `norm` when not NULL (the caller destroys them). */
static sam_status score(const compare_state *s, const reference *ref, const sam_image *full,
                        const sam_image *translucency, sam_image_comparison *all, sam_image_comparison *normal,
                        sam_image *shown, sam_image *norm, sam_error *err)
{
    sam_image a = {0}, b = {0};
    sam_status st = display(s, full, &a, err);
    if (st == SAM_OK)
        st = sam_image_compare_srgb8(&a, &ref->shown, ref->mask, all, err);
    if (st == SAM_OK)
        st = normalised(translucency, ref->max, &b, err);
    if (st == SAM_OK)
        st = sam_image_compare_srgb8(&b, &ref->norm, ref->mask, normal, err);
    if (st == SAM_OK && shown)
        *shown = a;
    else
        sam_image_destroy(&a);
    if (st == SAM_OK && norm)
        *norm = b;
    else
        sam_image_destroy(&b);
    return st;
}

/* Copies `img` (3 channels) into `row` at column x0. */
static void blit(sam_image *row, const sam_image *img, uint32_t x0)
{
    for (uint32_t y = 0; y < img->height; ++y)
        memcpy(row->pixels + ((size_t)y * row->width + x0) * 3, img->pixels + (size_t)y * img->width * 3,
               (size_t)img->width * 3 * sizeof *img->pixels);
}

/* Every image of the truth and of each available technique, their
 * differences x4, the scores, and two rows side by side (truth first, then
 * the techniques in the report's order): row.png of the full shading,
 * translucency_row.png of the normalised translucency. */
static sam_status write_images(const compare_state *s, technique_result *results, const sam_image *truth_full,
                               const sam_image *truth_translucency, const reference *ref, sam_error *err)
{
    /* shown[0] and norm[0] are the reference's; the caller owns them. */
    sam_image shown[MAX_TECHNIQUES + 1], norm[MAX_TECHNIQUES + 1], row = {0}, row_t = {0};
    memset(shown, 0, sizeof shown);
    memset(norm, 0, sizeof norm);
    shown[0] = ref->shown;
    norm[0] = ref->norm;
    sam_status st = write_pair(s, "truth", truth_full, &shown[0], err);
    if (st == SAM_OK)
        st = write_pair(s, "truth_translucency", truth_translucency, &norm[0], err);
    int count = 1;
    for (int t = 0; t < MAX_TECHNIQUES && st == SAM_OK; ++t) {
        technique_result *r = &results[t];
        if (!r->available)
            continue;
        char name[128];
        sam_image *a = &shown[count], *b = &norm[count];
        ++count;
        st = score(s, ref, &r->full, &r->translucency, &r->all, &r->normalised, a, b, err);
        if (st == SAM_OK)
            st = write_pair(s, technique_names[t], &r->full, a, err);
        snprintf(name, sizeof name, "%s_diff4", technique_names[t]);
        if (st == SAM_OK)
            st = write_difference(s, name, a, &shown[0], err);
        snprintf(name, sizeof name, "%s_translucency", technique_names[t]);
        if (st == SAM_OK)
            st = write_pair(s, name, &r->translucency, b, err);
        snprintf(name, sizeof name, "%s_translucency_diff4", technique_names[t]);
        if (st == SAM_OK)
            st = write_difference(s, name, b, &norm[0], err);
        if (st == SAM_OK)
            say("%-13s PSNR %6.2f dB (differing pixels %6.2f dB), translucency %6.2f dB", technique_names[t],
                r->all.psnr_db, r->all.psnr_differing_db, r->normalised.psnr_db);
    }
    uint32_t w = truth_full->width, h = truth_full->height;
    if (st == SAM_OK)
        st = sam_image_create(&row, w * (uint32_t)count, h, 3, err);
    if (st == SAM_OK)
        st = sam_image_create(&row_t, w * (uint32_t)count, h, 3, err);
    if (st == SAM_OK) {
        for (int i = 0; i < count; ++i) {
            blit(&row, &shown[i], w * (uint32_t)i);
            blit(&row_t, &norm[i], w * (uint32_t)i);
        }
        char path[4096];
        st = join_path(path, sizeof path, s->dir, "row.png", err);
        if (st == SAM_OK)
            st = sam_image_write_png(path, &row, SAM_PNG_SRGB, err);
        if (st == SAM_OK)
            st = join_path(path, sizeof path, s->dir, "translucency_row.png", err);
        if (st == SAM_OK)
            st = sam_image_write_png(path, &row_t, SAM_PNG_SRGB, err);
    }
    for (int i = 1; i <= MAX_TECHNIQUES; ++i) {
        sam_image_destroy(&shown[i]);
        sam_image_destroy(&norm[i]);
    }
    sam_image_destroy(&row);
    sam_image_destroy(&row_t);
    return st;
}

/* JSON has no infinity: an exact match is written as null. */
static void json_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.4f", v);
    else
        fprintf(f, "null");
}

static void md_db(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, " %.2f |", v);
    else
        fprintf(f, " inf |");
}

typedef struct truth_step {
    uint64_t samples;
    double seconds, sam_psnr_db, sam_psnr_normalised_db;
} truth_step;

typedef struct sweep_point {
    long n;
    double build_seconds;
    sam_image_comparison all, normalised;
} sweep_point;

static sam_status write_reports(const compare_state *s, const char *scene_path, const technique_result *results,
                                const technique_result *self, const truth_step *steps, int step_count,
                                int converged, float truth_max, const char *space,
                                const sweep_point *sweep, int sweep_count, int monotonic, sam_error *err)
{
    const truth_step *final = &steps[step_count - 1];
    char path[4096];
    sam_atomic_file f;
    sam_status st = join_path(path, sizeof path, s->dir, "report.json", err);
    if (st == SAM_OK)
        st = sam_atomic_open(&f, path, err);
    if (st != SAM_OK)
        return st;
    static const char *const diffusion_names[4] = {"none", "screen", "preintegrated", "texture"};
    fprintf(f.fp, "{\n  \"scene\": \"%s\",\n  \"resolution\": [%u, %u],\n  \"vertices\": %u,\n", sam_path_basename(scene_path),
            s->view.width, s->view.height, s->sam.vertex_count);
    if (s->animated)
        fprintf(f.fp, "  \"frame\": %ld,\n  \"time_s\": %.6g,\n  \"fps\": %g,\n", s->frame,
                (double)((float)s->frame / s->fps), (double)s->fps);
    fprintf(f.fp, "  \"samples_per_vertex\": %u,\n  \"map_build_seconds\": %.3f,\n  \"diffusion\": \"%s\",\n",
            s->sam.samples_per_vertex, s->build_seconds, diffusion_names[s->view.diffusion]);
    fprintf(f.fp, "  \"truth\": {\"samples\": %llu, \"seconds\": %.3f, \"space\": \"%s\", \"translucency_max\": %.6g, "
                  "\"far_field_tolerance\": %g, \"converged\": %s, \"convergence\": [",
            (unsigned long long)final->samples, final->seconds, space, (double)truth_max, (double)s->truth_tolerance,
            converged ? "true" : "false");
    for (int i = 0; i < step_count; ++i) {
        fprintf(f.fp, "%s{\"samples\": %llu, \"seconds\": %.3f, \"sam_psnr_db\": ", i ? ", " : "",
                (unsigned long long)steps[i].samples, steps[i].seconds);
        json_number(f.fp, steps[i].sam_psnr_db);
        fprintf(f.fp, ", \"sam_psnr_translucency_db\": ");
        json_number(f.fp, steps[i].sam_psnr_normalised_db);
        fprintf(f.fp, "}");
    }
    /* The truth scored against itself checks the scoring: an exact match. */
    fprintf(f.fp, "], \"self_psnr_db\": ");
    json_number(f.fp, self->all.psnr_db);
    fprintf(f.fp, ", \"self_differing_pixels\": %llu, \"self_psnr_translucency_db\": ",
            (unsigned long long)self->all.differing_pixels);
    json_number(f.fp, self->normalised.psnr_db);
    fprintf(f.fp, "},\n  \"techniques\": [\n");
    int first = 1;
    for (int t = 0; t < MAX_TECHNIQUES; ++t) {
        const technique_result *r = &results[t];
        if (!r->requested)
            continue;
        fprintf(f.fp, "%s    {\"name\": \"%s\", \"available\": %s", first ? "" : ",\n", technique_names[t],
                r->available ? "true" : "false");
        first = 0;
        if (!r->available) {
            fprintf(f.fp, ", \"reason\": \"%s\"}", r->reason);
            continue;
        }
        fprintf(f.fp, ", \"pixels\": %llu, \"differing_pixels\": %llu, \"psnr_db\": ", (unsigned long long)r->all.pixels,
                (unsigned long long)r->all.differing_pixels);
        json_number(f.fp, r->all.psnr_db);
        fprintf(f.fp, ", \"rmse\": %.4f, \"psnr_differing_db\": ", r->all.rmse);
        json_number(f.fp, r->all.psnr_differing_db);
        fprintf(f.fp, ", \"rmse_differing\": %.4f, \"psnr_translucency_db\": ", r->all.rmse_differing);
        json_number(f.fp, r->normalised.psnr_db);
        fprintf(f.fp, ", \"rmse_translucency\": %.4f, \"psnr_translucency_differing_db\": ", r->normalised.rmse);
        json_number(f.fp, r->normalised.psnr_differing_db);
        fprintf(f.fp, "}");
    }
    fprintf(f.fp, "\n  ]");
    if (sweep_count) {
        fprintf(f.fp, ",\n  \"samples_sweep\": {\"rmse_falls_monotonically\": %s, \"points\": [",
                monotonic ? "true" : "false");
        for (int i = 0; i < sweep_count; ++i) {
            fprintf(f.fp, "%s{\"n\": %ld, \"build_seconds\": %.3f, \"rmse\": %.4f, \"rmse_translucency\": %.4f, \"psnr_db\": ",
                    i ? ", " : "", sweep[i].n, sweep[i].build_seconds, sweep[i].all.rmse, sweep[i].normalised.rmse);
            json_number(f.fp, sweep[i].all.psnr_db);
            fprintf(f.fp, "}");
        }
        fprintf(f.fp, "]}");
    }
    fprintf(f.fp, "\n}\n");
    if ((st = sam_atomic_commit(&f, err)) != SAM_OK)
        return st;

    if ((st = join_path(path, sizeof path, s->dir, "report.md", err)) != SAM_OK ||
        (st = sam_atomic_open(&f, path, err)) != SAM_OK)
        return st;
    fprintf(f.fp, "# sam_compare: %s\n\n", sam_path_basename(scene_path));
    fprintf(f.fp, "%ux%u, %u vertices, N = %u back-side samples per vertex, %s diffusion.\n\n", s->view.width,
            s->view.height, s->sam.vertex_count, s->sam.samples_per_vertex, diffusion_names[s->view.diffusion]);
    if (s->animated)
        fprintf(f.fp, "Frame %ld of the animation at %g fps (t = %.4g s): the pose, the truth and every technique "
                      "at that time; the frames before it were played as `sam_render --animate` plays them (the "
                      "sample walk every frame, T smoothed with dt = 1/fps).\n\n",
                s->frame, (double)s->fps, (double)((float)s->frame / s->fps));
    fprintf(f.fp, "Ground truth: %llu surface samples, %.2f s, evaluated per %s, far-field tolerance %g. Doubling "
                  "the samples:\n\n",
            (unsigned long long)final->samples, final->seconds, space, (double)s->truth_tolerance);
    fprintf(f.fp, "| truth samples | seconds | SAM PSNR (dB) | SAM translucency PSNR (dB) |\n| --- | --- | --- | --- |\n");
    for (int i = 0; i < step_count; ++i) {
        fprintf(f.fp, "| %llu | %.2f |", (unsigned long long)steps[i].samples, steps[i].seconds);
        md_db(f.fp, steps[i].sam_psnr_db);
        md_db(f.fp, steps[i].sam_psnr_normalised_db);
        fprintf(f.fp, "\n");
    }
    fprintf(f.fp, converged ? "\nThe last doubling moved SAM's scores by under %.1f dB.\n"
                            : "\n**Not converged**: the last doubling still moved SAM's scores by %.1f dB or more.\n",
            CONVERGED_DB);
    fprintf(f.fp, "\nPSNR on tonemapped 8-bit sRGB over the object's pixels; \"differing\" counts only pixels that "
                  "differ from the truth (the paper's Fig. 11); translucency images are normalised by the truth's "
                  "maximum (%.4g).\n\n",
            (double)truth_max);
    fprintf(f.fp, "| technique | PSNR (dB) | RMSE | PSNR differing (dB) | differing pixels | translucency PSNR (dB) | "
                  "translucency RMSE |\n| --- | --- | --- | --- | --- | --- | --- |\n");
    for (int t = 0; t < MAX_TECHNIQUES; ++t) {
        const technique_result *r = &results[t];
        if (!r->requested)
            continue;
        if (!r->available) {
            fprintf(f.fp, "| %s | unavailable: %s | | | | | |\n", technique_names[t], r->reason);
            continue;
        }
        fprintf(f.fp, "| %s |", technique_names[t]);
        md_db(f.fp, r->all.psnr_db);
        fprintf(f.fp, " %.3f |", r->all.rmse);
        md_db(f.fp, r->all.psnr_differing_db);
        fprintf(f.fp, " %llu of %llu |", (unsigned long long)r->all.differing_pixels, (unsigned long long)r->all.pixels);
        md_db(f.fp, r->normalised.psnr_db);
        fprintf(f.fp, " %.3f |\n", r->normalised.rmse);
    }
    if (sweep_count) {
        fprintf(f.fp, "\nSAM against the truth as the map is rebuilt with N samples per vertex (rmse_vs_samples.png); "
                      "RMSE %s monotonically:\n\n| N | build s | RMSE | translucency RMSE |\n| --- | --- | --- | --- |\n",
                monotonic ? "falls" : "does not fall");
        for (int i = 0; i < sweep_count; ++i)
            fprintf(f.fp, "| %ld | %.2f | %.4f | %.4f |\n", sweep[i].n, sweep[i].build_seconds, sweep[i].all.rmse,
                    sweep[i].normalised.rmse);
    }
    return sam_atomic_commit(&f, err);
}

/* sweep.dat and rmse_vs_samples.png through gnuplot. */
static sam_status plot_sweep(const compare_state *s, const sweep_point *sweep, int count, sam_error *err)
{
    char dat[4096], script[4096], png[4096];
    sam_status st = join_path(dat, sizeof dat, s->dir, "sweep.dat", err);
    if (st == SAM_OK)
        st = join_path(script, sizeof script, s->dir, "sweep.gnuplot", err);
    if (st == SAM_OK)
        st = join_path(png, sizeof png, s->dir, "rmse_vs_samples.png", err);
    if (st != SAM_OK)
        return st;
    sam_atomic_file f;
    if ((st = sam_atomic_open(&f, dat, err)) != SAM_OK)
        return st;
    fprintf(f.fp, "# N rmse rmse_translucency (8-bit levels)\n");
    for (int i = 0; i < count; ++i)
        fprintf(f.fp, "%ld %.6f %.6f\n", sweep[i].n, sweep[i].all.rmse, sweep[i].normalised.rmse);
    if ((st = sam_atomic_commit(&f, err)) != SAM_OK)
        return st;
    if ((st = sam_atomic_open(&f, script, err)) != SAM_OK)
        return st;
    /* gnuplot writes the PNG itself; a temporary name keeps a failed run
     * from leaving half a picture. */
    fprintf(f.fp,
            "set terminal pngcairo size 800,500 noenhanced\nset output '%s.tmp'\n"
            "set title 'SAM against the ground truth (%s)'\nset xlabel 'back-side samples per vertex N'\n"
            "set ylabel 'RMSE (8-bit sRGB levels)'\nset grid\nset key top right\n"
            "plot '%s' using 1:2 with linespoints lw 2 title 'full shading', '' using 1:3 with linespoints lw 2 "
            "title 'translucency (normalised)'\n",
            png, sam_path_basename(s->scene.mesh_path ? s->scene.mesh_path : "scene"), dat);
    if ((st = sam_atomic_commit(&f, err)) != SAM_OK)
        return st;
    pid_t pid = fork();
    if (pid == 0) {
        execlp("gnuplot", "gnuplot", script, (char *)NULL);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) < 0)
        return sam_fail(err, SAM_ERR_IO, "could not run gnuplot: %s", strerror(errno));
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return sam_fail(err, SAM_ERR_IO,
                        WIFEXITED(status) && WEXITSTATUS(status) == 127
                            ? "gnuplot is not installed (scripts/deps.sh installs gnuplot-nox); %s and %s are written"
                            : "gnuplot failed on %s (data in %s)",
                        script, dat);
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", png);
    if (rename(tmp, png) != 0)
        return sam_fail(err, SAM_ERR_IO, "%s: %s", png, strerror(errno));
    return SAM_OK;
}

/* Rebuilds the map with N samples per vertex for each N and scores SAM. */
static sam_status run_sweep(const compare_state *s, const long *ns, int count, const reference *ref,
                            sweep_point *out, sam_error *err)
{
    for (int i = 0; i < count; ++i) {
        char what[64];
        snprintf(what, sizeof what, "sweep: building the map with N = %ld", ns[i]);
        progress_state ps = {what, -1};
        sam_build_settings settings;
        sam_build_default_settings(&settings);
        settings.samples_per_vertex = (uint32_t)ns[i];
        samfile_data sam;
        sam_profile profile;
        float mm;
        sam_status st =
            sam_app_scene_object(&s->scene, &settings, build_progress, &ps, &sam, &profile, &mm, &out[i].build_seconds, err);
        if (st != SAM_OK)
            return st;
        sam_runtime *rt = NULL;
        sam_image full = {0}, translucency = {0};
        st = sam_runtime_create(&sam, &profile, mm, &rt, err);
        if (st == SAM_OK)
            st = sam_runtime_scene_setup(rt, &s->scene, NULL, NULL, NULL, 0, err);
        if (st == SAM_OK)
            st = sam_runtime_irradiance(rt, err);
        if (st == SAM_OK)
            st = sam_runtime_translucency(rt, 0, 0.0f, 1, err);
        if (st == SAM_OK)
            st = render_pair(rt, &s->view, SAM_TECHNIQUE_SAM, NULL, &full, &translucency, err);
        if (st == SAM_OK)
            st = score(s, ref, &full, &translucency, &out[i].all, &out[i].normalised, NULL, NULL, err);
        out[i].n = ns[i];
        if (st == SAM_OK)
            say("sweep: N = %ld: RMSE %.4f, translucency RMSE %.4f", ns[i], out[i].all.rmse, out[i].normalised.rmse);
        sam_image_destroy(&full);
        sam_image_destroy(&translucency);
        sam_runtime_destroy(rt);
        samfile_free(&sam);
        if (st != SAM_OK)
            return st;
    }
    return SAM_OK;
}

/* DIR is checked before any work: one that already holds a report is kept
 * unless --force, so a finished comparison is not overwritten by accident.
 * It is created only when the first image is ready (create_dir), so a run
 * that fails before that leaves nothing behind. */
static sam_status check_dir(const char *dir, int force, sam_error *err)
{
    struct stat sb;
    if (stat(dir, &sb) != 0)
        return errno == ENOENT ? SAM_OK : sam_fail(err, SAM_ERR_IO, "%s: %s", dir, strerror(errno));
    if (!S_ISDIR(sb.st_mode))
        return sam_fail(err, SAM_ERR_IO, "%s is not a directory", dir);
    char report[4096];
    sam_status st = join_path(report, sizeof report, dir, "report.json", err);
    if (st == SAM_OK && !force && access(report, F_OK) == 0)
        st = sam_fail(err, SAM_ERR_IO, "%s already holds a report (report.json); give --force to overwrite it", dir);
    return st;
}

static sam_status create_dir(const char *dir, sam_error *err)
{
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return sam_fail(err, SAM_ERR_IO, "cannot create %s: %s", dir, strerror(errno));
    return SAM_OK;
}

/* What an animation's summary keeps of one compared frame. */
typedef struct pose_summary {
    long frame;
    uint64_t truth_samples;
    int converged;
    technique_result techniques[MAX_TECHNIQUES]; /* scores only: their images are freed */
} pose_summary;

/* Compares the runtime's current pose (L_d and T as the caller left them):
 * renders every requested technique, builds the truth from the posed
 * positions and normals the runtime holds, and writes images, scores and
 * the reports into s->dir (creating s->root and s->dir on the first
 * image). The techniques' images are freed before it returns. */
static sam_status compare_pose(compare_state *s, const char *scene_path, technique_result *results,
                               uint64_t first_samples, const long *sweep_n, int sweep_count, pose_summary *summary,
                               sam_error *err)
{
    sam_status st = SAM_OK;
    sam_image positions = {0}, normals = {0}, truth_full = {0}, truth_translucency = {0};
    sam_image candidate_full = {0}, candidate_translucency = {0};
    reference truth_ref = {0};
    truth_step steps[MAX_DOUBLINGS + 1];
    int step_count = 0, converged = 0;
    sweep_point sweep[MAX_SWEEP];
    technique_result self;
    memset(&self, 0, sizeof self);
    size_t nv = s->sam.vertex_count;
    float *pose = malloc(nv * 6 * sizeof *pose);
    if (!pose) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for the pose of %zu vertices", nv);
        goto done;
    }

    say("[2/5] the techniques");
    for (int t = 0; t < MAX_TECHNIQUES; ++t) {
        technique_result *r = &results[t];
        r->available = 0;
        if (!r->requested)
            continue;
        sam_status rs = render_pair(s->rt, &s->view, (sam_technique)t, NULL, &r->full, &r->translucency, err);
        if (rs == SAM_ERR_UNSUPPORTED) {
            snprintf(r->reason, sizeof r->reason, "%s", err->message);
            say("%s unavailable: %s", technique_names[t], r->reason);
            continue;
        }
        if ((st = rs) != SAM_OK)
            goto done;
        r->available = 1;
    }

    say("[3/5] the ground truth");
    sam_gbuffer_space space = s->view.diffusion == 3 ? SAM_GBUFFER_ATLAS : SAM_GBUFFER_SCREEN;
    const char *space_name = space == SAM_GBUFFER_ATLAS ? "atlas texel" : "pixel";
    if ((st = sam_runtime_gbuffer(s->rt, &s->view, space, &positions, &normals, err)) != SAM_OK)
        goto done;
    /* The truth samples the surface the runtime shows: its current
     * positions and normals (the deformed pose), the .sam's triangles. */
    if ((st = sam_runtime_read_positions(s->rt, pose, err)) != SAM_OK ||
        (st = sam_runtime_read_normals(s->rt, pose + 3 * nv, err)) != SAM_OK)
        goto done;
    s->truth_scene.positions = pose;
    s->truth_scene.normals = pose + 3 * nv;
    /* Double the samples until the SAM scores move by under 0.5 dB: the
     * truth is then converged for what the report measures. */
    const technique_result *sam_r = &results[0];
    uint64_t samples = first_samples;
    for (;;) {
        truth_step *step = &steps[step_count];
        sam_image override = {0};
        st = evaluate_truth(s, &positions, &normals, samples, &override, &step->samples, &step->seconds, err);
        if (st == SAM_OK)
            st = render_pair(s->rt, &s->view, SAM_TECHNIQUE_SAM, &override, &candidate_full, &candidate_translucency,
                             err);
        sam_image_destroy(&override);
        if (st != SAM_OK)
            goto done;
        float candidate_max = max_value(&candidate_translucency);
        sam_image_comparison all, norm;
        step->sam_psnr_db = step->sam_psnr_normalised_db = NAN;
        if (sam_r->available && candidate_max > 0) {
            reference candidate_ref;
            if ((st = reference_make(s, &candidate_full, &candidate_translucency, candidate_max, &candidate_ref,
                                     err)) != SAM_OK)
                goto done;
            st = score(s, &candidate_ref, &sam_r->full, &sam_r->translucency, &all, &norm, NULL, NULL, err);
            reference_destroy(&candidate_ref);
            if (st != SAM_OK)
                goto done;
            step->sam_psnr_db = all.psnr_db;
            step->sam_psnr_normalised_db = norm.psnr_db;
        }
        say("ground truth with %llu samples: %.2f s; SAM PSNR %.2f dB, translucency %.2f dB",
            (unsigned long long)step->samples, step->seconds, step->sam_psnr_db, step->sam_psnr_normalised_db);
        sam_image_destroy(&truth_full);
        sam_image_destroy(&truth_translucency);
        truth_full = candidate_full;
        truth_translucency = candidate_translucency;
        memset(&candidate_full, 0, sizeof candidate_full);
        memset(&candidate_translucency, 0, sizeof candidate_translucency);
        ++step_count;
        if (step_count > 1) {
            const truth_step *prev = &steps[step_count - 2];
            double d1 = fabs(step->sam_psnr_db - prev->sam_psnr_db);
            double d2 = fabs(step->sam_psnr_normalised_db - prev->sam_psnr_normalised_db);
            /* Without SAM in the run (or no translucency at all) there is
             * nothing to converge for: one doubling is all we check. */
            if (!(d1 >= CONVERGED_DB) && !(d2 >= CONVERGED_DB)) {
                converged = 1;
                break;
            }
        }
        if (step_count == MAX_DOUBLINGS + 1) {
            say("warning: the ground truth still moves by 0.5 dB or more after %d doublings; the report says so",
                MAX_DOUBLINGS);
            break;
        }
        samples = 2 * step->samples;
    }
    float truth_max = max_value(&truth_translucency);
    if (!(truth_max > 0)) {
        say("warning: the ground truth has no translucency in view; normalised scores use 1");
        truth_max = 1.0f;
    }

    say("[4/5] images and scores");
    if ((st = create_dir(s->root, err)) != SAM_OK || (s->dir != s->root && (st = create_dir(s->dir, err)) != SAM_OK) ||
        (st = reference_make(s, &truth_full, &truth_translucency, truth_max, &truth_ref, err)) != SAM_OK ||
        (st = score(s, &truth_ref, &truth_full, &truth_translucency, &self.all, &self.normalised, NULL, NULL, err)) !=
            SAM_OK ||
        (st = write_images(s, results, &truth_full, &truth_translucency, &truth_ref, err)) != SAM_OK)
        goto done;

    int monotonic = 1;
    if (sweep_count) {
        say("[5/5] samples sweep");
        if ((st = run_sweep(s, sweep_n, sweep_count, &truth_ref, sweep, err)) != SAM_OK)
            goto done;
        for (int i = 1; i < sweep_count; ++i)
            if (sweep_n[i] > sweep_n[i - 1] && sweep[i].all.rmse > sweep[i - 1].all.rmse)
                monotonic = 0;
    }
    if ((st = write_reports(s, scene_path, results, &self, steps, step_count, converged, truth_max, space_name, sweep,
                            sweep_count, monotonic, err)) != SAM_OK)
        goto done;
    if (sweep_count && (st = plot_sweep(s, sweep, sweep_count, err)) != SAM_OK)
        goto done;
    say("wrote %s/report.md", s->dir);
    summary->frame = s->frame;
    summary->truth_samples = steps[step_count - 1].samples;
    summary->converged = converged;
done:
    for (int t = 0; t < MAX_TECHNIQUES; ++t) {
        sam_image_destroy(&results[t].full);
        sam_image_destroy(&results[t].translucency);
    }
    if (st == SAM_OK)
        memcpy(summary->techniques, results, sizeof summary->techniques);
    s->truth_scene.positions = s->truth_scene.normals = NULL;
    free(pose);
    sam_image_destroy(&positions);
    sam_image_destroy(&normals);
    reference_destroy(&truth_ref);
    sam_image_destroy(&truth_full);
    sam_image_destroy(&truth_translucency);
    sam_image_destroy(&candidate_full);
    sam_image_destroy(&candidate_translucency);
    return st;
}

/* " a / b / c |": a technique's PSNRs on differing pixels, all pixels and
 * the normalised translucency, as the README's tables give them. */
static void md_scores(FILE *f, const technique_result *r)
{
    if (!r->requested)
        return;
    if (!r->available) {
        fprintf(f, " unavailable |");
        return;
    }
    const double v[3] = {r->all.psnr_differing_db, r->all.psnr_db, r->normalised.psnr_db};
    for (int i = 0; i < 3; ++i)
        fprintf(f, isfinite(v[i]) ? "%s%.2f" : "%sinf", i ? " / " : " ", v[i]);
    fprintf(f, " |");
}

/* The frame folder's name: frame_NNNN, like sam_render --animate's numbers. */
static void frame_dir_name(char *out, size_t n, long frame)
{
    snprintf(out, n, "frame_%04ld", frame);
}

/* DIR/report.json and report.md of an animation: every compared frame's
 * scores side by side; each frame's full report is in its folder. Written
 * last, so a run that stops halfway leaves no report.json and is not taken
 * for a finished one. */
static sam_status write_summary(const compare_state *s, const char *scene_path, const pose_summary *poses, int count,
                                sam_error *err)
{
    char path[4096], name[32];
    sam_atomic_file f;
    sam_status st = join_path(path, sizeof path, s->root, "report.json", err);
    if (st == SAM_OK)
        st = sam_atomic_open(&f, path, err);
    if (st != SAM_OK)
        return st;
    fprintf(f.fp, "{\n  \"scene\": \"%s\",\n  \"fps\": %g,\n  \"frames\": [", sam_path_basename(scene_path),
            (double)s->fps);
    for (int i = 0; i < count; ++i) {
        const pose_summary *p = &poses[i];
        frame_dir_name(name, sizeof name, p->frame);
        fprintf(f.fp, "%s\n    {\"frame\": %ld, \"time_s\": %.6g, \"dir\": \"%s\", \"truth_samples\": %llu, "
                      "\"truth_converged\": %s, \"techniques\": [",
                i ? "," : "", p->frame, (double)((float)p->frame / s->fps), name,
                (unsigned long long)p->truth_samples, p->converged ? "true" : "false");
        int first = 1;
        for (int t = 0; t < MAX_TECHNIQUES; ++t) {
            const technique_result *r = &p->techniques[t];
            if (!r->requested)
                continue;
            fprintf(f.fp, "%s{\"name\": \"%s\", \"available\": %s", first ? "" : ", ", technique_names[t],
                    r->available ? "true" : "false");
            first = 0;
            if (r->available) {
                fprintf(f.fp, ", \"psnr_db\": ");
                json_number(f.fp, r->all.psnr_db);
                fprintf(f.fp, ", \"psnr_differing_db\": ");
                json_number(f.fp, r->all.psnr_differing_db);
                fprintf(f.fp, ", \"psnr_translucency_db\": ");
                json_number(f.fp, r->normalised.psnr_db);
            }
            fprintf(f.fp, "}");
        }
        fprintf(f.fp, "]}");
    }
    fprintf(f.fp, "\n  ]\n}\n");
    if ((st = sam_atomic_commit(&f, err)) != SAM_OK)
        return st;

    if ((st = join_path(path, sizeof path, s->root, "report.md", err)) != SAM_OK ||
        (st = sam_atomic_open(&f, path, err)) != SAM_OK)
        return st;
    fprintf(f.fp, "# sam_compare: %s, animated\n\n", sam_path_basename(scene_path));
    fprintf(f.fp, "Each frame is the pose at t = frame / %g s, played from frame 0 as `sam_render --animate` plays "
                  "it (the sample walk every frame, T smoothed with dt = 1/fps), and compared against a ground truth "
                  "of that pose. Each frame's images and full report are in its folder. PSNR in dB: differing "
                  "pixels / all object pixels / translucency normalised by the truth's maximum.\n\n",
            (double)s->fps);
    fprintf(f.fp, "| frame | t (s) | truth samples |");
    for (int t = 0; t < MAX_TECHNIQUES; ++t)
        if (poses[0].techniques[t].requested)
            fprintf(f.fp, " %s |", technique_names[t]);
    fprintf(f.fp, "\n| --- | --- | --- |");
    for (int t = 0; t < MAX_TECHNIQUES; ++t)
        if (poses[0].techniques[t].requested)
            fprintf(f.fp, " --- |");
    fprintf(f.fp, "\n");
    for (int i = 0; i < count; ++i) {
        const pose_summary *p = &poses[i];
        frame_dir_name(name, sizeof name, p->frame);
        fprintf(f.fp, "| [%ld](%s/report.md) | %.4g | %llu%s |", p->frame, name, (double)((float)p->frame / s->fps),
                (unsigned long long)p->truth_samples, p->converged ? "" : " (not converged)");
        for (int t = 0; t < MAX_TECHNIQUES; ++t)
            md_scores(f.fp, &p->techniques[t]);
        fprintf(f.fp, "\n");
    }
    return sam_atomic_commit(&f, err);
}

int main(int argc, char **argv)
{
    const char *scene_path = NULL, *dir = NULL, *techniques = "sam,none,tsm,transmittance", *sweep_list = NULL,
               *frame_list = NULL;
    long map_samples = 0, truth_samples = 0;
    float truth_tolerance = 0.01f, fps = 0;
    int force = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--force")) {
            force = 1;
        } else if (a[0] == '-' && a[1] && !has_value) {
            fprintf(stderr, "sam_compare: %s needs a value (see --help)\n", a);
            return 2;
        } else if (!strcmp(a, "--out")) {
            dir = argv[++i];
        } else if (!strcmp(a, "--techniques")) {
            techniques = argv[++i];
        } else if (!strcmp(a, "--samples-sweep")) {
            sweep_list = argv[++i];
        } else if (!strcmp(a, "--frames")) {
            frame_list = argv[++i];
        } else if (!strcmp(a, "--fps")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !(v > 0 && v <= 1000)) {
                fprintf(stderr, "sam_compare: --fps must be a number in (0, 1000], got \"%s\"\n", argv[i]);
                return 2;
            }
            fps = (float)v;
        } else if (!strcmp(a, "--truth-tolerance")) {
            double v;
            if (!sam_parse_double(argv[++i], &v) || !(v >= 0 && (float)v < 0.5f)) {
                fprintf(stderr, "sam_compare: --truth-tolerance must be a number in [0, 0.5), got \"%s\"\n", argv[i]);
                return 2;
            }
            truth_tolerance = (float)v;
        } else if (!strcmp(a, "--samples") || !strcmp(a, "--truth-samples")) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            long hi = !strcmp(a, "--samples") ? 64 : 100000000L;
            if (*end || end == argv[i] || v < 1 || v > hi) {
                fprintf(stderr, "sam_compare: %s must be an integer in 1..%ld, got \"%s\"\n", a, hi, argv[i]);
                return 2;
            }
            *(!strcmp(a, "--samples") ? &map_samples : &truth_samples) = v;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "sam_compare: unknown option \"%s\" (see --help)\n", a);
            return 2;
        } else if (!scene_path) {
            scene_path = a;
        } else {
            fprintf(stderr, "sam_compare: unexpected argument \"%s\"\n", a);
            return 2;
        }
    }
    if (!scene_path || !dir) {
        usage(stderr);
        return 2;
    }
    technique_result results[MAX_TECHNIQUES];
    memset(results, 0, sizeof results);
    for (const char *p = techniques; *p;) {
        size_t n = strcspn(p, ",");
        int found = 0;
        for (int t = 0; t < MAX_TECHNIQUES; ++t)
            if (strlen(technique_names[t]) == n && !strncmp(p, technique_names[t], n))
                results[t].requested = found = 1;
        if (!found) {
            fprintf(stderr, "sam_compare: --techniques takes sam, tsm, transmittance and none, got \"%.*s\"\n", (int)n,
                    p);
            return 2;
        }
        p += n + (p[n] == ',');
    }
    long sweep_n[MAX_SWEEP];
    int sweep_count = 0;
    if (sweep_list && !parse_int_list(sweep_list, 1, 64, sweep_n, MAX_SWEEP, &sweep_count)) {
        fprintf(stderr, "sam_compare: --samples-sweep takes up to %d comma-separated integers in 1..64, got \"%s\"\n",
                MAX_SWEEP, sweep_list);
        return 2;
    }
    /* Without --frames the one pose compared is frame 0 (t = 0). */
    long frames[MAX_FRAMES] = {0};
    int frame_count = 1;
    if (frame_list) {
        if (!parse_int_list(frame_list, 0, MAX_FRAME, frames, MAX_FRAMES, &frame_count)) {
            fprintf(stderr,
                    "sam_compare: --frames takes up to %d comma-separated frame numbers in 0..%d, got \"%s\"\n",
                    MAX_FRAMES, MAX_FRAME, frame_list);
            return 2;
        }
        for (int i = 1; i < frame_count; ++i)
            if (frames[i] <= frames[i - 1]) {
                fprintf(stderr, "sam_compare: --frames must increase, got %ld after %ld in \"%s\"\n", frames[i],
                        frames[i - 1], frame_list);
                return 2;
            }
        if (sweep_count) {
            fprintf(stderr, "sam_compare: --samples-sweep rebuilds the rest pose's map; give it without --frames\n");
            return 2;
        }
    } else if (fps > 0) {
        fprintf(stderr, "sam_compare: --fps sets the times of --frames; give --frames too\n");
        return 2;
    }

    compare_state s;
    memset(&s, 0, sizeof s);
    s.root = s.dir = dir;
    s.truth_tolerance = truth_tolerance;
    s.fps = fps > 0 ? fps : DEFAULT_FPS;
    sam_error err;
    int code = 1;
    sam_gl_context *gl = NULL;
    pose_summary poses[MAX_FRAMES];
    memset(poses, 0, sizeof poses);
    char warning[512];
    if (sam_scene_load(scene_path, &s.scene, &err) != SAM_OK) {
        say("%s", err.message);
        return 1;
    }
    s.animated = s.scene.deformer_count || s.scene.keyframe_count;
    if (sweep_count && !s.scene.mesh_path) {
        say("%s: --samples-sweep rebuilds the map, so the scene must name a mesh", scene_path);
        sam_scene_destroy(&s.scene);
        return 2;
    }
    if (frame_list && !s.animated) {
        say("%s has no \"deformers\" or \"keyframes\": --frames compares frames of an animation (give it without "
            "--frames to compare the scene)",
            scene_path);
        sam_scene_destroy(&s.scene);
        return 2;
    }
    if (check_dir(dir, force, &err) != SAM_OK)
        goto done;
    if (s.animated && !frame_list)
        say("note: the scene is animated; comparing frame 0, the pose at t = 0 (--frames LIST [--fps F] picks "
            "the frames)");

    say("[1/5] the map");
    progress_state bps = {"building the map", -1};
    sam_build_settings build;
    sam_build_default_settings(&build);
    if (map_samples)
        build.samples_per_vertex = (uint32_t)map_samples;
    if (sam_app_scene_object(&s.scene, &build, build_progress, &bps, &s.sam, &s.profile, &s.mm_per_unit,
                               &s.build_seconds, &err) != SAM_OK)
        goto done;
    if (sam_gl_context_create_headless(&gl, &err) != SAM_OK ||
        sam_runtime_create(&s.sam, &s.profile, s.mm_per_unit, &s.rt, &err) != SAM_OK ||
        sam_runtime_scene_setup(s.rt, &s.scene, s.sh, &s.has_environment, warning, sizeof warning, &err) != SAM_OK ||
        sam_runtime_scene_keyframes(s.rt, &s.scene, &s.sam, &err) != SAM_OK)
        goto done;
    if (warning[0])
        say("warning: %s", warning);
    sam_runtime_scene_view(s.rt, &s.scene, &s.view, warning, sizeof warning);
    if (warning[0])
        say("warning: %s", warning);
    /* Lossy texture-space optimisations would change the picture under comparison. */
    s.view.options.culled = 0;
    s.view.options.depth_sized = 0;
    s.truth_scene.vertex_count = s.sam.vertex_count;
    s.truth_scene.triangle_count = s.sam.triangle_count;
    s.truth_scene.triangles = s.sam.triangles;
    s.truth_scene.mm_per_unit = s.mm_per_unit;
    s.truth_scene.profile = &s.profile;
    s.truth_scene.lights = s.scene.lights;
    s.truth_scene.light_count = s.scene.light_count;
    s.truth_scene.sh = s.has_environment ? (const float(*)[3])s.sh : NULL;
    s.truth_scene.environment_rho_dt = sam_runtime_environment_rho_dt(s.rt);
    s.truth_scene.rho_dt = rho_dt_of;
    s.truth_scene.rho_dt_user = s.rt;
    /* A query costs one test per sample in reach, so start small and let
     * the doublings find the count that the scores no longer notice. */
    uint64_t first_samples = truth_samples ? (uint64_t)truth_samples : SAM_TRUTH_MIN_SAMPLES;

    /* Every frame up to the last one compared is played as sam_render
     * --animate plays it: the pose at t = frame / fps, the sample walk, L_d,
     * and T smoothed with dt = 1 / fps (reset at frame 0). The walk moves
     * samples one ring per frame and T carries its history, so a frame is
     * only what a viewer sees when every frame before it has run. */
    char frame_dir[4096];
    for (long f = 0, next = 0; next < frame_count; ++f) {
        if (s.animated &&
            (sam_runtime_deform(s.rt, (float)f / s.fps, &err) != SAM_OK || sam_runtime_walk(s.rt, &err) != SAM_OK))
            goto done;
        if (sam_runtime_irradiance(s.rt, &err) != SAM_OK ||
            sam_runtime_translucency(s.rt, 0, 1.0f / s.fps, f == 0, &err) != SAM_OK)
            goto done;
        if (f != frames[next])
            continue;
        s.frame = f;
        if (frame_list) {
            char name[32];
            frame_dir_name(name, sizeof name, f);
            if (join_path(frame_dir, sizeof frame_dir, dir, name, &err) != SAM_OK)
                goto done;
            s.dir = frame_dir;
            say("frame %ld (t = %.4g s), %d of %d", f, (double)((float)f / s.fps), (int)next + 1, frame_count);
        }
        if (compare_pose(&s, scene_path, results, first_samples, sweep_n, sweep_count, &poses[next], &err) != SAM_OK)
            goto done;
        ++next;
    }
    if (frame_list) {
        if (write_summary(&s, scene_path, poses, frame_count, &err) != SAM_OK)
            goto done;
        say("wrote %s/report.md", dir);
    }
    code = 0;
done:
    if (code)
        say("%s", err.message);
    sam_runtime_destroy(s.rt);
    sam_gl_context_destroy(gl);
    samfile_free(&s.sam);
    sam_scene_destroy(&s.scene);
    return code;
}
