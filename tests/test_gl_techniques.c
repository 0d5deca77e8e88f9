/*
 * The comparison techniques and the ground truth's hooks on llvmpipe:
 * Jimenez's transmittance and d'Eon's translucent shadow maps through a
 * back-lit slab of known thickness against the analytic sum of Gaussians,
 * the local-thickness technique against the profile's slab transmission
 * (thin parts brighter than thick ones, nothing where no light reaches),
 * what they leave out (area lights, the environment, the lit side), the
 * per-pixel / per-texel translucency override, and the G-buffer read-back.
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

#include "sam/sam_build.h"
#include "sam/sam_runtime.h"
#include "sam/sam_thickness.h"
#include "sam_test.h"

#define PI 3.14159265358979323846
#define SIZE 64                 /* render side, pixels */
#define ATLAS 512
#define SLAB_MM_PER_UNIT 40.0f  /* a 40 x 40 mm slab ... */
#define SLAB_THICKNESS 0.05     /* ... 2 mm thick */

/* A built-in skin shape on the GPU; the caller frees `d` and `rt`. */
static sam_runtime *shape_runtime(const char *name, int resolution, double thickness, float mm, sam_profile *profile,
                                  samfile_data *d)
{
    sam_mesh mesh;
    sam_error err;
    sam_test_shape_mesh(name, resolution, 1.0, thickness, 0, &mesh);
    assert_int_equal(sam_profile_preset("skin", profile, NULL), SAM_OK);
    if (sam_build_samfile(&mesh, profile, mm, NULL, NULL, NULL, NULL, d, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_mesh_destroy(&mesh);
    sam_runtime *rt;
    if (sam_runtime_create(d, profile, mm, &rt, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return rt;
}

/* The slab lit from above by a shadowed directional light of irradiance 1
 * travelling down (-y), its irradiance and SAM translucency computed. */
static sam_runtime *lit_slab(sam_profile *profile, samfile_data *d)
{
    sam_runtime *rt = shape_runtime("slab", 16, SLAB_THICKNESS, SLAB_MM_PER_UNIT, profile, d);
    sam_light l;
    memset(&l, 0, sizeof l);
    l.type = SAM_LIGHT_DIRECTIONAL;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    l.intensity = 1.0f;
    l.direction[1] = -1.0f;
    l.shadow = 1;
    sam_error err;
    assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
    assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
    return rt;
}

/* Looking straight at the slab's unlit bottom face (below = 1) or its lit
 * top, translucency only, white albedo. */
static void slab_view(sam_render_view *view, int below, int diffusion, sam_technique technique)
{
    memset(view, 0, sizeof *view);
    view->width = view->height = SIZE;
    view->fov_deg = 30.0f;
    view->eye[1] = below ? -3.0f : 3.0f;
    view->up[2] = 1.0f;
    view->albedo[0] = view->albedo[1] = view->albedo[2] = 1.0f;
    view->diffusion = diffusion;
    view->technique = technique;
    view->options.atlas_size = ATLAS;
}

static void render(sam_runtime *rt, const sam_render_view *view, sam_image *out)
{
    sam_error err;
    if (sam_runtime_render(rt, view, out, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

static const float *centre_pixel(const sam_image *img)
{
    return img->pixels + 4 * ((size_t)(img->height / 2) * img->width + img->width / 2);
}

/* sum_i w_i exp(-d^2 / 2 v_i) of the runtime's fit for d mm. */
static void slab_transmission(const sam_profile *profile, double d, double out[3])
{
    sam_gaussian_fit fit;
    sam_error err;
    assert_int_equal(sam_profile_fit_gaussians(profile, &fit, &err), SAM_OK);
    out[0] = out[1] = out[2] = 0;
    for (uint32_t i = 0; i < fit.count; ++i)
        for (int c = 0; c < 3; ++c)
            out[c] += fit.weight[i][c] * exp(-d * d / (2.0 * fit.variance[i]));
}

/* Largest value of any channel on the object. */
static double image_max(const sam_image *img)
{
    double m = 0;
    for (size_t i = 0; i < (size_t)img->width * img->height; ++i)
        for (int c = 0; c < 3; ++c)
            m = fmax(m, img->pixels[4 * i + c]);
    return m;
}

/* Renders slab_view's view; the caller destroys `img`. */
static void render_slab(sam_runtime *rt, int below, int diffusion, sam_technique technique, sam_image *img)
{
    sam_render_view view;
    slab_view(&view, below, diffusion, technique);
    render(rt, &view, img);
}

/* The centre pixel's red and green against scale * t[c], to a relative
 * `tolerance`; `what` names the render in the log. */
static void assert_centre_near(const sam_image *img, double scale, const double t[3], double tolerance,
                               const char *what)
{
    const float *px = centre_pixel(img);
    for (int c = 0; c < 2; ++c) {
        double want = scale * t[c], rel = fabs(px[c] - want) / want;
        print_message("%s, channel %d: %.6g, analytic %.6g, relative error %.4f\n", what, c, px[c], want, rel);
        assert_true(rel < tolerance);
    }
}

/* image_max of the render_slab picture. */
static double slab_max(sam_runtime *rt, int below, int diffusion, sam_technique technique)
{
    sam_image img;
    render_slab(rt, below, diffusion, technique, &img);
    double m = image_max(&img);
    sam_image_destroy(&img);
    return m;
}

/* Behind a 2 mm slab lit at irradiance E = 1 head-on, Jimenez's
 * transmittance is E sum_i w_i exp(-d^2 / 2v_i) saturate(0.3 + 1) at the
 * bottom's centre, which the camera sees at N.V = 1 through the shading
 * factor rho_dt(1) / pi (albedo 1): the same in every diffusion mode, since
 * every blur keeps a uniform region's value. Zero on the lit top. */
static void test_transmittance_through_slab(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_slab(&profile, &d);
    double t[3];
    slab_transmission(&profile, SLAB_THICKNESS * SLAB_MM_PER_UNIT, t);
    double factor = sam_runtime_rho_dt(rt, 1.0f) / PI;
    for (int mode = 0; mode <= 3; ++mode) {
        sam_image img;
        render_slab(rt, 1, mode, SAM_TECHNIQUE_TRANSMITTANCE, &img);
        char what[64];
        snprintf(what, sizeof what, "transmittance, diffusion %d", mode);
        assert_centre_near(&img, factor, t, 0.02, what);
        sam_image_destroy(&img);
        render_slab(rt, 0, mode, SAM_TECHNIQUE_TRANSMITTANCE, &img);
        print_message("transmittance, diffusion %d, lit side's centre: %.3g\n", mode, centre_pixel(&img)[0]);
        assert_true(centre_pixel(&img)[0] == 0.0f);
        sam_image_destroy(&img);
    }
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* The TSM at the bottom's centre: the top's entering light E rho_dt(1)
 * (times R_total, which the level weights w_i / R_total take back) through
 * d = m = 2 mm, the fade at 1 (the top's chart is far away in the atlas):
 * E rho_dt(1) sum_i w_i exp(-d^2 / 2v_i), seen through rho_dt(1) / pi.
 * Held to 5%: the levels are the blur's 7-tap Gaussians, not exact ones.
 * Nothing on the lit side, where the pixel is not in shadow. */
static void test_tsm_through_slab(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_slab(&profile, &d);
    double t[3];
    slab_transmission(&profile, SLAB_THICKNESS * SLAB_MM_PER_UNIT, t);
    double factor = sam_runtime_rho_dt(rt, 1.0f) / PI, entering = sam_runtime_rho_dt(rt, 1.0f);
    sam_image img;
    render_slab(rt, 1, 3, SAM_TECHNIQUE_TSM, &img);
    assert_centre_near(&img, factor * entering, t, 0.05, "tsm");
    sam_image_destroy(&img);
    double lit = slab_max(rt, 0, 3, SAM_TECHNIQUE_TSM);
    print_message("tsm, lit side: largest value %.3g\n", lit);
    assert_true(lit == 0.0);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* The slab's local thickness from sam_thickness (Embree): its depth, 2 mm,
 * at every face vertex away from the sides. The caller frees it. */
static float *slab_thickness(const samfile_data *d)
{
    float *t = malloc(d->vertex_count * sizeof *t);
    assert_non_null(t);
    sam_thickness_surface s = {d->vertex_count, d->positions, d->normals, d->triangle_count, d->triangles};
    sam_error err;
    if (sam_thickness_compute(&s, SLAB_MM_PER_UNIT, NULL, NULL, NULL, t, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return t;
}

/* Mean red of the covered pixels (G-buffer of `view`) whose position's x
 * lies in [x0, x1] and |z| < 0.3, and how many there were. */
static double mean_red_over_x(sam_runtime *rt, const sam_render_view *view, const sam_image *img, double x0, double x1,
                              size_t *count)
{
    sam_image pos, nrm;
    sam_error err;
    assert_int_equal(sam_runtime_gbuffer(rt, view, SAM_GBUFFER_SCREEN, &pos, &nrm, &err), SAM_OK);
    double sum = 0;
    *count = 0;
    for (size_t i = 0; i < (size_t)pos.width * pos.height; ++i) {
        const float *p = pos.pixels + 4 * i;
        if (p[3] > 0 && p[0] >= x0 && p[0] <= x1 && fabs(p[2]) < 0.3) {
            sum += img->pixels[4 * i];
            ++*count;
        }
    }
    sam_image_destroy(&pos);
    sam_image_destroy(&nrm);
    return *count ? sum / (double)*count : 0.0;
}

/* Local thickness (Barre-Brisebois and Bouchard) behind the slab lit at
 * E = 1 head-on: the bottom's inverted normal faces the light, so
 * T = E rho_dt(1) G(t), seen through rho_dt(1) / pi. With the thickness
 * sam_thickness measures (2 mm) at the centre, in every diffusion mode;
 * with 1 mm given on the x < 0 half and 4 mm on the other, each half its
 * own G (the thin one far brighter). Nothing comes through to the lit top,
 * whose inverted normal faces away, nor with no light; a light 60 degrees
 * off gives its cosine, which the talk's distortion can take away. Without
 * a thickness the render is refused, and bad thickness is named. */
static void test_thickness_through_slab(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_slab(&profile, &d);
    sam_render_view view;
    sam_image img;
    sam_error err;
    slab_view(&view, 1, 0, SAM_TECHNIQUE_THICKNESS);
    assert_int_equal(sam_runtime_render(rt, &view, &img, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("thickness without one: %s\n", err.message);
    assert_non_null(strstr(err.message, "sam_runtime_set_thickness"));
    assert_null(img.pixels);

    float *t = slab_thickness(&d);
    t[3] = -1.0f;
    assert_int_equal(sam_runtime_set_thickness(rt, t, d.vertex_count, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("%s\n", err.message);
    assert_non_null(strstr(err.message, "vertex 3's thickness -1"));
    assert_int_equal(sam_runtime_set_thickness(rt, t, d.vertex_count - 1, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("%s\n", err.message);
    assert_int_equal(sam_runtime_set_thickness_distortion(rt, 1.5f, &err), SAM_ERR_INVALID_ARGUMENT);
    t[3] = t[2];
    assert_int_equal(sam_runtime_set_thickness(rt, t, d.vertex_count, &err), SAM_OK);

    float g[3];
    sam_profile_slab_transmission(&profile, (float)(SLAB_THICKNESS * SLAB_MM_PER_UNIT), g);
    double rho = sam_runtime_rho_dt(rt, 1.0f), factor = rho / PI;
    const double want[3] = {g[0], g[1], g[2]};
    for (int mode = 0; mode <= 3; ++mode) {
        render_slab(rt, 1, mode, SAM_TECHNIQUE_THICKNESS, &img);
        char what[64];
        snprintf(what, sizeof what, "thickness, diffusion %d", mode);
        assert_centre_near(&img, factor * rho, want, 0.02, what);
        sam_image_destroy(&img);
        render_slab(rt, 0, mode, SAM_TECHNIQUE_THICKNESS, &img);
        size_t at = 0;
        for (size_t i = 0; i < (size_t)SIZE * SIZE; ++i)
            if (img.pixels[4 * i] > img.pixels[4 * at])
                at = i;
        print_message("thickness, diffusion %d, lit side: largest value %.3g at pixel (%zu, %zu), centre %.3g\n", mode,
                      img.pixels[4 * at], at % SIZE, at / SIZE, centre_pixel(&img)[0]);
        /* The top's own T is 0 everywhere; texture space's blur reaches
         * the side faces' charts (lit near the bottom edge) across the
         * atlas's gaps, so only its corners pick some up. */
        assert_true(mode == 3 ? centre_pixel(&img)[0] == 0.0f : img.pixels[4 * at] == 0.0f);
        sam_image_destroy(&img);
    }

    /* Thin and thick halves. */
    for (uint32_t v = 0; v < d.vertex_count; ++v)
        t[v] = d.positions[3 * v] < 0 ? 1.0f : 4.0f;
    assert_int_equal(sam_runtime_set_thickness(rt, t, d.vertex_count, &err), SAM_OK);
    render_slab(rt, 1, 0, SAM_TECHNIQUE_THICKNESS, &img);
    slab_view(&view, 1, 0, SAM_TECHNIQUE_THICKNESS);
    size_t thin_n, thick_n;
    double thin = mean_red_over_x(rt, &view, &img, -0.45, -0.1, &thin_n);
    double thick = mean_red_over_x(rt, &view, &img, 0.1, 0.45, &thick_n);
    float g_thin[3], g_thick[3];
    sam_profile_slab_transmission(&profile, 1.0f, g_thin);
    sam_profile_slab_transmission(&profile, 4.0f, g_thick);
    double want_thin = factor * rho * g_thin[0], want_thick = factor * rho * g_thick[0];
    print_message("thickness 1 mm: %.6g over %zu pixels (G says %.6g); 4 mm: %.6g over %zu pixels (G says %.6g)\n",
                  thin, thin_n, want_thin, thick, thick_n, want_thick);
    assert_true(thin_n > 50 && thick_n > 50);
    assert_true(fabs(thin - want_thin) < 0.01 * want_thin);
    assert_true(fabs(thick - want_thick) < 0.01 * want_thick);
    assert_true(thin > 2 * thick);
    sam_image_destroy(&img);
    /* The pass's per-vertex T read back: rho_dt(1) G(t) on the bottom, 0 on
     * the top; SAM's own T is left as its pass wrote it. */
    float *vt = malloc(d.vertex_count * 3 * sizeof *vt), *sam_t = malloc(d.vertex_count * 3 * sizeof *sam_t);
    assert_int_equal(sam_runtime_read_thickness_translucency(rt, vt, &err), SAM_OK);
    assert_int_equal(sam_runtime_read_translucency(rt, sam_t, &err), SAM_OK);
    double worst = 0, top = 0, sam_sum = 0;
    for (uint32_t v = 0; v < d.vertex_count; ++v) {
        const float *p = d.positions + 3 * v, *n = d.normals + 3 * v;
        sam_sum += sam_t[3 * v];
        if (n[1] == 1.0f)
            top = fmax(top, vt[3 * v]);
        if (n[1] == -1.0f && fabsf(p[0]) < 0.45f && fabsf(p[2]) < 0.45f)
            worst = fmax(worst, fabs(vt[3 * v] - rho * (p[0] < 0 ? g_thin : g_thick)[0]) / (rho * g_thick[0]));
    }
    print_message("thickness T read back: worst relative error on the bottom %.2e, largest on the top %.3g; SAM's T "
                  "sums to %.4g\n",
                  worst, top, sam_sum);
    assert_true(worst < 1e-5);
    assert_true(top == 0.0);
    assert_true(sam_sum > 0);
    free(vt);
    free(sam_t);

    /* A light 60 degrees off the bottom's inverted normal: its cosine, 0.5;
     * distorted by 0.5 (L + N 0.5 lies in the slab's plane), none. */
    sam_light l;
    memset(&l, 0, sizeof l);
    l.type = SAM_LIGHT_DIRECTIONAL;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    l.intensity = 1.0f;
    l.direction[0] = -(float)sin(PI / 3);
    l.direction[1] = -(float)cos(PI / 3);
    assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
    render_slab(rt, 1, 0, SAM_TECHNIQUE_THICKNESS, &img);
    double slanted = mean_red_over_x(rt, &view, &img, -0.45, -0.1, &thin_n);
    double want_slanted = factor * sam_runtime_rho_dt(rt, 0.5f) * 0.5 * g_thin[0];
    sam_image_destroy(&img);
    assert_int_equal(sam_runtime_set_thickness_distortion(rt, 0.5f, &err), SAM_OK);
    render_slab(rt, 1, 0, SAM_TECHNIQUE_THICKNESS, &img);
    double distorted = mean_red_over_x(rt, &view, &img, -0.45, -0.1, &thin_n);
    sam_image_destroy(&img);
    print_message("light 60 degrees off: %.6g (expected %.6g); distorted by 0.5: %.3g\n", slanted, want_slanted,
                  distorted);
    assert_true(fabs(slanted - want_slanted) < 0.01 * want_slanted);
    assert_true(distorted < 1e-6 * slanted);
    assert_int_equal(sam_runtime_set_thickness_distortion(rt, 0.0f, &err), SAM_OK);

    /* No light at all. */
    assert_int_equal(sam_runtime_set_lights(rt, NULL, 0, &err), SAM_OK);
    double dark = slab_max(rt, 1, 0, SAM_TECHNIQUE_THICKNESS);
    print_message("thickness, no light: largest value %.3g\n", dark);
    assert_true(dark == 0.0);
    assert_int_equal(sam_runtime_set_thickness(rt, NULL, 0, &err), SAM_OK);
    assert_int_equal(sam_runtime_render(rt, &view, &img, &err), SAM_ERR_INVALID_ARGUMENT);
    free(t);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* An area light above the slab, then the environment alone: SAM and the
 * local thickness carry their light through, the two shadow-map techniques
 * by design do not. */
static void test_area_and_environment_give_none(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = shape_runtime("slab", 16, SLAB_THICKNESS, SLAB_MM_PER_UNIT, &profile, &d);
    sam_light area;
    memset(&area, 0, sizeof area);
    area.type = SAM_LIGHT_AREA;
    area.color[0] = area.color[1] = area.color[2] = 1.0f;
    area.intensity = 1.0f;
    area.shadow = 1;
    area.vertex_count = 4;
    const float square[4][3] = {{-0.4f, 0.5f, -0.4f}, {-0.4f, 0.5f, 0.4f}, {0.4f, 0.5f, 0.4f}, {0.4f, 0.5f, -0.4f}};
    memcpy(area.vertices, square, sizeof square);
    area.normal[1] = -1.0f;
    area.area = 0.64f;
    float sh[9][3] = {{0}};
    sh[0][0] = sh[0][1] = sh[0][2] = 1.0f;
    sam_error err;
    float *t = slab_thickness(&d);
    assert_int_equal(sam_runtime_set_thickness(rt, t, d.vertex_count, &err), SAM_OK);
    free(t);
    for (int scene = 0; scene < 2; ++scene) {
        assert_int_equal(sam_runtime_set_lights(rt, &area, scene == 0, &err), SAM_OK);
        sam_runtime_set_environment(rt, scene == 1 ? (const float(*)[3])sh : NULL);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
        const char *what = scene == 0 ? "area light" : "environment";
        double sam_max = slab_max(rt, 1, 0, SAM_TECHNIQUE_SAM);
        double transmittance_max = slab_max(rt, 1, 0, SAM_TECHNIQUE_TRANSMITTANCE);
        double tsm_max = slab_max(rt, 1, 3, SAM_TECHNIQUE_TSM);
        double thickness_max = slab_max(rt, 1, 0, SAM_TECHNIQUE_THICKNESS);
        print_message("%s, largest translucency seen below: sam %.4g, thickness %.4g, transmittance %.3g, tsm %.3g\n",
                      what, sam_max, thickness_max, transmittance_max, tsm_max);
        assert_true(sam_max > 1e-4);
        assert_true(thickness_max > 1e-4);
        assert_true(transmittance_max == 0.0);
        assert_true(tsm_max == 0.0);
    }
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

static void test_tsm_needs_texture_space(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_slab(&profile, &d);
    sam_render_view view;
    slab_view(&view, 1, 1, SAM_TECHNIQUE_TSM);
    sam_image img;
    sam_error err;
    assert_int_equal(sam_runtime_render(rt, &view, &img, &err), SAM_ERR_UNSUPPORTED);
    print_message("tsm with screen diffusion: %s\n", err.message);
    assert_non_null(strstr(err.message, "texture-space diffusion"));
    assert_null(img.pixels);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* The override replaces the technique's translucency. Zero gives the
 * picture of technique none (front light on). In screen space, a value
 * that grows down the rows comes out, pixel by pixel, as
 * rho_dt(N.V) / pi times itself (N from the G-buffer): a flipped or
 * shifted image would not. In the atlas, light on the bottom's texels only
 * (found by the atlas G-buffer) shows below and not above. Wrong sizes are
 * refused naming both. */
static void test_override(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_slab(&profile, &d);
    sam_error err;
    sam_image zero_view, zero_atlas;
    assert_int_equal(sam_image_create(&zero_view, SIZE, SIZE, 3, &err), SAM_OK);
    assert_int_equal(sam_image_create(&zero_atlas, ATLAS, ATLAS, 4, &err), SAM_OK);
    memset(zero_view.pixels, 0, (size_t)SIZE * SIZE * 3 * sizeof(float));
    memset(zero_atlas.pixels, 0, (size_t)ATLAS * ATLAS * 4 * sizeof(float));
    for (int mode = 0; mode <= 3; ++mode) {
        sam_render_view view;
        slab_view(&view, 0, mode, SAM_TECHNIQUE_NONE);
        view.front = 1;
        sam_image none, zero;
        render(rt, &view, &none);
        view.technique = SAM_TECHNIQUE_SAM;
        view.translucency = mode == 3 ? &zero_atlas : &zero_view;
        render(rt, &view, &zero);
        double worst = 0;
        for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; ++i)
            worst = fmax(worst, fabs(none.pixels[i] - zero.pixels[i]));
        print_message("diffusion %d: zero override vs technique none, largest difference %.3g (image max %.3g)\n",
                      mode, worst, image_max(&none));
        assert_true(worst == 0.0);
        assert_true(image_max(&none) > 0.0);
        sam_image_destroy(&none);
        sam_image_destroy(&zero);
    }

    /* A row gradient in screen space, translucency only. */
    sam_render_view view;
    slab_view(&view, 1, 0, SAM_TECHNIQUE_NONE);
    sam_image grad, img, pos, nrm;
    assert_int_equal(sam_image_create(&grad, SIZE, SIZE, 4, &err), SAM_OK);
    for (uint32_t y = 0; y < SIZE; ++y)
        for (uint32_t x = 0; x < SIZE; ++x)
            for (int c = 0; c < 4; ++c)
                grad.pixels[4 * (y * SIZE + x) + c] = 0.1f * (1.0f + (float)y) * (c == 1 ? 0.5f : 1.0f);
    view.translucency = &grad;
    render(rt, &view, &img);
    assert_int_equal(sam_runtime_gbuffer(rt, &view, SAM_GBUFFER_SCREEN, &pos, &nrm, &err), SAM_OK);
    double worst = 0;
    size_t covered = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE; ++i) {
        if (pos.pixels[4 * i + 3] == 0)
            continue;
        const float *p = pos.pixels + 4 * i, *n = nrm.pixels + 4 * i;
        double to[3] = {view.eye[0] - p[0], view.eye[1] - p[1], view.eye[2] - p[2]};
        double len = sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
        double ndv = (n[0] * to[0] + n[1] * to[1] + n[2] * to[2]) / len;
        for (int c = 0; c < 3; ++c) {
            double want = sam_runtime_rho_dt(rt, (float)ndv) / PI * grad.pixels[4 * i + c];
            worst = fmax(worst, fabs(img.pixels[4 * i + c] - want) / want);
        }
        covered++;
    }
    print_message("screen gradient override over %zu pixels: worst relative error %.2e\n", covered, worst);
    assert_true(covered > SIZE * SIZE / 4);
    assert_true(worst < 2e-3);
    sam_image_destroy(&img);
    sam_image_destroy(&pos);
    sam_image_destroy(&nrm);

    /* The bottom's texels only, in the atlas. */
    slab_view(&view, 1, 3, SAM_TECHNIQUE_NONE);
    assert_int_equal(sam_runtime_gbuffer(rt, &view, SAM_GBUFFER_ATLAS, &pos, &nrm, &err), SAM_OK);
    assert_int_equal(pos.width, ATLAS);
    const float c_rgb[3] = {0.3f, 0.2f, 0.1f};
    for (size_t i = 0; i < (size_t)ATLAS * ATLAS; ++i)
        for (int c = 0; c < 3; ++c)
            zero_atlas.pixels[4 * i + c] = pos.pixels[4 * i + 3] > 0 && pos.pixels[4 * i + 1] < 0 ? c_rgb[c] : 0.0f;
    view.translucency = &zero_atlas;
    render(rt, &view, &img);
    double below = centre_pixel(&img)[0], want = sam_runtime_rho_dt(rt, 1.0f) / PI * c_rgb[0];
    sam_image_destroy(&img);
    slab_view(&view, 0, 3, SAM_TECHNIQUE_NONE);
    view.translucency = &zero_atlas;
    render(rt, &view, &img);
    double above = centre_pixel(&img)[0];
    print_message("atlas override on the bottom's texels: below %.6g (expected %.6g), above %.3g\n", below, want,
                  above);
    assert_true(fabs(below - want) < 1e-3 * want);
    assert_true(above == 0.0);
    sam_image_destroy(&img);

    /* Wrong sizes. */
    view.translucency = &grad;
    assert_int_equal(sam_runtime_render(rt, &view, &img, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("view-sized override in texture space: %s\n", err.message);
    assert_non_null(strstr(err.message, "64x64"));
    assert_non_null(strstr(err.message, "512x512"));
    slab_view(&view, 1, 1, SAM_TECHNIQUE_NONE);
    view.translucency = &zero_atlas;
    assert_int_equal(sam_runtime_render(rt, &view, &img, &err), SAM_ERR_INVALID_ARGUMENT);
    print_message("atlas-sized override in screen space: %s\n", err.message);
    sam_image_destroy(&pos);
    sam_image_destroy(&nrm);
    sam_image_destroy(&grad);
    sam_image_destroy(&zero_view);
    sam_image_destroy(&zero_atlas);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* A sphere of radius 0.5 at the origin: every covered pixel's position lies
 * on it (within the tessellation's sagitta), its normal along p / |p|, and
 * the covered pixels are the render's alpha mask; the same in the atlas
 * against a texture-space render's irradiance map. */
static void test_gbuffer_sphere(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = shape_runtime("sphere", 48, 0, 60.0f, &profile, &d);
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = SIZE;
    view.height = SIZE - 16; /* not square: rows and columns cannot swap unnoticed */
    view.fov_deg = 40.0f;
    view.eye[0] = 0.4f, view.eye[1] = 0.6f, view.eye[2] = 1.8f;
    view.up[1] = 1.0f;
    view.albedo[0] = view.albedo[1] = view.albedo[2] = 1.0f;
    view.front = 1;
    view.options.atlas_size = ATLAS;
    sam_error err;
    for (int space = 0; space < 2; ++space) {
        sam_image pos, nrm, img, mask;
        assert_int_equal(sam_runtime_gbuffer(rt, &view, (sam_gbuffer_space)space, &pos, &nrm, &err), SAM_OK);
        view.diffusion = space == SAM_GBUFFER_ATLAS ? 3 : 0;
        render(rt, &view, &img);
        if (space == SAM_GBUFFER_ATLAS)
            assert_int_equal(sam_runtime_read_atlas(rt, SAM_ATLAS_IRRADIANCE, &mask, &err), SAM_OK);
        const sam_image *m = space == SAM_GBUFFER_ATLAS ? &mask : &img;
        assert_int_equal(pos.width, m->width);
        assert_int_equal(pos.height, m->height);
        double worst_r = 0, worst_deg = 0;
        size_t covered = 0, mismatched = 0;
        for (size_t i = 0; i < (size_t)pos.width * pos.height; ++i) {
            mismatched += (pos.pixels[4 * i + 3] > 0) != (m->pixels[4 * i + 3] > 0);
            mismatched += pos.pixels[4 * i + 3] != nrm.pixels[4 * i + 3];
            if (pos.pixels[4 * i + 3] == 0)
                continue;
            const float *p = pos.pixels + 4 * i, *n = nrm.pixels + 4 * i;
            double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            double cosine = (p[0] * n[0] + p[1] * n[1] + p[2] * n[2]) / r;
            worst_r = fmax(worst_r, fabs(r - 0.5) / 0.5);
            worst_deg = fmax(worst_deg, acos(fmin(cosine, 1.0)) * 180 / PI);
            covered++;
        }
        print_message("%s G-buffer: %zu covered, %zu disagree with the render's mask, worst |p| error %.4f of r, "
                      "worst normal angle %.3f deg\n",
                      space ? "atlas" : "screen", covered, mismatched, worst_r, worst_deg);
        assert_true(covered > (space ? (size_t)ATLAS * ATLAS / 4 : (size_t)SIZE * SIZE / 8));
        assert_int_equal(mismatched, 0);
        assert_true(worst_r < 0.005);
        assert_true(worst_deg < 2.0);
        sam_image_destroy(&pos);
        sam_image_destroy(&nrm);
        sam_image_destroy(&img);
        if (space == SAM_GBUFFER_ATLAS)
            sam_image_destroy(&mask);
    }
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_transmittance_through_slab),
        cmocka_unit_test(test_tsm_through_slab),
        cmocka_unit_test(test_thickness_through_slab),
        cmocka_unit_test(test_area_and_environment_give_none),
        cmocka_unit_test(test_tsm_needs_texture_space),
        cmocka_unit_test(test_override),
        cmocka_unit_test(test_gbuffer_sphere),
    };
    return cmocka_run_group_tests(tests, sam_test_gl_setup, sam_test_gl_teardown);
}
