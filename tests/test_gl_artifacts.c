/*
 * Artifacts a person sees at once and a PSNR against a truth that shares
 * them cannot: bands and copied outlines from the screen-space blur on
 * smooth surfaces, stair-stepped shadow terminators on coarse meshes,
 * shadow edges stepped by the shadow map's texels, and speckled shadows
 * far from the origin. On llvmpipe.
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
#include "sam_test.h"

/* A sam_shape mesh as a flat N = 3 map in `material` at `mm_per_unit`, on
 * the GPU; the caller destroys the runtime and frees `d`. */
static sam_runtime *shape_runtime(const char *shape, int resolution, double thickness, const char *material,
                                  float mm_per_unit, samfile_data *d)
{
    sam_mesh mesh;
    sam_test_shape_mesh(shape, resolution, 1.0, thickness, 0, &mesh);
    sam_profile profile;
    assert_int_equal(sam_profile_preset(material, &profile, NULL), SAM_OK);
    sam_build_settings set;
    sam_build_default_settings(&set);
    set.map = SAM_BUILD_MAP_FLAT;
    sam_error err;
    if (sam_build_samfile(&mesh, &profile, mm_per_unit, &set, NULL, NULL, NULL, d, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_mesh_destroy(&mesh);
    sam_runtime *rt;
    if (sam_runtime_create(d, &profile, mm_per_unit, &rt, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return rt;
}

/* One light casting shadows (without `shadow`, none), then L_d and T:
 * directional along (x, y, z), or with `point`, a point light at (x, y, z)
 * of intensity 0.2. */
static void light(sam_runtime *rt, float x, float y, float z, int point, int shadow)
{
    sam_light l;
    memset(&l, 0, sizeof l);
    l.type = point ? SAM_LIGHT_POINT : SAM_LIGHT_DIRECTIONAL;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    l.intensity = point ? 0.2f : 3.0f;
    l.shadow = shadow;
    float n = sqrtf(x * x + y * y + z * z);
    l.direction[0] = x / n, l.direction[1] = y / n, l.direction[2] = z / n;
    l.position[0] = x, l.position[1] = y, l.position[2] = z;
    sam_error err;
    if (sam_runtime_set_lights(rt, &l, 1, &err) != SAM_OK || sam_runtime_irradiance(rt, &err) != SAM_OK ||
        sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 1, &err) != SAM_OK)
        fail_msg("%s", err.message);
}

/* The object from (eye) towards the origin, `size` pixels square, 30
 * degrees of field of view (40 for a close eye). */
static sam_image render(sam_runtime *rt, uint32_t size, const float eye[3], int diffusion)
{
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = view.height = size;
    view.fov_deg = eye[0] * eye[0] + eye[1] * eye[1] + eye[2] * eye[2] < 1.0f ? 40.0f : 30.0f;
    memcpy(view.eye, eye, sizeof view.eye);
    view.up[1] = 1.0f;
    view.albedo[0] = view.albedo[1] = view.albedo[2] = 0.8f;
    view.front = 1;
    view.diffusion = diffusion;
    sam_image img;
    sam_error err;
    if (sam_runtime_render(rt, &view, &img, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return img;
}

static float luminance(const sam_image *img, uint32_t x, uint32_t y)
{
    const float *p = img->pixels + 4 * ((size_t)y * img->width + x);
    return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
}

/* Whether every pixel within `r` of (x, y) is on the object. */
static int inside(const sam_image *img, uint32_t x, uint32_t y, uint32_t r)
{
    if (x < r || y < r || x + r >= img->width || y + r >= img->height)
        return 0;
    for (uint32_t j = y - r; j <= y + r; ++j)
        for (uint32_t i = x - r; i <= x + r; ++i)
            if (!(img->pixels[4 * ((size_t)j * img->width + i) + 3] > 0.5f))
                return 0;
    return 1;
}

typedef struct smoothness {
    double p99; /* 99th percentile of |second difference| of what the blur changed, over the mean luminance */
    double rms; /* its rms, likewise */
    uint32_t pixels;
} smoothness;

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Second differences along rows and columns of what the blur changed,
 * blurred - unblurred, at interior pixels (4 pixels from any background):
 * the blur of smooth shading changes it smoothly, and a band is a jump.
 * The 99th percentile leaves out the few pixels at real edges (shadow
 * boundaries, where the blur rightly changes most). */
static smoothness measure(const sam_image *blurred, const sam_image *flat)
{
    smoothness s = {0, 0, 0};
    double mean = 0, sum2 = 0;
    double *d2 = malloc(2 * (size_t)blurred->width * blurred->height * sizeof *d2);
    assert_non_null(d2);
    size_t count = 0;
#define CHANGE(x, y) (luminance(blurred, x, y) - luminance(flat, x, y))
    for (uint32_t y = 0; y < blurred->height; ++y)
        for (uint32_t x = 0; x < blurred->width; ++x) {
            if (!inside(blurred, x, y, 4) || !inside(flat, x, y, 4))
                continue;
            float c = CHANGE(x, y);
            d2[count++] = fabsf(CHANGE(x - 1, y) - 2 * c + CHANGE(x + 1, y));
            d2[count++] = fabsf(CHANGE(x, y - 1) - 2 * c + CHANGE(x, y + 1));
            sum2 += d2[count - 1] * d2[count - 1] + d2[count - 2] * d2[count - 2];
            mean += luminance(flat, x, y);
            s.pixels++;
        }
#undef CHANGE
    mean /= s.pixels ? s.pixels : 1;
    if (count && mean > 0) {
        qsort(d2, count, sizeof *d2, cmp_double);
        s.p99 = d2[(size_t)(0.99 * (double)(count - 1))] / mean;
        s.rms = sqrt(sum2 / (double)count) / mean;
    }
    free(d2);
    return s;
}

/* Mean |a - b| of the luminance over the interior of both, over the mean
 * of b; and where `worst` is not NULL, the largest |a - b| over that mean. */
static double mean_difference_worst(const sam_image *a, const sam_image *b, double *worst)
{
    double sum = 0, ref = 0, most = 0;
    uint32_t n = 0;
    for (uint32_t y = 0; y < a->height; ++y)
        for (uint32_t x = 0; x < a->width; ++x)
            if (inside(a, x, y, 4) && inside(b, x, y, 4)) {
                const double d = fabsf(luminance(a, x, y) - luminance(b, x, y));
                sum += d;
                most = fmax(most, d);
                ref += luminance(b, x, y);
                n++;
            }
    if (worst)
        *worst = ref > 0 ? most / (ref / n) : 0;
    return ref > 0 ? sum / ref : 0;
}

static double mean_difference(const sam_image *a, const sam_image *b)
{
    return mean_difference_worst(a, b, NULL);
}

/* The screen-space blur of a smooth sphere, a torus (a bent cylinder) and
 * a plate seen at a grazing angle changes the unblurred picture smoothly
 * along every row and column, and little. Where a blur rounds its taps to
 * whole pixels, or drops a tap abruptly once its depth differs by more
 * than a threshold, the change jumps along the rows where depth crosses a
 * boundary, and each such row shows as a band. Where a wide kernel's taps
 * lie pixels apart and each reads one pixel, the change jumps wherever a
 * tap crosses the silhouette, a copy of the outline inside it at each
 * tap's offset (marble close up). */
static void test_screen_blur_has_no_bands(void **state)
{
    (void)state;
    static const struct {
        const char *shape;
        int resolution;
        double thickness;
        const char *material;
        float mm_per_unit;
        float eye[3], light[3];
        int point;
        double bound;  /* on the 99th percentile: the rounded, cut-off blur scored 0.0026, 0.019, 0.0063 on
                          the first three; a blur whose taps read one pixel each, 0.024 on the marble sphere */
        double change; /* on the mean change: marble's kernel is three times as wide as skin's */
    } cases[] = {{"sphere", 96, 0, "skin", 40.0f, {0.0f, 0.4f, 3.2f}, {-1.0f, -0.3f, -0.5f}, 0, 0.01, 0.05},
                 {"torus", 128, 0.4, "skin", 40.0f, {0.0f, 1.6f, 2.6f}, {-1.0f, -0.3f, -0.5f}, 0, 0.05, 0.05},
                 {"slab", 64, 0.05, "skin", 40.0f, {0.0f, 0.22f, 0.75f}, {0.0f, 0.3f, 0.2f}, 1, 0.001, 0.05},
                 /* A 30 mm marble sphere: its kernel's outer taps 10 pixels apart. */
                 {"sphere", 96, 0, "marble", 15.0f, {0.0f, 0.4f, 3.2f}, {-1.0f, -0.3f, -0.5f}, 0, 0.012, 0.1}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        samfile_data d;
        sam_runtime *rt = shape_runtime(cases[c].shape, cases[c].resolution, cases[c].thickness, cases[c].material, cases[c].mm_per_unit, &d);
        light(rt, cases[c].light[0], cases[c].light[1], cases[c].light[2], cases[c].point, 1);
        sam_image flat = render(rt, 256, cases[c].eye, 0), blurred = render(rt, 256, cases[c].eye, 1);
        smoothness b = measure(&blurred, &flat);
        double diff = mean_difference(&blurred, &flat);
        print_message("%s: %u interior pixels; second difference of blurred - unblurred over the mean: 99th "
                      "percentile %.6f, rms %.6f; blurred against unblurred %.2f%%\n",
                      cases[c].shape, b.pixels, b.p99, b.rms, 100 * diff);
        assert_true(b.pixels > 5000);
        assert_true(b.p99 < cases[c].bound);
        assert_true(diff < cases[c].change);
        sam_image_destroy(&flat);
        sam_image_destroy(&blurred);
        sam_runtime_destroy(rt);
        samfile_free(&d);
    }
}

/* Per row, the x (sub-pixel) where luminance rises through `level` going
 * right, from the dark side (-x) to the lit side (+x), nearest the lit
 * side; -1 when the row has none. */
static double crossing(const sam_image *img, uint32_t y, float level)
{
    for (uint32_t x = img->width - 2; x > 0; --x) {
        if (!inside(img, x, y, 2) || !inside(img, x + 1, y, 2))
            continue;
        float a = luminance(img, x, y), b = luminance(img, x + 1, y);
        if (a < level && b >= level)
            return x + (level - a) / (b - a);
    }
    return -1;
}

typedef struct terminator {
    double rms_d2; /* rms second difference of the crossing over rows, pixels */
    uint32_t rows; /* rows measured */
} terminator;

/* The crossings' smoothness down the picture, over the middle 60% of the
 * rows that have one (an edge that is round ends in rows where it runs
 * nearly along them, and its position there changes fast however smooth
 * it is). */
static terminator measure_terminator(const sam_image *img, float level)
{
    terminator t = {0, 0};
    double *x = malloc(img->height * sizeof *x);
    assert_non_null(x);
    uint32_t first = UINT32_MAX, last = 0;
    for (uint32_t y = 0; y < img->height; ++y) {
        x[y] = crossing(img, y, level);
        if (x[y] >= 0) {
            first = y < first ? y : first;
            last = y;
        }
    }
    double sum = 0;
    if (first != UINT32_MAX) {
        const uint32_t span = last - first, lo = first + span / 5, hi = last - span / 5;
        for (uint32_t y = lo + 1; y + 1 <= hi; ++y) {
            if (x[y - 1] < 0 || x[y] < 0 || x[y + 1] < 0)
                continue;
            double d2 = x[y - 1] - 2 * x[y] + x[y + 1];
            sum += d2 * d2;
            t.rows++;
        }
    }
    t.rms_d2 = t.rows ? sqrt(sum / t.rows) : 0;
    free(x);
    return t;
}

/* Fine (rt[0]) and coarse (rt[1]) meshes of one shape, from the front
 * under one directional light along `dir`: the coarse edge where the
 * luminance crosses `level` of the fine picture's peak runs down the rows
 * as smoothly as the fine one (rms second difference at most twice the
 * fine one's and a quarter pixel, over at least `min_rows` rows), and the
 * coarse picture stays within 5% of the fine one. Frees both. */
static void check_coarse_against_fine(const char *what, sam_runtime *rt[2], samfile_data d[2], const float dir[3],
                                      float level, uint32_t min_rows)
{
    const float eye[3] = {0.0f, 0.0f, 3.2f};
    sam_image img[2];
    terminator t[2];
    float peak = 0;
    for (int k = 0; k < 2; ++k) {
        light(rt[k], dir[0], dir[1], dir[2], 0, 1);
        img[k] = render(rt[k], 256, eye, 0);
    }
    for (uint32_t i = 0; i < img[0].width * img[0].height; ++i)
        peak = fmaxf(peak, luminance(&img[0], i % img[0].width, i / img[0].width));
    for (int k = 0; k < 2; ++k)
        t[k] = measure_terminator(&img[k], level * peak);
    double diff = mean_difference(&img[1], &img[0]);
    print_message("%s at %.0f%% of the peak: fine (%u vertices) %u rows, rms second difference %.3f px; coarse (%u "
                  "vertices) %u rows, %.3f px; coarse against fine %.2f%%\n",
                  what, 100 * level, d[0].vertex_count, t[0].rows, t[0].rms_d2, d[1].vertex_count, t[1].rows,
                  t[1].rms_d2, 100 * diff);
    assert_true(t[0].rows > min_rows && t[1].rows > min_rows);
    assert_true(t[1].rms_d2 <= 2.0 * t[0].rms_d2 + 0.25);
    assert_true(diff < 0.05);
    for (int k = 0; k < 2; ++k) {
        sam_image_destroy(&img[k]);
        sam_runtime_destroy(rt[k]);
        samfile_free(&d[k]);
    }
}

/* A coarse sphere (a few hundred vertices) lit from the side: its
 * terminator runs as smoothly down the picture as a fine sphere's (25k),
 * and its shading stays close to the fine one's. This held before the
 * front lighting moved to the pixels too; it keeps per-pixel shadow
 * lookups from letting the flat facets shadow their neighbours. */
static void test_coarse_terminator_is_smooth(void **state)
{
    (void)state;
    const int resolution[2] = {256, 28};
    const float dir[3] = {-1.0f, -0.25f, 0.35f};
    samfile_data d[2];
    sam_runtime *rt[2];
    /* Half a metre across: no translucency to speak of, the front alone. */
    for (int k = 0; k < 2; ++k)
        rt[k] = shape_runtime("sphere", resolution[k], 0, "skin", 500.0f, &d[k]);
    check_coarse_against_fine("terminator", rt, d, dir, 0.15f, 60);
}

/* Two spheres of `resolution` in one mesh: a unit one at `at` (NULL: the
 * origin) and a small one in front of it, up and to the left, that shadows
 * it; as a flat map on the GPU at half a metre across (no translucency to
 * speak of). */
static sam_runtime *shadowed_sphere_at(int resolution, const float *at_centre, samfile_data *d)
{
    sam_mesh big, small;
    sam_test_shape_mesh("sphere", resolution, 1.0, 0, 0, &big);
    sam_test_shape_mesh("sphere", resolution / 2, 0.3, 0, 0, &small);
    const uint32_t nv = big.vertex_count + small.vertex_count, nt = big.triangle_count + small.triangle_count;
    float *pos = malloc((size_t)nv * 3 * sizeof *pos);
    uint32_t *tri = malloc((size_t)nt * 3 * sizeof *tri);
    assert_non_null(pos);
    assert_non_null(tri);
    memcpy(pos, big.positions, (size_t)big.vertex_count * 3 * sizeof *pos);
    for (uint32_t v = 0; v < small.vertex_count; ++v) {
        const float at[3] = {-0.3f, 0.3f, 0.75f};
        for (int c = 0; c < 3; ++c)
            pos[3 * ((size_t)big.vertex_count + v) + c] = small.positions[3 * (size_t)v + c] + at[c];
    }
    memcpy(tri, big.triangles, (size_t)big.triangle_count * 3 * sizeof *tri);
    for (uint32_t t = 0; t < 3 * small.triangle_count; ++t)
        tri[3 * (size_t)big.triangle_count + t] = small.triangles[t] + big.vertex_count;
    for (uint32_t i = 0; at_centre && i < 3 * nv; ++i)
        pos[i] += at_centre[i % 3];
    sam_mesh_input in = {.name = "two spheres", .vertex_count = nv, .positions = pos, .triangle_count = nt,
                         .triangles = tri};
    sam_mesh mesh;
    sam_error err;
    if (sam_mesh_create(&in, &mesh, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_profile profile;
    assert_int_equal(sam_profile_preset("skin", &profile, NULL), SAM_OK);
    sam_build_settings set;
    sam_build_default_settings(&set);
    set.map = SAM_BUILD_MAP_FLAT;
    sam_runtime *rt = NULL;
    if (sam_build_samfile(&mesh, &profile, 500.0f, &set, NULL, NULL, NULL, d, NULL, &err) != SAM_OK ||
        sam_runtime_create(d, &profile, 500.0f, &rt, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_mesh_destroy(&mesh);
    sam_mesh_destroy(&big);
    sam_mesh_destroy(&small);
    free(pos);
    free(tri);
    return rt;
}

static sam_runtime *shadowed_sphere(int resolution, samfile_data *d)
{
    return shadowed_sphere_at(resolution, NULL, d);
}

/* The small sphere's shadow on the big one: on a coarse mesh (a few
 * hundred vertices) its edge runs as smoothly down the picture as on a
 * fine one, and the picture stays close to the fine one's. Front lighting
 * interpolated from the vertices' shadowed L_d made the edge follow the
 * triangles, a staircase a vertex apart. */
static void test_coarse_cast_shadow_is_smooth(void **state)
{
    (void)state;
    const int resolution[2] = {256, 28};
    const float dir[3] = {0.45f, -0.45f, -1.0f};
    samfile_data d[2];
    sam_runtime *rt[2];
    for (int k = 0; k < 2; ++k)
        rt[k] = shadowed_sphere(resolution[k], &d[k]);
    check_coarse_against_fine("cast shadow's edge", rt, d, dir, 0.5f, 25);
}

/* The mean width, in pixels, of the band where a row of `img` rises from
 * `lo` to `hi` (crossing's edges), over the rows that have both. */
static double band_width(const sam_image *img, float lo, float hi, uint32_t *rows)
{
    double sum = 0;
    *rows = 0;
    for (uint32_t y = 0; y < img->height; ++y) {
        double a = crossing(img, y, lo), b = crossing(img, y, hi);
        if (a >= 0 && b >= a) {
            sum += b - a;
            ++*rows;
        }
    }
    return *rows ? sum / *rows : 0;
}

/* The small sphere's shadow from a point light six radii away: its edge,
 * where the picture with shadows falls to half the one without, runs
 * smoothly down the picture, and sharply (a point light's shadow has no
 * penumbra). One hardware compare tap per lookup of a cube map, whose
 * texels were about 7 pixels here, drew it as a staircase of texels (rms
 * second difference 0.37 px here, against 0.19 with PCF; a head's ear
 * cast steps 10 to 20 pixels long at 1080p). With PCF the edge was a blur
 * some 25 pixels wide, and rings of self-shadowing crossed both lit
 * spheres: visibility rose from 10% to 90% over 140 pixels of a row on
 * average. The map fitted to the object, under a pixel a texel here,
 * draws the edge in 2.7. */
static void test_point_light_shadow_edge_is_smooth(void **state)
{
    (void)state;
    samfile_data d;
    sam_runtime *rt = shadowed_sphere(256, &d);
    const float eye[3] = {0.0f, 0.0f, 3.2f};
    sam_image img[2];
    for (int shadow = 0; shadow < 2; ++shadow) {
        light(rt, -2.3f, 2.3f, 5.1f, 1, shadow);
        img[shadow] = render(rt, 512, eye, 0);
    }
    float peak = 0;
    for (uint32_t i = 0; i < img[0].width * img[0].height; ++i)
        peak = fmaxf(peak, luminance(&img[0], i % img[0].width, i / img[0].width));
    /* Visibility, shadowed over unshadowed, where the light reaches at all. */
    for (uint32_t i = 0; i < img[1].width * img[1].height; ++i) {
        float lit = luminance(&img[0], i % img[0].width, i / img[0].width),
              shadowed = luminance(&img[1], i % img[1].width, i / img[1].width);
        float vis = lit > 0.02f * peak ? shadowed / lit : 1.0f;
        for (int c = 0; c < 3; ++c)
            img[1].pixels[4 * (size_t)i + c] = vis;
    }
    terminator t = measure_terminator(&img[1], 0.5f);
    uint32_t band_rows;
    double band = band_width(&img[1], 0.1f, 0.9f, &band_rows);
    print_message("point light's cast shadow: %u rows, rms second difference %.3f px; from 10%% to 90%% "
                  "visibility in %.1f px (%u rows)\n",
                  t.rows, t.rms_d2, band, band_rows);
    assert_true(t.rows > 40 && band_rows > 40);
    assert_true(t.rms_d2 < 0.3);
    assert_true(band < 6.0);
    for (int k = 0; k < 2; ++k)
        sam_image_destroy(&img[k]);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* A front view of `size` pixels square, 3.25 units in front of `at`. */
static sam_render_view view_of(const float at[3], uint32_t size)
{
    sam_render_view view;
    memset(&view, 0, sizeof view);
    view.width = view.height = size;
    view.fov_deg = 30.0f;
    memcpy(view.eye, at, sizeof view.eye);
    view.eye[2] += 3.25f;
    memcpy(view.target, at, sizeof view.target);
    view.up[1] = 1.0f;
    return view;
}

/* The two spheres lit by a point, a spot and a directional light, all with
 * shadows, seen from the front, with every position given as `at` plus
 * the offset to it (the lights' and the camera's too). */
static sam_image render_at(sam_runtime *rt, const float at[3])
{
    sam_light l[3];
    memset(l, 0, sizeof l);
    /* Offsets that floats hold exactly at 1e5: the far scene is the near one. */
    const float point[3] = {-2.25f, 2.25f, 5.125f}, spot[3] = {3.0f, 1.0f, 4.0f}, dir[3] = {0.4f, -0.5f, -0.77f};
    for (int i = 0; i < 3; ++i) {
        l[i].color[0] = l[i].color[1] = l[i].color[2] = 1.0f;
        l[i].shadow = 1;
    }
    for (int c = 0; c < 3; ++c) {
        l[0].position[c] = at[c] + point[c];
        l[1].position[c] = at[c] + spot[c];
        l[1].direction[c] = -spot[c] / 5.0f;
        l[2].direction[c] = dir[c];
    }
    l[0].type = SAM_LIGHT_POINT, l[0].intensity = 0.2f;
    l[1].type = SAM_LIGHT_SPOT, l[1].intensity = 0.2f, l[1].inner_angle_deg = 20, l[1].outer_angle_deg = 30;
    l[2].type = SAM_LIGHT_DIRECTIONAL, l[2].intensity = 1.0f;
    sam_error err;
    if (sam_runtime_set_lights(rt, l, 3, &err) != SAM_OK || sam_runtime_irradiance(rt, &err) != SAM_OK ||
        sam_runtime_translucency(rt, 0, 1.0f / 60.0f, 1, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_render_view view = view_of(at, 384);
    view.albedo[0] = view.albedo[1] = view.albedo[2] = 0.8f;
    view.front = 1;
    sam_image img;
    if (sam_runtime_render(rt, &view, &img, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return img;
}

/* The same mesh, lights and camera 1e5 of its radii from the origin (a
 * scan in georeferenced coordinates) render as they do about the origin,
 * and the runtime answers in model units. Positions on the GPU at 1e5
 * erred by a shadow texel or more in the rasteriser's interpolation and
 * the shadow matrices' products, and every shadowed light speckled the
 * lit spheres (no worse a precision than the vertices' own, which the
 * builder's precision warning covers). The far mesh is the near one moved
 * by a power of two, so that both hold the same triangles. */
static void test_far_from_origin_renders_as_near(void **state)
{
    (void)state;
    const float far[3] = {98304.0f, -65536.0f, 32768.0f}, near[3] = {0, 0, 0};
    samfile_data d;
    sam_runtime *rt[2] = {shadowed_sphere_at(160, far, &d), NULL};
    /* The near mesh from the far one's rounded vertices, exactly. */
    samfile_data moved = d;
    moved.positions = malloc((size_t)d.vertex_count * 3 * sizeof *moved.positions);
    assert_non_null(moved.positions);
    for (uint32_t i = 0; i < 3 * d.vertex_count; ++i)
        moved.positions[i] = d.positions[i] - far[i % 3];
    sam_profile profile;
    assert_int_equal(sam_profile_preset("skin", &profile, NULL), SAM_OK);
    sam_error err;
    if (sam_runtime_create(&moved, &profile, 500.0f, &rt[1], &err) != SAM_OK)
        fail_msg("%s", err.message);
    float centre[3], radius;
    sam_runtime_bounds(rt[0], centre, &radius);
    for (int c = 0; c < 3; ++c)
        assert_true(fabsf(centre[c] - far[c]) < 1.0f);
    float *pos = malloc((size_t)d.vertex_count * 3 * sizeof *pos);
    assert_non_null(pos);
    assert_int_equal(sam_runtime_read_positions(rt[0], pos, &err), SAM_OK);
    assert_memory_equal(pos, d.positions, (size_t)d.vertex_count * 3 * sizeof *pos);
    free(pos);
    sam_image img[2] = {render_at(rt[0], far), render_at(rt[1], near)};
    double worst;
    const double mean = mean_difference_worst(&img[0], &img[1], &worst);
    print_message("1e5 radii from the origin against at it: mean difference %.3f%%, largest %.2f%% of the mean\n",
                  100 * mean, 100 * worst);
    /* The far scene is the near one moved by floats' exact offsets, and so
     * it is on the GPU: the pictures match (without the frame, 24% apart
     * on average, the spheres covered in specks). */
    assert_true(mean < 1e-4);
    assert_true(worst < 0.01);
    const sam_render_view view = view_of(far, 64);
    sam_image gpos, gnrm;
    assert_int_equal(sam_runtime_gbuffer(rt[0], &view, SAM_GBUFFER_SCREEN, &gpos, &gnrm, &err), SAM_OK);
    const float *mid = gpos.pixels + 4 * (32 * 64 + 32);
    assert_true(mid[3] > 0 && fabsf(mid[0] - far[0]) < 1.5f && fabsf(mid[1] - far[1]) < 1.5f &&
                fabsf(mid[2] - far[2]) < 1.5f);
    sam_image_destroy(&gpos);
    sam_image_destroy(&gnrm);
    for (int k = 0; k < 2; ++k) {
        sam_image_destroy(&img[k]);
        sam_runtime_destroy(rt[k]);
    }
    free(moved.positions);
    samfile_free(&d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_screen_blur_has_no_bands),
        cmocka_unit_test(test_coarse_terminator_is_smooth),
        cmocka_unit_test(test_coarse_cast_shadow_is_smooth),
        cmocka_unit_test(test_point_light_shadow_edge_is_smooth),
        cmocka_unit_test(test_far_from_origin_renders_as_near),
    };
    return cmocka_run_group_tests(tests, sam_test_gl_setup, sam_test_gl_teardown);
}
