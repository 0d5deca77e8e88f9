/*
 * sam_truth_report: scores against a hand-made truth (an exact match and a
 * known difference in 8-bit levels), report.json and report.md of a
 * hand-made result, an animation's summary, the difference and row images,
 * and the output folder's refusal to overwrite a report.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sam/sam_truth_report.h"
#include "sam_test.h"

#define W 4
#define H 2

/* A W x H RGBA image of colour (v, v, v) and alpha 1. */
static void flat_sized(sam_image *img, uint32_t w, uint32_t h, float v)
{
    sam_error err;
    assert_int_equal(sam_image_create(img, w, h, 4, &err), SAM_OK);
    for (size_t i = 0; i < (size_t)w * h; ++i) {
        float *p = img->pixels + i * 4;
        p[0] = p[1] = p[2] = v;
        p[3] = 1;
    }
}

static void flat(sam_image *img, float v)
{
    flat_sized(img, W, H, v);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    return buf;
}

/* Each of the `count` strings of `wanted` is in `text`. */
static void assert_all(const char *text, const char *const *wanted, size_t count)
{
    for (size_t i = 0; i < count; ++i)
        if (!strstr(text, wanted[i]))
            fail_msg("\"%s\" not in:\n%s", wanted[i], text);
}

static void test_score_identical(void **state)
{
    (void)state;
    sam_image full, translucency;
    flat(&full, 0.5f);
    flat(&translucency, 0.25f);
    sam_truth_report_reference ref;
    sam_error err;
    assert_int_equal(sam_truth_report_reference_make(SAM_TONEMAP_ACES, 0, &full, &translucency, 0.25f, &ref, &err),
                     SAM_OK);
    sam_image_comparison all, norm;
    assert_int_equal(sam_truth_report_score(&ref, &full, &translucency, &all, &norm, NULL, NULL, &err), SAM_OK);
    assert_int_equal(all.pixels, W * H);
    assert_int_equal(all.differing_pixels, 0);
    assert_true(isinf(all.psnr_db) && all.psnr_db > 0);
    assert_true(all.rmse == 0);
    assert_true(isinf(norm.psnr_db) && norm.psnr_db > 0);
    assert_true(sam_truth_report_max_value(&translucency) == 0.25f);
    sam_truth_report_reference_destroy(&ref);
    sam_image_destroy(&full);
    sam_image_destroy(&translucency);
}

/* The truth's translucency is its maximum everywhere (255 once
 * normalised); the candidate's is 0 on half the pixels: 255 levels off in
 * every channel of half the pixels, an RMSE of 255 / sqrt(2). */
static void test_score_known_difference(void **state)
{
    (void)state;
    sam_image full, truth_t, candidate_t, shown = {0}, norm_img = {0};
    flat(&full, 0.5f);
    flat(&truth_t, 2.0f);
    flat(&candidate_t, 2.0f);
    for (size_t i = 0; i < (size_t)W * H / 2; ++i)
        candidate_t.pixels[i * 4] = candidate_t.pixels[i * 4 + 1] = candidate_t.pixels[i * 4 + 2] = 0;
    sam_truth_report_reference ref;
    sam_error err;
    assert_int_equal(sam_truth_report_reference_make(SAM_TONEMAP_REINHARD, 0, &full, &truth_t,
                                                     sam_truth_report_max_value(&truth_t), &ref, &err),
                     SAM_OK);
    sam_image_comparison all, norm;
    assert_int_equal(sam_truth_report_score(&ref, &full, &candidate_t, &all, &norm, &shown, &norm_img, &err), SAM_OK);
    assert_true(isinf(all.psnr_db));
    assert_int_equal(norm.pixels, W * H);
    assert_int_equal(norm.differing_pixels, W * H / 2);
    assert_float_equal(norm.rmse, 255.0 / sqrt(2.0), 1e-9);
    assert_float_equal(norm.psnr_db, 20 * log10(sqrt(2.0)), 1e-9);
    assert_float_equal(norm.rmse_differing, 255.0, 1e-9);
    /* The normalised image handed back is the candidate's, clamped to [0, 1]. */
    assert_int_equal(norm_img.channels, 3);
    assert_true(norm_img.pixels[0] == 0 && norm_img.pixels[3 * (W * H - 1)] == 1);
    assert_int_equal(shown.width, W);
    sam_image_destroy(&shown);
    sam_image_destroy(&norm_img);
    sam_truth_report_reference_destroy(&ref);
    sam_image_destroy(&full);
    sam_image_destroy(&truth_t);
    sam_image_destroy(&candidate_t);
}

static void make_dir(char *dir, size_t n, const char *name)
{
    sam_error err;
    sam_test_tmp_path(dir, n, name);
    assert_int_equal(sam_truth_report_make_dir(dir, &err), SAM_OK);
}

/* sam: scored, with an exact match on the differing pixels; tsm:
 * unavailable; none and transmittance: not requested. */
static void hand_made(sam_truth_report_technique *t)
{
    memset(t, 0, SAM_TRUTH_REPORT_TECHNIQUES * sizeof *t);
    t[0].requested = t[0].available = 1;
    t[0].all = (sam_image_comparison){100, 10, 2.5, 40.1234, 7.5, INFINITY};
    t[0].normalised = (sam_image_comparison){100, 20, 3.0, 38.5, 6.0, 32.25};
    t[2].requested = 1;
    snprintf(t[2].reason, sizeof t[2].reason, "no shadow maps here");
}

static void test_write_report(void **state)
{
    (void)state;
    char dir[4096], path[4200];
    make_dir(dir, sizeof dir, "truth_report");
    sam_truth_report_technique t[SAM_TRUTH_REPORT_TECHNIQUES], self;
    hand_made(t);
    memset(&self, 0, sizeof self);
    self.all.psnr_db = self.normalised.psnr_db = INFINITY;
    const sam_truth_report_step steps[2] = {{4096, 1.5, 30.0, NAN}, {8192, 3.0, 31.0, 29.0}};
    const sam_truth_report_sweep_point sweep[2] = {
        {3, 32, 0.5, {.rmse = 4.0}, {.rmse = 5.0}, 1, {.rmse = 6.0}, {.rmse = 7.0}, {.rmse = 3.5}, {.rmse = 4.25}},
        {5, 32, 0.75, {.rmse = 3.0}, {.rmse = 4.5}, 1, {.rmse = 5.5}, {.rmse = 6.5}, {.rmse = 2.5}, {.rmse = 3.75}}};
    const sam_truth_report report = {.scene_path = "scenes/slab.json", .width = 64, .height = 48,
                                     .vertex_count = 1234, .samples_per_vertex = 3, .map = "flat", .build_seconds = 2.0,
                                     .diffusion = 3, .animated = 1, .frame = 15, .fps = 30, .truth_tolerance = 0.01f,
                                     .techniques = t, .self = &self, .steps = steps, .step_count = 2,
                                     .converged = 0, .truth_max = 0.75f, .translucency_share = 0.004,
                                     .space = "atlas texel", .sweep = sweep,
                                     .sweep_count = 2, .monotonic = 1};
    sam_error err;
    assert_int_equal(sam_truth_report_write(dir, &report, &err), SAM_OK);
    snprintf(path, sizeof path, "%s/report.json", dir);
    const char *json = slurp(path);
    static const char *const json_has[] = {
        "\"scene\": \"slab.json\"",
        "\"resolution\": [64, 48]",
        "\"vertices\": 1234",
        "\"frame\": 15,\n  \"time_s\": 0.5,\n  \"fps\": 30,",
        "\"diffusion\": \"texture\"",
        "\"map\": \"flat\"",
        "\"truth\": {\"samples\": 8192, \"seconds\": 3.000, \"space\": \"atlas texel\"",
        "\"translucency_share\": 0.004,",
        "\"converged\": false",
        "\"sam_psnr_translucency_db\": null}",
        "\"self_psnr_db\": null",
        /* One entry split over two lines (parenthesised: clang's -Wstring-concatenation). */
        ("{\"name\": \"sam\", \"available\": true, \"pixels\": 100, \"differing_pixels\": 10, "
         "\"psnr_db\": 40.1234, \"rmse\": 2.5000, \"psnr_differing_db\": null"),
        "{\"name\": \"tsm\", \"available\": false, \"reason\": \"no shadow maps here\"}",
        "\"rmse_falls_monotonically\": true",
        "{\"n\": 5, \"build_seconds\": 0.750, \"rmse\": 3.0000, \"rmse_translucency\": 4.5000",
        "\"cut_budget\": 32, \"flat_rmse\": 5.5000, \"flat_rmse_translucency\": 6.5000, \"flat_scaled_rmse\": 2.5000, "
        "\"flat_scaled_rmse_translucency\": 3.7500",
    };
    assert_all(json, json_has, sizeof json_has / sizeof *json_has);
    assert_null(strstr(json, "\"none\""));
    snprintf(path, sizeof path, "%s/report.md", dir);
    const char *md = slurp(path);
    static const char *const md_has[] = {
        "# sam_compare: slab.json\n",
        "64x48, 1234 vertices, N = 3 back-side samples per vertex (flat map), texture diffusion.",
        "Frame 15 of the animation at 30 fps (t = 0.5 s)",
        "| 8192 | 3.00 | 31.00 | 29.00 |",
        "**Not converged**",
        "| sam | 40.12 | 2.500 | inf | 10 of 100 | 38.50 | 3.000 |",
        "| tsm | unavailable: no shadow maps here |",
        "RMSE falls monotonically",
        "| N | cut budget | build s |",
        "| 3 | 32 | 0.50 | 4.0000 | 5.0000 | 6.0000 | 7.0000 | 3.5000 | 4.2500 |",
        "flat map RMSE",
        "flat-scaled translucency RMSE",
        ("The truth's translucency is 0.4% of its light: the translucency scores judge a part of the picture "
         "hardly seen."),
    };
    assert_all(md, md_has, sizeof md_has / sizeof *md_has);
    /* A folder that holds a report is refused unless forced. */
    assert_int_equal(sam_truth_report_check_dir(dir, 0, &err), SAM_ERR_IO);
    assert_non_null(strstr(err.message, "already holds a report"));
    assert_int_equal(sam_truth_report_check_dir(dir, 1, &err), SAM_OK);
}

static void test_write_summary(void **state)
{
    (void)state;
    char dir[4096], path[4200];
    make_dir(dir, sizeof dir, "truth_report_summary");
    sam_truth_report_pose poses[2];
    memset(poses, 0, sizeof poses);
    for (int i = 0; i < 2; ++i) {
        hand_made(poses[i].techniques);
        poses[i].frame = 10 * i;
        poses[i].truth_samples = 65536;
        poses[i].converged = i == 0;
    }
    sam_error err;
    assert_int_equal(sam_truth_report_write_summary(dir, "anim.json", 10, poses, 2, &err), SAM_OK);
    snprintf(path, sizeof path, "%s/report.json", dir);
    const char *json = slurp(path);
    static const char *const json_has[] = {
        "{\"frame\": 10, \"time_s\": 1, \"dir\": \"frame_0010\", \"truth_samples\": 65536, "
        "\"truth_converged\": false",
        "{\"name\": \"tsm\", \"available\": false}",
    };
    assert_all(json, json_has, sizeof json_has / sizeof *json_has);
    snprintf(path, sizeof path, "%s/report.md", dir);
    const char *md = slurp(path);
    static const char *const md_has[] = {
        "| frame | t (s) | truth samples | sam | tsm |\n| --- | --- | --- | --- | --- |\n",
        "| [10](frame_0010/report.md) | 1 | 65536 (not converged) | inf / 40.12 / 38.50 | unavailable |",
    };
    assert_all(md, md_has, sizeof md_has / sizeof *md_has);
}

/* The images of one technique that matches the truth: its differences are
 * black and the rows hold the truth and it side by side. */
static void test_write_images(void **state)
{
    (void)state;
    char dir[4096], path[4200];
    make_dir(dir, sizeof dir, "truth_report_images");
    sam_truth_report_technique t[SAM_TRUTH_REPORT_TECHNIQUES];
    memset(t, 0, sizeof t);
    sam_image full, translucency;
    /* Wide enough for the rows' names. */
    enum { RW = 64, RH = 32 };
    flat_sized(&full, RW, RH, 0.5f);
    flat_sized(&translucency, RW, RH, 0.25f);
    t[1].requested = t[1].available = 1;
    t[1].full = full;
    t[1].translucency = translucency;
    sam_truth_report_reference ref;
    sam_error err;
    assert_int_equal(sam_truth_report_reference_make(SAM_TONEMAP_ACES, 0, &full, &translucency, 0.25f, &ref, &err),
                     SAM_OK);
    assert_int_equal(sam_truth_report_write_images(dir, t, &full, &translucency, &ref, &err), SAM_OK);
    assert_true(isinf(t[1].all.psnr_db));
    sam_image img;
    snprintf(path, sizeof path, "%s/none_diff4.png", dir);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    for (size_t i = 0; i < (size_t)img.width * img.height * img.channels; ++i)
        assert_true(img.pixels[i] == 0);
    sam_image_destroy(&img);
    snprintf(path, sizeof path, "%s/translucency_row.png", dir);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    assert_int_equal(img.width, 2 * RW);
    assert_int_equal(img.height, RH);
    sam_image_destroy(&img);
    /* Each panel is named in white on black at its top-left ("truth",
     * "none"), and only there: the flat grey below is untouched. */
    snprintf(path, sizeof path, "%s/row.png", dir);
    assert_int_equal(sam_image_read_png(path, &img, SAM_PNG_LINEAR, &err), SAM_OK);
    for (int panel = 0; panel < 2; ++panel) {
        size_t white = 0, changed_below = 0;
        for (uint32_t y = 0; y < img.height; ++y)
            for (uint32_t x = (uint32_t)panel * RW; x < (uint32_t)(panel + 1) * RW; ++x) {
                const float *p = img.pixels + ((size_t)y * img.width + x) * img.channels;
                white += y < 24 && p[0] == 1.0f && p[1] == 1.0f && p[2] == 1.0f;
                changed_below += y >= 24 && (p[0] == 1.0f || p[0] == 0.0f);
            }
        assert_true(white > 10);
        assert_int_equal(changed_below, 0);
    }
    sam_image_destroy(&img);
    const char *names[] = {"truth.exr", "truth_translucency.png", "none.exr", "none_translucency.exr", "row.png"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        assert_true(sam_test_file_exists(path));
    }
    sam_truth_report_reference_destroy(&ref);
    sam_image_destroy(&full);
    sam_image_destroy(&translucency);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_score_identical),
        cmocka_unit_test(test_score_known_difference),
        cmocka_unit_test(test_write_report),
        cmocka_unit_test(test_write_summary),
        cmocka_unit_test(test_write_images),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
