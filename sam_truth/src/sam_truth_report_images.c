/* Scores against the ground truth and the comparison's images
 * (sam_truth_report.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sam/sam_scene.h"
#include "sam/sam_truth_report.h"

/* The scene files' names, so a report and a scene never disagree. */
const char *sam_truth_report_technique_name(int t)
{
    return sam_technique_name((sam_technique)t);
}

sam_status sam_truth_report_path(char *out, size_t n, const char *dir, const char *name, sam_error *err)
{
    int len = snprintf(out, n, "%s/%s", dir, name);
    if (len < 0 || (size_t)len >= n)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "output path %s/%s is too long", dir, name);
    return SAM_OK;
}

/* The display image of a render: tonemapped with the scene's curve over black. */
static sam_status display(const sam_truth_report_reference *ref, const sam_image *hdr, sam_image *out,
                          sam_error *err)
{
    static const float black[3] = {0, 0, 0};
    return sam_image_tonemap(hdr, ref->tonemap, ref->exposure, black, out, err);
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

float sam_truth_report_max_value(const sam_image *img)
{
    float m = 0;
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; ++i)
        if (img->pixels[i * 4 + 3] > 0)
            for (int c = 0; c < 3; ++c)
                m = fmaxf(m, img->pixels[i * 4 + (size_t)c]);
    return m;
}

void sam_truth_report_reference_destroy(sam_truth_report_reference *ref)
{
    sam_image_destroy(&ref->shown);
    sam_image_destroy(&ref->norm);
}

sam_status sam_truth_report_reference_make(sam_tonemap tonemap, float exposure, const sam_image *full,
                                           const sam_image *translucency, float max,
                                           sam_truth_report_reference *ref, sam_error *err)
{
    memset(ref, 0, sizeof *ref);
    ref->mask = full;
    ref->max = max;
    ref->tonemap = tonemap;
    ref->exposure = exposure;
    sam_status st = display(ref, full, &ref->shown, err);
    if (st == SAM_OK)
        st = normalised(translucency, max, &ref->norm, err);
    if (st != SAM_OK)
        sam_truth_report_reference_destroy(ref);
    return st;
}

sam_status sam_truth_report_score(const sam_truth_report_reference *ref, const sam_image *full,
                                  const sam_image *translucency, sam_image_comparison *all,
                                  sam_image_comparison *normal, sam_image *shown, sam_image *norm, sam_error *err)
{
    sam_image a = {0}, b = {0};
    sam_status st = display(ref, full, &a, err);
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

/* Writes NAME.exr and NAME.png (the display image `shown`). */
static sam_status write_pair(const char *dir, const char *name, const sam_image *hdr, const sam_image *shown,
                             sam_error *err)
{
    char path[4096], file[256];
    snprintf(file, sizeof file, "%s.exr", name);
    sam_status st = sam_truth_report_path(path, sizeof path, dir, file, err);
    if (st == SAM_OK)
        st = sam_image_write_exr(path, hdr, SAM_EXR_FLOAT, err);
    snprintf(file, sizeof file, "%s.png", name);
    if (st == SAM_OK)
        st = sam_truth_report_path(path, sizeof path, dir, file, err);
    if (st == SAM_OK)
        st = sam_image_write_png(path, shown, SAM_PNG_SRGB, err);
    return st;
}

/* |a - b| x 4 of two display images as they look in 8-bit sRGB (the
 * paper's enhanced difference images). */
static sam_status write_difference(const char *dir, const char *name, const sam_image *a, const sam_image *b,
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
    st = sam_truth_report_path(path, sizeof path, dir, file, err);
    if (st == SAM_OK)
        st = sam_image_write_png(path, &d, SAM_PNG_LINEAR, err);
    sam_image_destroy(&d);
    return st;
}

/* Each panel's name at its top-left corner, white on a black outline so
 * that it reads on a lit object and on the background alike: which panel
 * is which changes when a technique cannot run. */
static void label_panels(sam_image *row, const sam_image *panels, const char *const *names, int count)
{
    static const float black[3] = {0, 0, 0}, white[3] = {1, 1, 1};
    const int scale = row->height >= 360 ? 2 : 1;
    for (int i = 0, x0 = 0; i < count; x0 += (int)panels[i++].width) {
        if (sam_image_text_width(names[i], scale) + 8 > (int)panels[i].width)
            continue; /* a panel too narrow for its name goes without */
        for (int d = 0; d < 9; ++d)
            if (d != 4)
                sam_image_draw_text(row, x0 + 4 + d % 3 - 1, 4 + d / 3 - 1, scale, black, names[i]);
        sam_image_draw_text(row, x0 + 4, 4, scale, white, names[i]);
    }
}

/* row.png and translucency_row.png: the `count` display and normalised
 * images side by side, each named. */
static sam_status write_rows(const char *dir, const sam_image *shown, const sam_image *norm,
                             const char *const *names, int count, sam_error *err)
{
    sam_image row = {0}, row_t = {0};
    sam_status st = sam_image_row(shown, (uint32_t)count, &row, err);
    if (st == SAM_OK)
        st = sam_image_row(norm, (uint32_t)count, &row_t, err);
    if (st == SAM_OK) {
        label_panels(&row, shown, names, count);
        label_panels(&row_t, norm, names, count);
        char path[4096];
        st = sam_truth_report_path(path, sizeof path, dir, "row.png", err);
        if (st == SAM_OK)
            st = sam_image_write_png(path, &row, SAM_PNG_SRGB, err);
        if (st == SAM_OK)
            st = sam_truth_report_path(path, sizeof path, dir, "translucency_row.png", err);
        if (st == SAM_OK)
            st = sam_image_write_png(path, &row_t, SAM_PNG_SRGB, err);
    }
    sam_image_destroy(&row);
    sam_image_destroy(&row_t);
    return st;
}

sam_status sam_truth_report_write_images(const char *dir, sam_truth_report_technique *techniques,
                                         const sam_image *truth_full, const sam_image *truth_translucency,
                                         const sam_truth_report_reference *ref, sam_error *err)
{
    /* shown[0] and norm[0] are the reference's; the caller owns them. */
    sam_image shown[SAM_TRUTH_REPORT_TECHNIQUES + 1], norm[SAM_TRUTH_REPORT_TECHNIQUES + 1];
    memset(shown, 0, sizeof shown);
    memset(norm, 0, sizeof norm);
    shown[0] = ref->shown;
    norm[0] = ref->norm;
    sam_status st = write_pair(dir, "truth", truth_full, &shown[0], err);
    if (st == SAM_OK)
        st = write_pair(dir, "truth_translucency", truth_translucency, &norm[0], err);
    const char *names[SAM_TRUTH_REPORT_TECHNIQUES + 1] = {"truth"};
    int count = 1;
    for (int t = 0; t < SAM_TRUTH_REPORT_TECHNIQUES && st == SAM_OK; ++t) {
        sam_truth_report_technique *r = &techniques[t];
        if (!r->available)
            continue;
        char name[128];
        sam_image *a = &shown[count], *b = &norm[count];
        names[count++] = sam_truth_report_technique_name(t);
        st = sam_truth_report_score(ref, &r->full, &r->translucency, &r->all, &r->normalised, a, b, err);
        if (st == SAM_OK)
            st = write_pair(dir, sam_truth_report_technique_name(t), &r->full, a, err);
        snprintf(name, sizeof name, "%s_diff4", sam_truth_report_technique_name(t));
        if (st == SAM_OK)
            st = write_difference(dir, name, a, &shown[0], err);
        snprintf(name, sizeof name, "%s_translucency", sam_truth_report_technique_name(t));
        if (st == SAM_OK)
            st = write_pair(dir, name, &r->translucency, b, err);
        snprintf(name, sizeof name, "%s_translucency_diff4", sam_truth_report_technique_name(t));
        if (st == SAM_OK)
            st = write_difference(dir, name, b, &norm[0], err);
    }
    if (st == SAM_OK)
        st = write_rows(dir, shown, norm, names, count, err);
    for (int i = 1; i <= SAM_TRUTH_REPORT_TECHNIQUES; ++i) {
        sam_image_destroy(&shown[i]);
        sam_image_destroy(&norm[i]);
    }
    return st;
}
