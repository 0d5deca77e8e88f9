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

#include "sam/sam_image.h"
#include "sam/sam_light.h"
#include "sam_test.h"

#define PI_D 3.14159265358979323846

/* ------------------------------------------------------------------------ */
/* helpers                                                                   */

/* Deterministic uniform doubles in [0, 1) (64-bit LCG, high bits). */
static double next_uniform(uint64_t *state)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*state >> 11) / 9007199254740992.0;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void normalize3f(float v[3])
{
    float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; ++k)
        v[k] /= len;
}

static void assert_rel_close(double got, double want, double tolerance, const char *what)
{
    double scale = fabs(want) > 1e-12 ? fabs(want) : 1.0;
    if (!(fabs(got - want) <= tolerance * scale)) {
        print_error("%s: got %.9g, expected %.9g (relative error %.3g > %.3g)\n", what, got, want,
                    fabs(got - want) / scale, tolerance);
        fail();
    }
}

/* Radiance of an analytic environment in the world direction d. */
typedef void (*env_fn)(const void *ctx, const double d[3], double rgb[3]);

/* Fills a lat-long image by evaluating `fn` at every texel centre. */
static void fill_env(sam_image *img, uint32_t w, uint32_t h, uint32_t channels, env_fn fn,
                     const void *ctx)
{
    assert_int_equal(sam_image_create(img, w, h, channels, NULL), SAM_OK);
    for (uint32_t row = 0; row < h; ++row)
        for (uint32_t col = 0; col < w; ++col) {
            float d[3];
            sam_light_latlong_direction((col + 0.5f) / w, (row + 0.5f) / h, d);
            double dd[3] = {d[0], d[1], d[2]}, rgb[3];
            fn(ctx, dd, rgb);
            float *px = img->pixels + (size_t)channels * ((size_t)row * w + col);
            for (int c = 0; c < 3; ++c)
                px[c] = (float)rgb[c];
            if (channels == 4)
                px[3] = -7.0f; /* alpha must be ignored */
        }
}

/* Reference irradiance by brute force over texels: sum of L cos+ dw with
 * each texel's exact solid angle and its centre direction, the map rotated
 * by rotation_deg (a texel at u lights from u + rotation / 360). */
static void brute_force_irradiance(const sam_image *img, double rotation_deg, const double n[3],
                                   double out[3])
{
    out[0] = out[1] = out[2] = 0;
    uint32_t w = img->width, h = img->height;
    for (uint32_t row = 0; row < h; ++row) {
        double dw = (2 * PI_D / w) * (cos(PI_D * row / h) - cos(PI_D * (row + 1) / h));
        for (uint32_t col = 0; col < w; ++col) {
            float d[3];
            sam_light_latlong_direction((col + 0.5f) / w + (float)(rotation_deg / 360.0),
                                        (row + 0.5f) / h, d);
            double dd[3] = {d[0], d[1], d[2]};
            double c = dot3(dd, n);
            if (c <= 0)
                continue;
            const float *px = img->pixels + (size_t)img->channels * ((size_t)row * w + col);
            for (int k = 0; k < 3; ++k)
                out[k] += px[k] * c * dw;
        }
    }
}

static void sh_irradiance_d(const float sh[9][3], const double n[3], double out[3])
{
    float nf[3] = {(float)n[0], (float)n[1], (float)n[2]}, e[3];
    sam_light_sh9_irradiance(sh, nf, e);
    for (int c = 0; c < 3; ++c)
        out[c] = e[c];
}

/* A set of unit normals covering the sphere: axes, diagonals, odd ones. */
#define NORMAL_COUNT 14
static void test_normals(double normals[NORMAL_COUNT][3])
{
    static const double raw[NORMAL_COUNT][3] = {
        {0, 1, 0},    {0, -1, 0},    {1, 0, 0},     {-1, 0, 0},  {0, 0, 1},
        {0, 0, -1},   {1, 1, 1},     {-1, 1, -1},   {1, -1, 1},  {-1, -1, -1},
        {0.3, 0.9, -0.2}, {-0.7, 0.1, 0.4}, {0.2, -0.5, -0.8}, {0.9, 0.3, 0.1},
    };
    for (int i = 0; i < NORMAL_COUNT; ++i) {
        double len = sqrt(dot3(raw[i], raw[i]));
        for (int k = 0; k < 3; ++k)
            normals[i][k] = raw[i][k] / len;
    }
}

/* ------------------------------------------------------------------------ */
/* lat-long mapping and SH                                                   */

static void test_latlong_convention(void **state)
{
    (void)state;
    static const struct {
        float u, v, d[3];
    } cases[] = {
        {0.0f, 0.5f, {0, 0, 1}},   {0.25f, 0.5f, {1, 0, 0}}, {0.5f, 0.5f, {0, 0, -1}},
        {0.75f, 0.5f, {-1, 0, 0}}, {0.3f, 0.0f, {0, 1, 0}},  {0.6f, 1.0f, {0, -1, 0}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        float d[3];
        sam_light_latlong_direction(cases[i].u, cases[i].v, d);
        for (int k = 0; k < 3; ++k)
            assert_true(fabsf(d[k] - cases[i].d[k]) < 1e-6f);
    }
    /* Round trip, including the wrap of u. */
    uint64_t rng = 7;
    for (int i = 0; i < 1000; ++i) {
        float u = (float)next_uniform(&rng), v = (float)(0.01 + 0.98 * next_uniform(&rng));
        float d[3], u2, v2;
        sam_light_latlong_direction(u, v, d);
        sam_light_latlong_from_direction(d, &u2, &v2);
        assert_true(u2 >= 0.0f && u2 < 1.0f);
        float du = fabsf(u2 - u);
        assert_true(fminf(du, 1.0f - du) < 1e-5f);
        assert_true(fabsf(v2 - v) < 1e-5f);
    }
}

static void constant_rgb(const void *ctx, const double d[3], double rgb[3])
{
    (void)ctx;
    (void)d;
    rgb[0] = 0.5;
    rgb[1] = 1.0;
    rgb[2] = 2.0;
}

static void test_constant_environment(void **state)
{
    (void)state;
    static const uint32_t sizes[][2] = {{1, 1}, {4, 2}, {37, 19}, {256, 128}};
    double normals[NORMAL_COUNT][3];
    test_normals(normals);
    for (size_t s = 0; s < 4; ++s) {
        for (uint32_t channels = 3; channels <= 4; ++channels) {
            sam_image img;
            fill_env(&img, sizes[s][0], sizes[s][1], channels, constant_rgb, NULL);
            float sh[9][3];
            sam_error err;
            assert_int_equal(sam_light_sh9_from_latlong(&img, 33.0f, 1.5f, sh, &err), SAM_OK);
            const double want[3] = {1.5 * 0.5, 1.5 * 1.0, 1.5 * 2.0};
            for (int c = 0; c < 3; ++c) {
                assert_rel_close(sh[0][c], 2 * sqrt(PI_D) * want[c], 1e-5, "L00");
                for (int k = 1; k < 9; ++k)
                    assert_true(fabsf(sh[k][c]) < 1e-5f * (float)want[c]);
            }
            for (int i = 0; i < NORMAL_COUNT; ++i) {
                double e[3];
                sh_irradiance_d(sh, normals[i], e);
                for (int c = 0; c < 3; ++c)
                    assert_rel_close(e[c], PI_D * want[c], 1e-4, "constant map irradiance");
            }
            sam_image_destroy(&img);
        }
    }
}

/* Each basis function, sampled at texel centres, projects onto itself:
 * the basis is orthonormal and the projection's weights are right. */
static void basis_env(const void *ctx, const double d[3], double rgb[3])
{
    float y[9], df[3] = {(float)d[0], (float)d[1], (float)d[2]};
    sam_light_sh9_basis(df, y);
    rgb[0] = rgb[1] = rgb[2] = y[*(const int *)ctx];
}

static void test_basis_orthonormal(void **state)
{
    (void)state;
    for (int basis_index = 0; basis_index < 9; ++basis_index) {
        sam_image img;
        fill_env(&img, 256, 128, 3, basis_env, &basis_index);
        float sh[9][3];
        assert_int_equal(sam_light_sh9_from_latlong(&img, 0.0f, 1.0f, sh, NULL), SAM_OK);
        for (int k = 0; k < 9; ++k)
            assert_true(fabsf(sh[k][0] - (k == basis_index ? 1.0f : 0.0f)) < 1e-3f);
        sam_image_destroy(&img);
    }
}

/* Low-order polynomials have no SH content above l = 2, so SH-9 irradiance
 * is exact for them: for L = a + b.d + (d.s)^2,
 * E(n) = pi a + (2 pi / 3) b.n + pi / 3 + (pi / 4) ((n.s)^2 - 1/3). */
static const double poly_b[3] = {0.3, -0.2, 0.45};
static const double poly_s[3] = {0.48, 0.6, 0.64};
static void poly_env(const void *ctx, const double d[3], double rgb[3])
{
    (void)ctx;
    double q = dot3(d, poly_s);
    for (int c = 0; c < 3; ++c)
        rgb[c] = (1.0 + 0.5 * c) + dot3(poly_b, d) + q * q;
}

static void test_polynomial_environment_exact(void **state)
{
    (void)state;
    sam_image img;
    fill_env(&img, 512, 256, 3, poly_env, NULL);
    float sh[9][3];
    assert_int_equal(sam_light_sh9_from_latlong(&img, 0.0f, 1.0f, sh, NULL), SAM_OK);
    double normals[NORMAL_COUNT][3];
    test_normals(normals);
    for (int i = 0; i < NORMAL_COUNT; ++i) {
        double e[3], ns = dot3(normals[i], poly_s);
        sh_irradiance_d(sh, normals[i], e);
        for (int c = 0; c < 3; ++c) {
            double want = PI_D * (1.0 + 0.5 * c) + 2 * PI_D / 3 * dot3(poly_b, normals[i]) +
                          PI_D / 3 + PI_D / 4 * (ns * ns - 1.0 / 3);
            assert_rel_close(e[c], want, 1e-4, "polynomial map irradiance");
        }
    }
    sam_image_destroy(&img);
}

/*
 * The smooth test map: a sky gradient (brighter and bluer upwards, a dim
 * ground) plus a broad warm "sun" lobe 4 exp(3 (d.s - 1)) (half maximum at
 * 32 degrees). It has content above l = 2, which SH-9 drops, but little:
 * the irradiance must match the brute-force cosine integral within 2%.
 */
static void smooth_env(const void *ctx, const double d[3], double rgb[3])
{
    (void)ctx;
    static const double sun[3] = {0.5, 0.7, -0.5099019513592785};
    double lobe = 4.0 * exp(3.0 * (dot3(d, sun) - 1.0));
    double up = 0.5 + 0.5 * d[1];
    rgb[0] = 0.25 + 0.35 * up + 1.00 * lobe;
    rgb[1] = 0.25 + 0.50 * up + 0.85 * lobe;
    rgb[2] = 0.30 + 0.90 * up + 0.60 * lobe;
}

static void test_smooth_map_matches_brute_force(void **state)
{
    (void)state;
    sam_image img;
    fill_env(&img, 256, 128, 3, smooth_env, NULL);
    double normals[NORMAL_COUNT][3];
    test_normals(normals);
    double worst = 0;
    for (int r = 0; r < 2; ++r) {
        double rotation = r ? -127.0 : 0.0;
        float sh[9][3];
        assert_int_equal(sam_light_sh9_from_latlong(&img, (float)rotation, 1.0f, sh, NULL),
                         SAM_OK);
        for (int i = 0; i < NORMAL_COUNT; ++i) {
            double e[3], ref[3];
            sh_irradiance_d(sh, normals[i], e);
            brute_force_irradiance(&img, rotation, normals[i], ref);
            for (int c = 0; c < 3; ++c) {
                assert_rel_close(e[c], ref[c], 0.02, "smooth map vs brute force");
                worst = fmax(worst, fabs(e[c] - ref[c]) / ref[c]);
            }
        }
    }
    print_message("smooth map: worst SH-9 irradiance error vs brute force %.3f%%\n", 100 * worst);
    sam_image_destroy(&img);
}

/* A lobe facing +Z; rotated by 90 degrees it must face +X. */
static void lobe_env(const void *ctx, const double d[3], double rgb[3])
{
    (void)ctx;
    double lobe = exp(2.0 * (d[2] - 1.0));
    rgb[0] = rgb[1] = rgb[2] = 0.1 + lobe;
}

static void test_rotation_moves_features(void **state)
{
    (void)state;
    sam_image img;
    fill_env(&img, 128, 64, 3, lobe_env, NULL);
    float sh0[9][3], sh90[9][3], sh450[9][3];
    assert_int_equal(sam_light_sh9_from_latlong(&img, 0.0f, 1.0f, sh0, NULL), SAM_OK);
    assert_int_equal(sam_light_sh9_from_latlong(&img, 90.0f, 1.0f, sh90, NULL), SAM_OK);
    assert_int_equal(sam_light_sh9_from_latlong(&img, 450.0f, 1.0f, sh450, NULL), SAM_OK);
    const double px[3] = {1, 0, 0}, nx[3] = {-1, 0, 0}, pz[3] = {0, 0, 1}, nz[3] = {0, 0, -1};
    double e0_pz[3], e0_nz[3], e90_px[3], e90_nx[3], e90_pz[3], e0_nx[3];
    sh_irradiance_d(sh0, pz, e0_pz);
    sh_irradiance_d(sh0, nz, e0_nz);
    sh_irradiance_d(sh0, nx, e0_nx);
    sh_irradiance_d(sh90, px, e90_px);
    sh_irradiance_d(sh90, nx, e90_nx);
    sh_irradiance_d(sh90, pz, e90_pz);
    assert_true(e0_pz[0] > 2 * e0_nz[0]); /* the lobe really is one-sided */
    assert_rel_close(e90_px[0], e0_pz[0], 1e-4, "rotated lobe now faces +X");
    assert_rel_close(e90_nx[0], e0_nz[0], 1e-4, "rotated back side now faces -X");
    /* +Z now sees what -X saw before the turn (the side, not the lobe). */
    assert_rel_close(e90_pz[0], e0_nx[0], 1e-4, "rotated side");
    for (int k = 0; k < 9; ++k)
        assert_true(fabsf(sh450[k][0] - sh90[k][0]) < 1e-4f);
    sam_image_destroy(&img);
}

static void test_sh_bad_inputs(void **state)
{
    (void)state;
    sam_image img;
    fill_env(&img, 8, 4, 3, constant_rgb, NULL);
    float sh[9][3];
    sam_error err;
    assert_int_equal(sam_light_sh9_from_latlong(NULL, 0, 1, sh, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "env"));
    assert_int_equal(sam_light_sh9_from_latlong(&img, 0, 1, NULL, &err), SAM_ERR_INVALID_ARGUMENT);
    sam_image bad = img;
    bad.width = 0;
    sh[0][0] = 99;
    assert_int_equal(sam_light_sh9_from_latlong(&bad, 0, 1, sh, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "0x4"));
    assert_true(sh[0][0] == 0.0f);
    bad = img;
    bad.height = 0;
    assert_int_equal(sam_light_sh9_from_latlong(&bad, 0, 1, sh, NULL), SAM_ERR_INVALID_ARGUMENT);
    bad = img;
    bad.channels = 2;
    assert_int_equal(sam_light_sh9_from_latlong(&bad, 0, 1, sh, NULL), SAM_ERR_INVALID_ARGUMENT);
    bad = img;
    bad.pixels = NULL;
    assert_int_equal(sam_light_sh9_from_latlong(&bad, 0, 1, sh, NULL), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_sh9_from_latlong(&img, 0, -1, sh, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "-1"));
    assert_int_equal(sam_light_sh9_from_latlong(&img, INFINITY, 1, sh, NULL),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_sh9_from_latlong(&img, 0, NAN, sh, NULL), SAM_ERR_INVALID_ARGUMENT);
    img.pixels[3 * (2 * 8 + 5) + 1] = NAN;
    assert_int_equal(sam_light_sh9_from_latlong(&img, 0, 1, sh, &err), SAM_ERR_FORMAT);
    assert_non_null(strstr(err.message, "column 5, row 2"));
    assert_non_null(strstr(err.message, "channel 1"));
    for (int k = 0; k < 9; ++k)
        assert_true(sh[k][0] == 0.0f && sh[k][1] == 0.0f && sh[k][2] == 0.0f);
    sam_image_destroy(&img);
}

/* ------------------------------------------------------------------------ */
/* procedural skies                                                          */

static const float *texel_at(const sam_image *img, const float d[3])
{
    float u, v;
    sam_light_latlong_from_direction(d, &u, &v);
    uint32_t col = (uint32_t)(u * img->width), row = (uint32_t)(v * img->height);
    if (row >= img->height)
        row = img->height - 1;
    return img->pixels + 3 * ((size_t)row * img->width + col);
}

static void dir_from_angles(float elevation_deg, float azimuth_deg, float d[3])
{
    float e = elevation_deg * (float)PI_D / 180, a = azimuth_deg * (float)PI_D / 180;
    d[0] = cosf(e) * sinf(a);
    d[1] = sinf(e);
    d[2] = cosf(e) * cosf(a);
}

/* Largest value, checking every texel is finite, >= 0 and fits a half. */
static float check_values(const sam_image *img)
{
    float peak = 0;
    for (size_t i = 0; i < (size_t)img->width * img->height * 3; ++i) {
        assert_true(isfinite(img->pixels[i]) && img->pixels[i] >= 0 && img->pixels[i] < 65504);
        peak = fmaxf(peak, img->pixels[i]);
    }
    return peak;
}

static void test_studio_sky(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    assert_int_equal(sam_light_make_sky(512, 256, SAM_SKY_STUDIO, &img, &err), SAM_OK);
    assert_int_equal(img.width, 512);
    assert_int_equal(img.height, 256);
    assert_int_equal(img.channels, 3);
    assert_true(check_values(&img) > 10.0f); /* HDR boxes */
    float d[3];
    dir_from_angles(35, 45, d); /* key box centre */
    assert_true(texel_at(&img, d)[0] > 10.0f);
    dir_from_angles(20, 290, d); /* fill box, cooler */
    const float *fill = texel_at(&img, d);
    assert_true(fill[2] > 3.0f && fill[2] > fill[0]);
    dir_from_angles(60, 180, d); /* top box */
    assert_true(texel_at(&img, d)[1] > 5.0f);
    dir_from_angles(-60, 0, d); /* floor: dim grey */
    const float *floor = texel_at(&img, d);
    assert_true(floor[0] > 0.02f && floor[0] < 0.1f && floor[0] == floor[2]);
    dir_from_angles(10, 180, d); /* wall between boxes */
    assert_true(texel_at(&img, d)[0] < 0.3f);
    /* Soft edges: going out of the key box sideways passes through
     * intermediate values rather than jumping. */
    int intermediate = 0;
    for (float az = 45; az < 75; az += 0.5f) {
        dir_from_angles(35, az, d);
        float value = texel_at(&img, d)[1];
        intermediate += value > 1.0f && value < 10.0f;
    }
    assert_true(intermediate >= 2);
    sam_image_destroy(&img);
}

/* Total radiant energy (sum of L dw) of an image, channel c. */
static double energy(const sam_image *img, int c)
{
    double sum = 0;
    for (uint32_t row = 0; row < img->height; ++row) {
        double dw = (2 * PI_D / img->width) *
                    (cos(PI_D * row / img->height) - cos(PI_D * (row + 1) / img->height));
        for (uint32_t col = 0; col < img->width; ++col)
            sum += img->pixels[3 * ((size_t)row * img->width + col) + c] * dw;
    }
    return sum;
}

static void test_outdoor_sky(void **state)
{
    (void)state;
    sam_image img;
    assert_int_equal(sam_light_make_sky(1024, 512, SAM_SKY_OUTDOOR, &img, NULL), SAM_OK);
    float peak = check_values(&img);
    float d[3];
    dir_from_angles(40, 120, d); /* the sun */
    assert_true(texel_at(&img, d)[0] > 4000.0f);
    assert_true(peak <= 5000.0f + 10.0f);
    const float up[3] = {0, 1, 0};
    const float *zenith = texel_at(&img, up);
    dir_from_angles(2, 300, d);
    const float *horizon = texel_at(&img, d);
    assert_true(zenith[2] > 2 * zenith[0]);             /* blue zenith */
    assert_true(horizon[0] > 0.7f && horizon[2] < 1.5f); /* hazy, whitish horizon */
    dir_from_angles(-45, 300, d);
    const float *ground = texel_at(&img, d);
    assert_true(ground[0] < 0.15f && ground[2] < ground[0]);
    /* The disk's energy does not depend on the resolution (coverage
     * subsampling), so low-resolution maps light a scene the same. */
    sam_image small;
    assert_int_equal(sam_light_make_sky(64, 32, SAM_SKY_OUTDOOR, &small, NULL), SAM_OK);
    double sun_energy = 5000.0 * 2 * PI_D * (1 - cos(1.5 * PI_D / 180));
    double big = energy(&img, 0), lo = energy(&small, 0);
    assert_true(big > sun_energy);
    assert_rel_close(lo, big, 0.03, "outdoor energy at 64x32 vs 1024x512");
    print_message("outdoor: energy %.4f at 1024x512 (sun disk %.4f), %.4f at 64x32\n", big,
                  sun_energy, lo);
    /* SH-9 rings around the sun: facing away from it the series goes
     * negative, and the irradiance is clamped to 0 there. */
    float sh[9][3], e[3];
    assert_int_equal(sam_light_sh9_from_latlong(&small, 0, 1, sh, NULL), SAM_OK);
    const float down[3] = {0, -1, 0};
    sam_light_sh9_irradiance(sh, down, e);
    float raw = 0, ydown[9];
    sam_light_sh9_basis(down, ydown);
    const float band[9] = {3.14159265f, 2.0943951f, 2.0943951f, 2.0943951f, 0.78539816f,
                           0.78539816f, 0.78539816f, 0.78539816f, 0.78539816f};
    for (int k = 0; k < 9; ++k)
        raw += band[k] * sh[k][1] * ydown[k];
    assert_true(raw < 0);
    assert_true(e[1] == 0.0f);
    sam_image_destroy(&small);
    sam_image_destroy(&img);
}

/* The map survives a half-float EXR round trip well enough for lighting. */
static void test_sky_exr_round_trip(void **state)
{
    (void)state;
    char path[512];
    sam_test_tmp_path(path, sizeof path, "light_studio.exr");
    sam_image img, back;
    sam_error err;
    assert_int_equal(sam_light_make_sky(128, 64, SAM_SKY_STUDIO, &img, &err), SAM_OK);
    assert_int_equal(sam_image_write_exr(path, &img, SAM_EXR_HALF, &err), SAM_OK);
    assert_int_equal(sam_image_read_exr(path, &back, &err), SAM_OK);
    float sh[9][3], sh_back[9][3];
    assert_int_equal(sam_light_sh9_from_latlong(&img, 20, 1, sh, &err), SAM_OK);
    assert_int_equal(sam_light_sh9_from_latlong(&back, 20, 1, sh_back, &err), SAM_OK);
    for (int k = 0; k < 9; ++k)
        for (int c = 0; c < 3; ++c)
            assert_true(fabsf(sh[k][c] - sh_back[k][c]) < 1e-3f * fabsf(sh[0][c]));
    sam_image_destroy(&img);
    sam_image_destroy(&back);
}

static void test_sky_bad_inputs(void **state)
{
    (void)state;
    sam_image img;
    sam_error err;
    assert_int_equal(sam_light_make_sky(64, 32, 7, &img, &err), SAM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "7"));
    assert_null(img.pixels);
    assert_int_equal(sam_light_make_sky(0, 32, SAM_SKY_STUDIO, &img, NULL), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_make_sky(64, 0, SAM_SKY_OUTDOOR, &img, NULL), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_make_sky(65536, 65536, SAM_SKY_STUDIO, &img, NULL),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_make_sky(64, 32, SAM_SKY_STUDIO, NULL, NULL), SAM_ERR_INVALID_ARGUMENT);
}

/* ------------------------------------------------------------------------ */
/* polygon lights                                                            */

typedef struct polygon {
    uint32_t count;
    float v[SAM_AREA_LIGHT_MAX_VERTICES][3];
    float normal[3]; /* from the winding (right hand) */
} polygon;

static polygon make_polygon(uint32_t count, const float (*v)[3])
{
    polygon poly;
    memset(&poly, 0, sizeof poly);
    poly.count = count;
    memcpy(poly.v, v, count * sizeof v[0]);
    float nrm[3] = {0, 0, 0};
    for (uint32_t i = 0; i < count; ++i) {
        const float *a = v[i], *b = v[(i + 1) % count];
        nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    normalize3f(nrm);
    memcpy(poly.normal, nrm, sizeof nrm);
    return poly;
}

static double triangle_area(const float *a, const float *b, const float *c)
{
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
    }
    double x[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    return 0.5 * sqrt(dot3(x, x));
}

/* E = L * integral over the polygon of cos_p+ cos_l / r^2 dA by uniform
 * area sampling (fan triangles chosen by area, uniform barycentrics). */
static double monte_carlo_irradiance(const polygon *poly, int two_sided, double radiance,
                                     const float p[3], const float n[3], int samples)
{
    double areas[SAM_AREA_LIGHT_MAX_VERTICES], total = 0;
    for (uint32_t i = 1; i + 1 < poly->count; ++i) {
        areas[i] = triangle_area(poly->v[0], poly->v[i], poly->v[i + 1]);
        total += areas[i];
    }
    uint64_t rng = 12345;
    double sum = 0;
    for (int s = 0; s < samples; ++s) {
        double pick = next_uniform(&rng) * total;
        uint32_t t = 1;
        while (t + 2 < poly->count && pick > areas[t]) {
            pick -= areas[t];
            ++t;
        }
        double a = next_uniform(&rng), b = next_uniform(&rng);
        if (a + b > 1) {
            a = 1 - a;
            b = 1 - b;
        }
        double x[3], w[3];
        for (int k = 0; k < 3; ++k) {
            x[k] = poly->v[0][k] + a * (poly->v[t][k] - poly->v[0][k]) +
                   b * (poly->v[t + 1][k] - poly->v[0][k]);
            w[k] = x[k] - p[k];
        }
        double r2 = dot3(w, w), r = sqrt(r2);
        double nd[3] = {n[0], n[1], n[2]}, nl[3] = {poly->normal[0], poly->normal[1], poly->normal[2]};
        double cos_p = dot3(nd, w) / r, cos_l = -dot3(nl, w) / r;
        if (two_sided)
            cos_l = fabs(cos_l);
        if (cos_p > 0 && cos_l > 0)
            sum += cos_p * cos_l / r2;
    }
    return radiance * total * sum / samples;
}

static float polygon_e(const polygon *poly, int two_sided, float radiance, const float p[3],
                       const float n[3])
{
    float e = -1;
    assert_int_equal(sam_light_polygon_irradiance((const float (*)[3])poly->v, poly->count,
                                                  poly->normal, two_sided, radiance, p, n, &e),
                     SAM_OK);
    return e;
}

static void test_polygon_matches_monte_carlo(void **state)
{
    (void)state;
    /* Square above the receiver, emitting downwards (clockwise seen from +Y). */
    const float square[4][3] = {{-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}};
    /* Tilted triangle off to the side. */
    const float tri[3][3] = {{1.5f, 1.0f, -0.5f}, {2.5f, 2.5f, 0.2f}, {0.8f, 2.0f, 1.2f}};
    /* Vertical hexagonal wall facing -Z, straddling the receiver's horizon. */
    float hex[6][3];
    for (int i = 0; i < 6; ++i) {
        double a = -2 * PI_D * i / 6; /* clockwise seen from -Z: normal -Z */
        hex[i][0] = (float)(0.3 + 1.2 * cos(a));
        hex[i][1] = (float)(0.2 + 1.2 * sin(a));
        hex[i][2] = 1.5f;
    }
    const polygon polys[3] = {make_polygon(4, square), make_polygon(3, tri), make_polygon(6, hex)};
    assert_true(polys[0].normal[1] < -0.99f);
    assert_true(polys[2].normal[2] < -0.99f);
    float tri_n[3] = {-0.4f, 0.9f, 0.3f};
    normalize3f(tri_n);
    float hex_n[3] = {0.2f, 0.9f, 0.3f}; /* tilted: clips the hexagon */
    normalize3f(hex_n);
    const struct {
        int poly;
        float p[3], n[3];
        const char *what;
    } cases[] = {
        {0, {0, 0, 0}, {0, 1, 0}, "square overhead"},
        {0, {0.7f, 0.3f, -0.4f}, {0.6f, 0.8f, 0}, "square, offset tilted receiver"},
        {0, {3, 1.5f, 0}, {0, 0.6f, 0.8f}, "square cut by the receiver's horizon"},
        {1, {0, 0, 0}, {tri_n[0], tri_n[1], tri_n[2]}, "tilted triangle"},
        {2, {0, 0, 0}, {0, 0, 1}, "hexagon facing the receiver"},
        {2, {0, 0, 0}, {hex_n[0], hex_n[1], hex_n[2]}, "hexagon partly below the horizon"},
        {2, {0.1f, 0.5f, -0.2f}, {0, 1, 0}, "hexagon, half below the horizon"},
    };
    double worst = 0;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const polygon *poly = &polys[cases[i].poly];
        double want = monte_carlo_irradiance(poly, 0, 2.5, cases[i].p, cases[i].n, 400000);
        float got = polygon_e(poly, 0, 2.5f, cases[i].p, cases[i].n);
        assert_true(want > 0.01);
        assert_rel_close(got, want, 0.01, cases[i].what);
        worst = fmax(worst, fabs(got - want) / want);
        /* Two-sided emission changes nothing on the front side. */
        assert_rel_close(polygon_e(poly, 1, 2.5f, cases[i].p, cases[i].n), got, 1e-6,
                         cases[i].what);
    }
    print_message("polygon: worst error vs Monte Carlo (400k samples) %.3f%%\n", 100 * worst);
}

static void test_polygon_back_side(void **state)
{
    (void)state;
    /* Square emitting downwards; a receiver above it looks down at its back. */
    const float square[4][3] = {{-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}};
    polygon poly = make_polygon(4, square);
    assert_true(poly.normal[1] < -0.99f);
    const float p[3] = {0.2f, 3.0f, 0.1f}, down[3] = {0, -1, 0};
    assert_true(polygon_e(&poly, 0, 3.0f, p, down) == 0.0f);
    double want = monte_carlo_irradiance(&poly, 1, 3.0, p, down, 400000);
    assert_rel_close(polygon_e(&poly, 1, 3.0f, p, down), want, 0.01, "two-sided back face");
    /* Mirror image of a front-side configuration gives the same value. */
    const float p_front[3] = {0.2f, 1.0f, 0.1f}, up[3] = {0, 1, 0};
    assert_rel_close(polygon_e(&poly, 1, 3.0f, p, down), polygon_e(&poly, 0, 3.0f, p_front, up),
                     1e-5, "two-sided mirror symmetry");
    /* In the light's plane, or facing away from it: nothing. */
    const float in_plane[3] = {3, 2, 0}, side[3] = {-1, 0, 0};
    assert_true(polygon_e(&poly, 1, 3.0f, in_plane, side) == 0.0f);
    const float below[3] = {0, 0, 0};
    assert_true(polygon_e(&poly, 0, 3.0f, below, down) == 0.0f);
}

/* Form factor from a differential area to a parallel rectangle a x b at
 * height c with a corner straight above it (standard closed form). */
static double rectangle_form_factor(double a, double b, double c)
{
    double x = a / c, y = b / c, sx = sqrt(1 + x * x), sy = sqrt(1 + y * y);
    return (x / sx * atan(y / sx) + y / sy * atan(x / sy)) / (2 * PI_D);
}

static void test_polygon_analytic_cases(void **state)
{
    (void)state;
    const float origin[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    /* Rectangle 2 x 3 at height 1.5 with a corner above the receiver. */
    const float rect[4][3] = {{0, 1.5f, 0}, {2, 1.5f, 0}, {2, 1.5f, 3}, {0, 1.5f, 3}};
    polygon poly = make_polygon(4, rect);
    assert_true(poly.normal[1] < -0.99f);
    assert_rel_close(polygon_e(&poly, 0, 1.0f, origin, up),
                     PI_D * rectangle_form_factor(2, 3, 1.5), 1e-5, "corner rectangle");
    /* A huge square overhead covers nearly the whole hemisphere: E -> pi L
     * (the missing part is of the order of (height / half side)^2). */
    const float big[4][3] = {{-1e3f, 1, -1e3f}, {1e3f, 1, -1e3f}, {1e3f, 1, 1e3f}, {-1e3f, 1, 1e3f}};
    polygon huge = make_polygon(4, big);
    assert_rel_close(polygon_e(&huge, 0, 2.0f, origin, up), 2 * PI_D, 1e-5, "huge square");
    /* Tiny far polygon: E ~ L A cos_p cos_l / r^2. */
    const float s = 0.01f;
    const float tiny[4][3] = {{10, 4, 3}, {10, 4 + s, 3}, {10 + s, 4 + s, 3 + s}, {10 + s, 4, 3 + s}};
    polygon small = make_polygon(4, tiny);
    float n[3] = {0.6f, 0.3f, 0.2f};
    normalize3f(n);
    double c[3] = {10 + s / 2, 4 + s / 2, 3 + s / 2}, r2 = dot3(c, c), r = sqrt(r2);
    double nl[3] = {small.normal[0], small.normal[1], small.normal[2]};
    double cos_l = -dot3(nl, c) / r, cos_p = (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]) / r;
    double area = s * s * sqrt(2.0);
    float e_tiny = polygon_e(&small, 1, 5.0f, origin, n);
    assert_rel_close(e_tiny, 5.0 * area * cos_p * fabs(cos_l) / r2, 2e-3, "tiny far polygon");
}

static void test_polygon_symmetry_and_winding(void **state)
{
    (void)state;
    /* A regular octagon overhead, tilted receiver. */
    float oct[8][3];
    for (int i = 0; i < 8; ++i) {
        double a = 2 * PI_D * i / 8;
        oct[i][0] = (float)cos(a);
        oct[i][1] = 1.2f;
        oct[i][2] = (float)sin(a);
    }
    polygon poly = make_polygon(8, oct);
    assert_true(poly.normal[1] < -0.99f);
    float n[3] = {0.3f, 0.8f, 0.2f};
    normalize3f(n);
    const float p[3] = {0.4f, 0.1f, -0.3f};
    float e = polygon_e(&poly, 0, 1.0f, p, n);
    /* Any starting vertex and the reversed winding give the same result. */
    for (uint32_t shift = 1; shift < 8; ++shift) {
        polygon rolled = poly, reversed = poly;
        for (uint32_t i = 0; i < 8; ++i) {
            memcpy(rolled.v[i], oct[(i + shift) % 8], sizeof oct[0]);
            memcpy(reversed.v[i], oct[(8 + shift - i) % 8], sizeof oct[0]);
        }
        assert_rel_close(polygon_e(&rolled, 0, 1.0f, p, n), e, 1e-5, "rolled vertices");
        assert_rel_close(polygon_e(&reversed, 0, 1.0f, p, n), e, 1e-5, "reversed winding");
    }
    /* Mirroring receiver and normal across the octagon's x = 0 plane of
     * symmetry, and turning about its axis by 45 degrees, change nothing. */
    const float p_mirror[3] = {-p[0], p[1], p[2]}, n_mirror[3] = {-n[0], n[1], n[2]};
    assert_rel_close(polygon_e(&poly, 0, 1.0f, p_mirror, n_mirror), e, 1e-5, "mirror");
    const float c = (float)cos(PI_D / 4), s = (float)sin(PI_D / 4);
    const float p_turn[3] = {c * p[0] - s * p[2], p[1], s * p[0] + c * p[2]};
    const float n_turn[3] = {c * n[0] - s * n[2], n[1], s * n[0] + c * n[2]};
    assert_rel_close(polygon_e(&poly, 0, 1.0f, p_turn, n_turn), e, 1e-5, "turn by 45 degrees");
    /* Linear in radiance. */
    assert_rel_close(polygon_e(&poly, 0, 4.0f, p, n), 4 * e, 1e-6, "radiance scale");
    /* Entirely below the horizon: nothing. */
    const float down[3] = {0, -1, 0};
    assert_true(polygon_e(&poly, 0, 1.0f, p, down) == 0.0f);
}

static void test_polygon_bad_inputs(void **state)
{
    (void)state;
    const float v[9][3] = {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}};
    const float nl[3] = {0, -1, 0}, p[3] = {0, 0, 0}, n[3] = {0, 1, 0};
    float e = 5;
    assert_int_equal(sam_light_polygon_irradiance(v, 2, nl, 0, 1, p, n, &e), SAM_ERR_INVALID_ARGUMENT);
    assert_true(e == 0.0f);
    e = 5;
    assert_int_equal(sam_light_polygon_irradiance(v, 9, nl, 0, 1, p, n, &e), SAM_ERR_INVALID_ARGUMENT);
    assert_true(e == 0.0f);
    assert_int_equal(sam_light_polygon_irradiance(NULL, 3, nl, 0, 1, p, n, &e),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_polygon_irradiance(v, 3, NULL, 0, 1, p, n, &e),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_polygon_irradiance(v, 3, nl, 0, 1, NULL, n, &e),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_polygon_irradiance(v, 3, nl, 0, 1, p, NULL, &e),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_polygon_irradiance(v, 3, nl, 0, 1, p, n, NULL),
                     SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_polygon_irradiance(v, 3, nl, 0, 1, p, n, &e), SAM_OK);
    assert_true(e > 0);
}

/* ------------------------------------------------------------------------ */
/* scene lights                                                              */

static sam_light base_light(sam_light_type type)
{
    sam_light light;
    memset(&light, 0, sizeof light);
    light.type = type;
    light.color[0] = 1.0f;
    light.color[1] = 0.5f;
    light.color[2] = 0.25f;
    light.intensity = 8.0f;
    return light;
}

static void test_point_and_directional(void **state)
{
    (void)state;
    sam_light point = base_light(SAM_LIGHT_POINT);
    point.position[0] = 0;
    point.position[1] = 2;
    point.position[2] = 0;
    const float p[3] = {0, 0, 0}, up[3] = {0, 1, 0};
    float n60[3] = {(float)sin(PI_D / 3), (float)cos(PI_D / 3), 0}, out[3];
    assert_int_equal(sam_light_irradiance(&point, p, up, out), SAM_OK);
    assert_rel_close(out[0], 8.0 / 4, 1e-6, "point, normal incidence");
    assert_rel_close(out[2], 0.25 * 8.0 / 4, 1e-6, "point colour");
    assert_int_equal(sam_light_irradiance(&point, p, n60, out), SAM_OK);
    assert_rel_close(out[1], 0.5 * 8.0 / 4 * 0.5, 1e-6, "point at 60 degrees");
    const float down[3] = {0, -1, 0};
    assert_int_equal(sam_light_irradiance(&point, p, down, out), SAM_OK);
    assert_true(out[0] == 0 && out[1] == 0 && out[2] == 0);
    assert_int_equal(sam_light_irradiance(&point, point.position, up, out), SAM_OK);
    assert_true(out[0] == 0);

    sam_light sun = base_light(SAM_LIGHT_DIRECTIONAL);
    sun.direction[0] = 0;
    sun.direction[1] = -1;
    sun.direction[2] = 0;
    assert_int_equal(sam_light_irradiance(&sun, p, n60, out), SAM_OK);
    assert_rel_close(out[0], 8.0 * 0.5, 1e-6, "directional at 60 degrees");
    const float far[3] = {100, -50, 7};
    assert_int_equal(sam_light_irradiance(&sun, far, up, out), SAM_OK);
    assert_rel_close(out[0], 8.0, 1e-6, "directional ignores position");
    assert_int_equal(sam_light_irradiance(&sun, p, down, out), SAM_OK);
    assert_true(out[0] == 0);
}

static void test_spot_falloff(void **state)
{
    (void)state;
    sam_light spot = base_light(SAM_LIGHT_SPOT);
    spot.position[1] = 4;
    spot.direction[1] = -1;
    spot.inner_angle_deg = 20;
    spot.outer_angle_deg = 30;
    const float up[3] = {0, 1, 0};
    float out[3];
    /* Receivers on a sphere of radius 4 around the light, normal facing it,
     * at angles from the axis. */
    const double angles[] = {0, 10, 19.9, 20.1, 25, 29.9, 30.1, 45};
    for (size_t i = 0; i < sizeof angles / sizeof angles[0]; ++i) {
        double a = angles[i] * PI_D / 180;
        float p[3] = {(float)(4 * sin(a)), (float)(4 - 4 * cos(a)), 0};
        float n[3] = {-p[0], 4 - p[1], 0};
        normalize3f(n);
        assert_int_equal(sam_light_irradiance(&spot, p, n, out), SAM_OK);
        double c = cos(a), ci = cos(20 * PI_D / 180), co = cos(30 * PI_D / 180);
        double t = (c - co) / (ci - co);
        double falloff = c >= ci ? 1 : c <= co ? 0 : t * t * (3 - 2 * t);
        assert_true(fabs(out[0] - 8.0 / 16 * falloff) < 1e-5);
    }
    /* Halfway in cos: exactly half. */
    double c_half = 0.5 * (cos(20 * PI_D / 180) + cos(30 * PI_D / 180)), a = acos(c_half);
    float p[3] = {(float)(4 * sin(a)), (float)(4 - 4 * cos(a)), 0};
    float n[3] = {-p[0], 4 - p[1], 0};
    normalize3f(n);
    assert_int_equal(sam_light_irradiance(&spot, p, n, out), SAM_OK);
    assert_rel_close(out[0], 0.5 * 8.0 / 16, 1e-4, "spot halfway");
    /* inner == outer: a hard edge. */
    spot.inner_angle_deg = spot.outer_angle_deg = 25;
    for (int side = 0; side < 2; ++side) {
        double b = (side ? 25.2 : 24.8) * PI_D / 180;
        float q[3] = {(float)(4 * sin(b)), (float)(4 - 4 * cos(b)), 0};
        assert_int_equal(sam_light_irradiance(&spot, q, up, out), SAM_OK);
        assert_true(side ? out[0] == 0 : out[0] > 0.1f);
    }
}

static void test_area_light(void **state)
{
    (void)state;
    const float square[4][3] = {{-1, 2, -1}, {1, 2, -1}, {1, 2, 1}, {-1, 2, 1}};
    polygon poly = make_polygon(4, square);
    sam_light area = base_light(SAM_LIGHT_AREA);
    area.vertex_count = 4;
    memcpy(area.vertices, square, sizeof square);
    memcpy(area.normal, poly.normal, sizeof area.normal);
    area.area = 4;
    const float p[3] = {0.3f, 0, 0.2f}, up[3] = {0, 1, 0};
    float out[3];
    assert_int_equal(sam_light_irradiance(&area, p, up, out), SAM_OK);
    float e = polygon_e(&poly, 0, 1.0f, p, up);
    assert_rel_close(out[0], 8.0 * e, 1e-6, "area red");
    assert_rel_close(out[2], 0.25 * 8.0 * e, 1e-6, "area blue");
    const float above[3] = {0, 3, 0}, down[3] = {0, -1, 0};
    assert_int_equal(sam_light_irradiance(&area, above, down, out), SAM_OK);
    assert_true(out[0] == 0);
    area.two_sided = 1;
    assert_int_equal(sam_light_irradiance(&area, above, down, out), SAM_OK);
    assert_true(out[0] > 0);

    area.vertex_count = 2;
    out[0] = 1;
    assert_int_equal(sam_light_irradiance(&area, p, up, out), SAM_ERR_INVALID_ARGUMENT);
    assert_true(out[0] == 0);
    area.vertex_count = 4;
    area.type = (sam_light_type)9;
    assert_int_equal(sam_light_irradiance(&area, p, up, out), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_irradiance(NULL, p, up, out), SAM_ERR_INVALID_ARGUMENT);
    area.type = SAM_LIGHT_AREA;
    assert_int_equal(sam_light_irradiance(&area, NULL, up, out), SAM_ERR_INVALID_ARGUMENT);
    assert_int_equal(sam_light_irradiance(&area, p, up, NULL), SAM_ERR_INVALID_ARGUMENT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_latlong_convention),
        cmocka_unit_test(test_constant_environment),
        cmocka_unit_test(test_basis_orthonormal),
        cmocka_unit_test(test_polynomial_environment_exact),
        cmocka_unit_test(test_smooth_map_matches_brute_force),
        cmocka_unit_test(test_rotation_moves_features),
        cmocka_unit_test(test_sh_bad_inputs),
        cmocka_unit_test(test_studio_sky),
        cmocka_unit_test(test_outdoor_sky),
        cmocka_unit_test(test_sky_exr_round_trip),
        cmocka_unit_test(test_sky_bad_inputs),
        cmocka_unit_test(test_polygon_matches_monte_carlo),
        cmocka_unit_test(test_polygon_back_side),
        cmocka_unit_test(test_polygon_analytic_cases),
        cmocka_unit_test(test_polygon_symmetry_and_winding),
        cmocka_unit_test(test_polygon_bad_inputs),
        cmocka_unit_test(test_point_and_directional),
        cmocka_unit_test(test_spot_falloff),
        cmocka_unit_test(test_area_light),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
