/*
 * Surface diffusion on llvmpipe: the texture-space stretch map on a sphere
 * with a known parameterisation, the shape of a blurred spot of light
 * against the profile, Jimenez and Gutierrez's optimisations against the
 * unoptimised render, d'Eon's albedo, and the fallback for unusable UVs.
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
#include "sam/sam_mesh.h"
#include "sam/sam_runtime.h"
#include "sam_test.h"

#define PI 3.14159265358979323846

/* A mesh from raw arrays, built into a .sam with `material` at `mm_per_unit`. */
static void build(const char *name, uint32_t vertex_count, const float *positions, const float *uvs,
                  uint32_t triangle_count, const uint32_t *triangles, const char *material, float mm_per_unit,
                  sam_profile *profile, samfile_data *out)
{
    sam_error err;
    sam_mesh_input in = {.name = name, .vertex_count = vertex_count, .positions = positions, .uvs = uvs,
                         .triangle_count = triangle_count, .triangles = triangles};
    sam_mesh mesh;
    if (sam_mesh_create(&in, &mesh, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    assert_int_equal(sam_profile_preset(material, profile, NULL), SAM_OK);
    if (sam_build_samfile(&mesh, profile, mm_per_unit, NULL, NULL, NULL, NULL, out, NULL, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_mesh_destroy(&mesh);
}

/* plane()'s UV layouts. */
enum {
    UV_UNIT,     /* (s, t) = ((x, z) + size/2) / size */
    UV_MIRRORED, /* the half x > 0 takes the UVs of its mirror image, so the halves overlap */
    UV_PAST,     /* (1.2 s - 0.1, 0.6 t): past [0,1] in u, in the atlas (s, t / 2) */
    UV_TILED,    /* (2 s, t): a map repeats twice across the plane */
};

/* An n x n vertex grid over [-size/2, size/2]^2 in the xz plane, facing +y,
 * with UVs of `layout`. Quad (i, j) is split along its (i, j)-(i+1, j+1)
 * diagonal. */
static void plane(int n, float size, int layout, const char *material, sam_profile *profile, samfile_data *out)
{
    float *pos = malloc((size_t)n * n * 3 * sizeof *pos), *uv = malloc((size_t)n * n * 2 * sizeof *uv);
    uint32_t *tri = malloc((size_t)(n - 1) * (n - 1) * 6 * sizeof *tri);
    assert_non_null(pos);
    assert_non_null(uv);
    assert_non_null(tri);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            size_t v = (size_t)j * n + i;
            float s = (float)i / (float)(n - 1), t = (float)j / (float)(n - 1);
            pos[3 * v] = (s - 0.5f) * size;
            pos[3 * v + 1] = 0.0f;
            pos[3 * v + 2] = (t - 0.5f) * size;
            uv[2 * v] = layout == UV_MIRRORED && s > 0.5f ? 1.0f - s
                        : layout == UV_PAST                ? 1.2f * s - 0.1f
                        : layout == UV_TILED               ? 2.0f * s
                                                           : s;
            uv[2 * v + 1] = layout == UV_PAST ? 0.6f * t : t;
        }
    size_t k = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            uint32_t a = (uint32_t)(j * n + i), b = a + 1, c = a + (uint32_t)n, d = c + 1;
            uint32_t quad[6] = {a, c, d, a, d, b};
            memcpy(tri + k, quad, sizeof quad);
            k += 6;
        }
    build("plane", (uint32_t)(n * n), pos, uv, (uint32_t)(k / 3), tri, material, 1.0f, profile, out);
    free(pos);
    free(uv);
    free(tri);
}

/* plane()'s skin plane on the GPU; the caller frees `d` and the runtime. */
static sam_runtime *skin_plane_runtime(int n, float size, int layout, sam_profile *profile, samfile_data *d)
{
    plane(n, size, layout, "skin", profile, d);
    sam_runtime *rt;
    sam_error err;
    if (sam_runtime_create(d, profile, 1.0f, &rt, &err) != SAM_OK)
        fail_msg("%s", err.message);
    return rt;
}

static sam_light directional(float x, float y, float z, float intensity)
{
    sam_light l;
    memset(&l, 0, sizeof l);
    l.type = SAM_LIGHT_DIRECTIONAL;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    l.intensity = intensity;
    float n = sqrtf(x * x + y * y + z * z);
    l.direction[0] = x / n, l.direction[1] = y / n, l.direction[2] = z / n;
    return l;
}

/* A hard-edged spot 5 mm above the plane, straight down: a disk of radius
 * 5 tan(angle) mm. */
static sam_light spot_from_above(float angle_deg)
{
    sam_light l;
    memset(&l, 0, sizeof l);
    l.type = SAM_LIGHT_SPOT;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    l.intensity = 25.0f;
    memcpy(l.position, (float[3]){0, 5, 0}, 3 * sizeof(float));
    memcpy(l.direction, (float[3]){0, -1, 0}, 3 * sizeof(float));
    l.inner_angle_deg = l.outer_angle_deg = angle_deg;
    return l;
}

/* plane()'s skin plane, 40 mm across, under a light from straight above
 * and without specular (it does not take the albedo, and would blur the
 * ratios), its irradiance computed. */
static sam_runtime *lit_plane(int layout, sam_profile *profile, samfile_data *d)
{
    sam_runtime *rt = skin_plane_runtime(33, 40.0f, layout, profile, d);
    sam_error err;
    sam_light l = directional(0, -1, 0, 1.0f);
    assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_set_surface(rt, 0.3f, 0.0f, &err), SAM_OK);
    assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
    return rt;
}

static void look(sam_render_view *view, uint32_t size, float fov, const float eye[3], const float target[3],
                 const float up[3])
{
    memset(view, 0, sizeof *view);
    view->width = view->height = size;
    view->fov_deg = fov;
    memcpy(view->eye, eye, 3 * sizeof(float));
    memcpy(view->target, target, 3 * sizeof(float));
    memcpy(view->up, up, 3 * sizeof(float));
    view->albedo[0] = view->albedo[1] = view->albedo[2] = 1.0f;
    view->front = 1;
    view->diffusion = 3;
}

/* Renders, and checks that the diffusion pass's timer does not read
 * longer than the render took (llvmpipe answered texture-space diffusion's with the time since
 * boot; the runtime reports such a time as missing, < 0). */
static void render(sam_runtime *rt, const sam_render_view *view, sam_image *out)
{
    sam_error err;
    double start = sam_seconds();
    if (sam_runtime_render(rt, view, out, &err) != SAM_OK)
        fail_msg("%s", err.message);
    double wall_ms = 1e3 * (sam_seconds() - start);
    /* Only screen and texture space time a diffusion pass. */
    double ms = view->diffusion == 1 || view->diffusion == 3 ? sam_runtime_pass_ms(rt, SAM_PASS_DIFFUSION) : -1;
    if (ms > wall_ms)
        fail_msg("texture-space diffusion's timer reads %.3f ms for a render of %.3f ms", ms, wall_ms);
}

/* A latitude band of the unit sphere (theta 20..160 degrees) with
 * u = phi / 2 pi and v = (theta - 20 deg) / 140 deg: one texel spans
 * 2 pi r sin(theta) / T along u and r (140 deg in radians) / T along v. */
static void test_stretch_matches_sphere(void **state)
{
    (void)state;
    const int cols = 256, rows = 128;
    const double t0 = 20 * PI / 180, t1 = 160 * PI / 180, mm = 10.0;
    uint32_t nv = (uint32_t)((cols + 1) * (rows + 1));
    float *pos = malloc(nv * 3 * sizeof *pos), *uv = malloc(nv * 2 * sizeof *uv);
    uint32_t *tri = malloc((size_t)cols * rows * 6 * sizeof *tri);
    assert_non_null(pos);
    assert_non_null(uv);
    assert_non_null(tri);
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i <= cols; ++i) {
            size_t v = (size_t)j * (cols + 1) + i;
            double phi = 2 * PI * i / cols, theta = t0 + (t1 - t0) * j / rows;
            pos[3 * v] = (float)(sin(theta) * cos(phi));
            pos[3 * v + 1] = (float)cos(theta);
            pos[3 * v + 2] = (float)(-sin(theta) * sin(phi));
            uv[2 * v] = (float)i / cols;
            uv[2 * v + 1] = (float)j / rows;
        }
    size_t k = 0;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i) {
            uint32_t a = (uint32_t)(j * (cols + 1) + i), b = a + 1, c = a + (uint32_t)cols + 1, d = c + 1;
            /* Outward: theta grows downward, phi counter-clockwise seen from +y. */
            uint32_t quad[6] = {a, c, d, a, d, b};
            memcpy(tri + k, quad, sizeof quad);
            k += 6;
        }
    sam_profile profile;
    samfile_data d;
    build("band", nv, pos, uv, (uint32_t)(k / 3), tri, "skin", (float)mm, &profile, &d);
    free(pos);
    free(uv);
    free(tri);
    sam_runtime *rt;
    sam_error err;
    assert_int_equal(sam_runtime_create(&d, &profile, (float)mm, &rt, &err), SAM_OK);
    char reason[160];
    if (!sam_runtime_uv_status(rt, reason, sizeof reason, NULL))
        fail_msg("%s", reason);
    sam_render_view view;
    look(&view, 64, 40.0f, (float[3]){0, 0, 4}, (float[3]){0, 0, 0}, (float[3]){0, 1, 0});
    sam_image img, stretch;
    render(rt, &view, &img);
    assert_int_equal(sam_runtime_read_atlas(rt, SAM_ATLAS_STRETCH, &stretch, &err), SAM_OK);
    uint32_t T = stretch.width;
    assert_int_equal(T, 1024);
    /* Rows 60..120 degrees, away from the u seam: a triangle's affine map
     * takes its u derivative from one of its two rows of vertices, which
     * are up to 140/128 degrees from the texel: a relative error of up to
     * dtheta |cot theta| = 1.1% here. */
    double worst_u = 0, worst_v = 0;
    size_t checked = 0;
    for (uint32_t y = 0; y < T; ++y) {
        double theta = t0 + (t1 - t0) * (y + 0.5) / T;
        if (theta < PI / 3 || theta > 2 * PI / 3)
            continue;
        for (uint32_t x = T / 20; x < T - T / 20; ++x) {
            const float *s = stretch.pixels + 4 * ((size_t)y * T + x);
            assert_true(s[3] > 0);
            double eu = 2 * PI * sin(theta) * mm / T, ev = (t1 - t0) * mm / T;
            worst_u = fmax(worst_u, fabs(s[0] - eu) / eu);
            worst_v = fmax(worst_v, fabs(s[1] - ev) / ev);
            checked++;
        }
    }
    printf("stretch on the sphere band: %zu texels, worst relative error %.4f along u, %.4f along v\n", checked,
           worst_u, worst_v);
    assert_true(checked > 300000);
    assert_true(worst_u < 0.015);
    assert_true(worst_v < 0.005);
    sam_image_destroy(&img);
    sam_image_destroy(&stretch);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* Linear interpolation of per-vertex values on plane()'s grid at (x, z). */
static double plane_value(const float *ld, int n, float size, int c, double x, double z)
{
    double h = size / (n - 1), gx = (x + 0.5 * size) / h, gz = (z + 0.5 * size) / h;
    int i = (int)floor(gx), j = (int)floor(gz);
    if (i < 0 || j < 0 || i >= n - 1 || j >= n - 1)
        return 0;
    double s = gx - i, t = gz - j;
    double l00 = ld[3 * (j * n + i) + c], l10 = ld[3 * (j * n + i + 1) + c], l01 = ld[3 * ((j + 1) * n + i) + c],
           l11 = ld[3 * ((j + 1) * n + i + 1) + c];
    /* The (i, j)-(i+1, j+1) diagonal splits the quad. */
    return t >= s ? l00 + s * (l11 - l01) + t * (l01 - l00) : l00 + s * (l10 - l00) + t * (l11 - l10);
}

/* A narrow spot light makes a small disk of light on a flat 20 x 20 mm skin
 * plane; texture-space diffusion spreads it. Along four directions from
 * the spot's centre, the diffused atlas matches the exact profile
 * convolved with the same light on the CPU: sum over the lit area of
 * R(|x - y|) L_d(y) dA. */
static void test_spot_matches_profile(void **state)
{
    (void)state;
    const int n = 129;
    const float size = 20.0f;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = skin_plane_runtime(n, size, UV_UNIT, &profile, &d);
    sam_error err;
    sam_light l = spot_from_above(8.0f); /* a disk of radius 0.7 mm */
    assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
    float *ld = malloc((size_t)n * n * 3 * sizeof *ld);
    assert_non_null(ld);
    assert_int_equal(sam_runtime_read_irradiance(rt, ld, &err), SAM_OK);
    sam_render_view view;
    look(&view, 64, 40.0f, (float[3]){0, 30, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
    sam_image img, atlas;
    render(rt, &view, &img);
    assert_int_equal(sam_runtime_read_atlas(rt, SAM_ATLAS_DIFFUSED, &atlas, &err), SAM_OK);
    uint32_t T = atlas.width;

    /* The CPU reference: the lit area (|x|, |z| < 1.2 mm) on a fine grid. */
    const int fine = 240;
    const double extent = 1.2, dA = (2 * extent / fine) * (2 * extent / fine);
    static const int dirs[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    double sum2[3] = {0}, err2[3] = {0}, worst[3] = {0};
    int samples = 0;
    for (int r_step = 0; r_step < 36; ++r_step) {
        int offset = (int)lround((0.25 + 0.2 * r_step) / size * T); /* 0.25 .. 7.25 mm */
        for (int dir = 0; dir < 4; ++dir) {
            int tx = (int)T / 2 + dirs[dir][0] * offset, ty = (int)T / 2 + dirs[dir][1] * offset;
            double x = ((tx + 0.5) / T - 0.5) * size, z = ((ty + 0.5) / T - 0.5) * size;
            double ref[3] = {0, 0, 0};
            for (int fj = 0; fj < fine; ++fj)
                for (int fi = 0; fi < fine; ++fi) {
                    double yx = -extent + (fi + 0.5) * 2 * extent / fine, yz = -extent + (fj + 0.5) * 2 * extent / fine;
                    double e = plane_value(ld, n, size, 0, yx, yz);
                    if (e <= 0)
                        continue;
                    float R[3];
                    sam_profile_eval(&profile, (float)hypot(x - yx, z - yz), R);
                    for (int c = 0; c < 3; ++c)
                        ref[c] += R[c] * plane_value(ld, n, size, c, yx, yz) * dA;
                }
            const float *got = atlas.pixels + 4 * ((size_t)ty * T + tx);
            for (int c = 0; c < 3; ++c) {
                double e = got[c] - ref[c];
                sum2[c] += ref[c] * ref[c];
                err2[c] += e * e;
                if (ref[c] > 0)
                    worst[c] = fmax(worst[c], fabs(e) / ref[c]);
            }
            samples++;
        }
    }
    for (int c = 0; c < 3; ++c) {
        double rel = sqrt(err2[c] / sum2[c]);
        printf("spot through texture-space diffusion, channel %d: relative RMS %.4f over %d samples "
               "(0.25-7.25 mm), worst single sample %.3f\n",
               c, rel, samples, worst[c]);
        assert_true(rel < 0.01);
    }
    free(ld);
    sam_image_destroy(&img);
    sam_image_destroy(&atlas);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* Texels the blur used (alpha > 0) in the last texture-space render. */
static size_t used_texels(sam_runtime *rt, uint32_t *side)
{
    sam_image a;
    sam_error err;
    assert_int_equal(sam_runtime_read_atlas(rt, SAM_ATLAS_IRRADIANCE, &a, &err), SAM_OK);
    size_t used = 0;
    for (size_t i = 0; i < (size_t)a.width * a.height; ++i)
        used += a.pixels[4 * i + 3] > 0;
    *side = a.width;
    sam_image_destroy(&a);
    return used;
}

static double psnr(const sam_image *a, const sam_image *b)
{
    sam_image ta, tb;
    sam_error err;
    assert_int_equal(sam_image_tonemap(a, SAM_TONEMAP_ACES, 0.0f, NULL, &ta, &err), SAM_OK);
    assert_int_equal(sam_image_tonemap(b, SAM_TONEMAP_ACES, 0.0f, NULL, &tb, &err), SAM_OK);
    sam_image_comparison cmp;
    assert_int_equal(sam_image_compare_srgb8(&ta, &tb, a, &cmp, &err), SAM_OK);
    sam_image_destroy(&ta);
    sam_image_destroy(&tb);
    return cmp.psnr_db;
}

/* Jimenez and Gutierrez's optimisations against the unoptimised render, on
 * a skin sphere (cube-sphere charts) lit from the side and behind: each
 * must skip texels, and still give the same picture (PSNR over the
 * object >= 45 dB, or the bound below with its reason). */
static void test_optimizations_match(void **state)
{
    (void)state;
    sam_mesh mesh;
    sam_test_shape_mesh("sphere", 40, 1.0, 0, 0, &mesh);
    sam_profile profile;
    assert_int_equal(sam_profile_preset("skin", &profile, NULL), SAM_OK);
    samfile_data d;
    sam_error err;
    const float mm = 60.0f; /* a 60 mm ball */
    assert_int_equal(sam_build_samfile(&mesh, &profile, mm, NULL, NULL, NULL, NULL, &d, NULL, &err), SAM_OK);
    sam_mesh_destroy(&mesh);
    sam_runtime *rt;
    assert_int_equal(sam_runtime_create(&d, &profile, mm, &rt, &err), SAM_OK);
    /* A key light from the viewer's side, and a red-heavy one from behind. */
    sam_light lights[2] = {directional(-1, -0.3f, -0.5f, 3.0f), directional(0.4f, 0.2f, 1.0f, 1.5f)};
    lights[1].color[1] = lights[1].color[2] = 0.5f;

    /* The bound each case is held to. A depth-sized atlas resamples
     * everything, irradiance included, at about one texel per pixel, so
     * it is held to 44 dB far away (46.0 dB measured); the others to 45.
     * While the blur stopped at UV seams, culled back-lit scored 40 dB and
     * depth-sized 37.7: the seams' artefacts moved with what the
     * optimisations left beside them. docs/validation.md gives these
     * numbers. */
    struct {
        const char *name;
        float eye[3], fov;
        int back_lit, culled, clipped, depth_sized;
        double bound_db;
    } cases[] = {
        {"culled, front-lit, whole object in view", {0.3f, 0.4f, 2.5f}, 40.0f, 0, 1, 0, 0, 45.0},
        {"culled, back-lit, whole object in view", {0.3f, 0.4f, 2.5f}, 40.0f, 1, 1, 0, 0, 45.0},
        {"clipped, back-lit close-up", {0.2f, 0.1f, 0.9f}, 30.0f, 1, 0, 1, 0, 45.0},
        {"depth-sized, back-lit, far away", {0.0f, 0.0f, 14.0f}, 30.0f, 1, 0, 0, 1, 44.0},
        {"all three, back-lit close-up", {0.2f, 0.1f, 0.9f}, 30.0f, 1, 1, 1, 1, 45.0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        assert_int_equal(sam_runtime_set_lights(rt, lights, cases[i].back_lit ? 2 : 1, &err), SAM_OK);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        assert_int_equal(sam_runtime_translucency(rt, 0, 0.0f, 1, &err), SAM_OK);
        sam_render_view view;
        look(&view, 256, cases[i].fov, cases[i].eye, (float[3]){0, 0, 0}, (float[3]){0, 1, 0});
        sam_image base, fast;
        uint32_t base_side, fast_side;
        render(rt, &view, &base);
        size_t base_used = used_texels(rt, &base_side);

        view.options.culled = cases[i].culled;
        view.options.clipped = cases[i].clipped;
        view.options.depth_sized = cases[i].depth_sized;
        render(rt, &view, &fast);
        size_t fast_used = used_texels(rt, &fast_side);
        double db = psnr(&base, &fast);
        printf("%s: atlas %u -> %u, texels blurred %zu -> %zu (%.2fx fewer), PSNR %.2f dB\n", cases[i].name,
               base_side, fast_side, base_used, fast_used, (double)base_used / (double)fast_used, db);
        assert_true(fast_used < base_used);
        if (cases[i].depth_sized && cases[i].eye[2] > 10)
            assert_true(fast_side < base_side);
        assert_true(db >= cases[i].bound_db);
        sam_image_destroy(&base);
        sam_image_destroy(&fast);
    }
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* The worst relative difference of two 96 x 96 renders' RGB. */
static double worst_relative(const sam_image *plain, const sam_image *other)
{
    double worst = 0;
    for (size_t i = 0; i < 96 * 96; ++i)
        for (int c = 0; c < 3; ++c)
            worst = fmax(worst, fabs(plain->pixels[4 * i + c] - other->pixels[4 * i + c]) /
                                    fmax(plain->pixels[4 * i + c], 1e-6));
    return worst;
}

/* Sets (on) or clears the albedo source a test gives in `what`. */
typedef void (*albedo_setter)(sam_runtime *rt, int on, const void *what);

static void set_map(sam_runtime *rt, int on, const void *map)
{
    sam_error err;
    assert_int_equal(sam_runtime_set_albedo_map(rt, on ? map : NULL, &err), SAM_OK);
}

typedef struct vertex_colors {
    const float *rgb;
    uint32_t count;
} vertex_colors;

static void set_colors(sam_runtime *rt, int on, const void *colors)
{
    const vertex_colors *c = colors;
    sam_error err;
    assert_int_equal(sam_runtime_set_vertex_colors(rt, on ? c->rgb : NULL, on ? c->count : 0, &err), SAM_OK);
}

/* In every diffusion mode, an albedo of `tone` that `set` gives (`what`,
 * `name` in the output) renders as the view's uniform albedo `tone`. */
static void assert_like_uniform(sam_runtime *rt, sam_render_view *view, const float tone[3], albedo_setter set,
                                const void *what, const char *name)
{
    for (int mode = 0; mode <= 3; ++mode) {
        sam_image plain, given;
        view->diffusion = mode;
        memcpy(view->albedo, tone, 3 * sizeof *tone);
        set(rt, 0, what);
        render(rt, view, &plain);
        view->albedo[0] = view->albedo[1] = view->albedo[2] = 1.0f;
        set(rt, 1, what);
        render(rt, view, &given);
        const double worst = worst_relative(&plain, &given);
        printf("diffusion %d: %s vs uniform albedo, worst relative difference %.2e\n", mode, name, worst);
        assert_true(worst < 1e-5);
        sam_image_destroy(&plain);
        sam_image_destroy(&given);
    }
}

/* Under uniform light, an albedo of 0.25 on the plane's z > 0 half (the
 * image's bottom) and 0.9 on the other comes out at their ratio away from
 * the edge, without diffusion and in texture space; `ratio` is that of
 * the values the albedo holds. */
static void assert_two_tone(sam_runtime *rt, sam_render_view *view, const char *what, double ratio)
{
    for (int mode = 0; mode <= 3; mode += 3) {
        sam_image img;
        view->diffusion = mode;
        render(rt, view, &img);
        /* The plane spans 40 mm over about 79 pixels; rows 20 and 76 are
         * 14 mm from the edge, beyond the skin profile's reach. */
        double top = img.pixels[4 * (20 * 96 + 48)], bottom = img.pixels[4 * (76 * 96 + 48)];
        printf("diffusion %d: two-tone %s, bottom / top %.4f (albedo ratio %.4f)\n", mode, what, bottom / top, ratio);
        assert_true(fabs(bottom / top - ratio) < 0.01 * ratio);
        sam_image_destroy(&img);
    }
}

/* d'Eon Sec. 5.3: sqrt(albedo) before the blur and after it. A constant
 * map gives the picture of the same uniform albedo in every mode, and
 * under uniform light a two-tone map comes out at its own albedo away
 * from the edge, the right way up. */
static void test_albedo_map(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_plane(UV_UNIT, &profile, &d);
    sam_error err;
    sam_render_view view;
    /* Looking down with image up = world -z: the top of the image is v = 0. */
    look(&view, 96, 40.0f, (float[3]){0, 40, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
    const float tone[3] = {0.9f, 0.5f, 0.3f};
    sam_image map;
    assert_int_equal(sam_image_create(&map, 8, 8, 3, &err), SAM_OK);
    for (int i = 0; i < 64; ++i)
        memcpy(map.pixels + 3 * i, tone, sizeof tone);
    assert_like_uniform(rt, &view, tone, set_map, &map, "constant albedo map");
    /* Top rows of the map (v = 1, the image's bottom) dark. */
    for (int y = 0; y < 4; ++y)
        for (int i = 0; i < 8 * 3; ++i)
            map.pixels[y * 8 * 3 + i] = 0.25f;
    assert_int_equal(sam_runtime_set_albedo_map(rt, &map, &err), SAM_OK);
    sam_image_destroy(&map);
    assert_two_tone(rt, &view, "map", 0.25 / 0.9);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* Several maps, each on its own triangles: maps of different sizes (one
 * array layer each, resampled) come out at their own albedo away from the
 * boundary between them; a map with no pixels, or a triangle reading
 * none, is white; a triangle count or map index the runtime cannot take
 * is refused; sam_runtime_set_albedo_map clears them. */
static void test_albedo_maps(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_plane(UV_UNIT, &profile, &d);
    sam_error err;
    sam_render_view view;
    look(&view, 96, 40.0f, (float[3]){0, 40, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
    sam_image maps[3];
    const float tone[2] = {0.9f, 0.25f};
    for (int m = 0; m < 2; ++m) {
        assert_int_equal(sam_image_create(&maps[m], 8 >> (2 * m), 8 >> m, 3, &err), SAM_OK);
        for (size_t i = 0; i < (size_t)maps[m].width * maps[m].height * 3; ++i)
            maps[m].pixels[i] = tone[m];
    }
    memset(&maps[2], 0, sizeof maps[2]);
    const uint32_t nt = d.triangle_count;
    uint32_t *tri = malloc(nt * sizeof *tri);
    assert_non_null(tri);
    /* z > 0 (the image's bottom) reads map 1. */
    for (uint32_t t = 0; t < nt; ++t) {
        float z = 0;
        for (int k = 0; k < 3; ++k)
            z += d.positions[3 * d.triangles[3 * t + (uint32_t)k] + 2];
        tri[t] = z > 0 ? 1 : 0;
    }
    assert_int_equal(sam_runtime_set_albedo_maps(rt, maps, 2, tri, nt - 1, &err), SAM_ERR_INVALID_ARGUMENT);
    printf("%s\n", err.message);
    tri[0] = 2;
    assert_int_equal(sam_runtime_set_albedo_maps(rt, maps, 2, tri, nt, &err), SAM_ERR_INVALID_ARGUMENT);
    printf("%s\n", err.message);
    tri[0] = 0;
    assert_int_equal(sam_runtime_set_albedo_maps(rt, maps, 2, tri, nt, &err), SAM_OK);
    /* Held as sRGB bytes, as the 8-bit textures they come from. */
    const double q9 = sam_srgb_to_linear(roundf(sam_linear_to_srgb(0.9f) * 255) / 255),
                 q25 = sam_srgb_to_linear(roundf(sam_linear_to_srgb(0.25f) * 255) / 255);
    assert_two_tone(rt, &view, "maps", q25 / q9);
    /* The bottom white (no map, an empty map), the top 0.9: uniform 0.9
     * from the view's albedo and a constant map below gives the same. */
    for (int none = 0; none < 2; ++none) {
        for (uint32_t t = 0; t < nt; ++t)
            tri[t] = tri[t] ? (none ? SAM_ALBEDO_NO_MAP : 2) : 0;
        assert_int_equal(sam_runtime_set_albedo_maps(rt, maps, 3, tri, nt, &err), SAM_OK);
        sam_image img;
        view.diffusion = 0;
        render(rt, &view, &img);
        const double top = img.pixels[4 * (20 * 96 + 48)], bottom = img.pixels[4 * (76 * 96 + 48)];
        printf("%s: bottom / top %.4f (white / 0.9 as a byte = %.4f)\n", none ? "no map" : "an empty map",
               bottom / top, 1 / q9);
        assert_true(fabs(bottom / top - 1 / q9) < 0.01 / q9);
        sam_image_destroy(&img);
    }
    assert_int_equal(sam_runtime_set_albedo_map(rt, NULL, &err), SAM_OK);
    sam_image flat;
    render(rt, &view, &flat);
    assert_true(fabs(flat.pixels[4 * (76 * 96 + 48)] / flat.pixels[4 * (20 * 96 + 48)] - 1) < 1e-3);
    sam_image_destroy(&flat);
    for (int m = 0; m < 2; ++m)
        sam_image_destroy(&maps[m]);
    free(tri);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* Vertex colours multiply the albedo as a map does: constant ones give the
 * picture of that uniform albedo in every mode, and a two-tone colouring
 * by position comes out at its own albedo away from the edge, given in
 * the source mesh's order where the map has SRCV (here the vertices
 * reversed). A count that is not the source mesh's is refused. */
static void test_vertex_colors(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_plane(UV_UNIT, &profile, &d);
    sam_error err;
    sam_render_view view;
    look(&view, 96, 40.0f, (float[3]){0, 40, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
    const float tone[3] = {0.9f, 0.5f, 0.3f};
    const uint32_t nv = d.vertex_count;
    float *rgb = malloc((size_t)nv * 3 * sizeof *rgb);
    assert_non_null(rgb);
    for (uint32_t v = 0; v < nv; ++v)
        memcpy(rgb + 3 * v, tone, sizeof tone);
    assert_int_equal(sam_runtime_set_vertex_colors(rt, rgb, nv - 1, &err), SAM_ERR_INVALID_ARGUMENT);
    printf("%s\n", err.message);
    const vertex_colors colors = {rgb, nv};
    assert_like_uniform(rt, &view, tone, set_colors, &colors, "constant vertex colours");
    sam_runtime_destroy(rt);

    /* The same plane as built from a mesh whose vertices came in reverse. */
    assert_int_equal(d.source_vertex_count, nv);
    for (uint32_t v = 0; v < nv; ++v)
        d.vertex_source[v] = d.source_vertex[v] = nv - 1 - v;
    if (sam_runtime_create(&d, &profile, 1.0f, &rt, &err) != SAM_OK)
        fail_msg("%s", err.message);
    sam_light l = directional(0, -1, 0, 1.0f);
    assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
    assert_int_equal(sam_runtime_set_surface(rt, 0.3f, 0.0f, &err), SAM_OK);
    assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
    /* z > 0 (the image's bottom) dark, in the source order. */
    for (uint32_t v = 0; v < nv; ++v)
        for (int c = 0; c < 3; ++c)
            rgb[3 * (nv - 1 - v) + (uint32_t)c] = d.positions[3 * v + 2] > 0 ? 0.25f : 0.9f;
    assert_int_equal(sam_runtime_set_vertex_colors(rt, rgb, nv, &err), SAM_OK);
    assert_two_tone(rt, &view, "vertex colours", 0.25 / 0.9);
    free(rgb);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* Mirrored UVs (the plane's right half on its left half) make texture-space
 * diffusion unavailable, with a reason, instead of summing two places'
 * light in one texel. */
static void test_overlapping_uvs_refused(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = skin_plane_runtime(17, 20.0f, UV_MIRRORED, &profile, &d);
    sam_error err;
    char reason[160];
    assert_int_equal(sam_runtime_uv_status(rt, reason, sizeof reason, NULL), 0);
    printf("mirrored plane: %s\n", reason);
    assert_non_null(strstr(reason, "more than one"));
    sam_render_view view;
    look(&view, 32, 40.0f, (float[3]){0, 30, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
    sam_image img;
    assert_int_equal(sam_runtime_render(rt, &view, &img, &err), SAM_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "more than one"));
    view.diffusion = 1;
    render(rt, &view, &img);
    sam_image_destroy(&img);
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* A spot-lit plane whose UVs reach past [0,1]^2 gets texture-space
 * diffusion (its layout moved into the atlas), and the picture of the same
 * plane with UVs in the unit square. */
static void test_uvs_past_the_square(void **state)
{
    (void)state;
    const sam_light l = spot_from_above(20.0f); /* a disk of radius 1.8 mm */
    sam_render_view view;
    look(&view, 96, 40.0f, (float[3]){0, 20, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
    sam_image img[2];
    for (int k = 0; k < 2; ++k) {
        sam_profile profile;
        samfile_data d;
        sam_runtime *rt = skin_plane_runtime(49, 16.0f, k ? UV_PAST : UV_UNIT, &profile, &d);
        sam_error err;
        char reason[160];
        sam_uv_atlas atlas;
        assert_int_equal(sam_runtime_uv_status(rt, reason, sizeof reason, &atlas), 1);
        assert_int_equal(atlas.moved, k);
        if (k) {
            printf("UVs u %g..%g, v %g..%g: scale %g, offset (%g, %g)\n", (double)atlas.lo[0], (double)atlas.hi[0],
                   (double)atlas.lo[1], (double)atlas.hi[1], (double)atlas.scale, (double)atlas.offset[0],
                   (double)atlas.offset[1]);
            assert_float_equal(atlas.scale, 1.0 / 1.2, 1e-5);
        }
        assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        render(rt, &view, &img[k]);
        sam_runtime_destroy(rt);
        samfile_free(&d);
    }
    /* The moved atlas packs v into half the texels, so the two differ by
     * resampling only. */
    const double db = psnr(&img[0], &img[1]);
    printf("spot-lit plane, UVs in the unit square vs past it: PSNR %.2f dB\n", db);
    assert_true(db > 40.0);
    sam_image_destroy(&img[0]);
    sam_image_destroy(&img[1]);
}

/* A tiled layout (u from 0 to 2) repeats the albedo map across the plane
 * instead of stretching its edge texels over the second tile. */
static void test_tiled_albedo_repeats(void **state)
{
    (void)state;
    sam_profile profile;
    samfile_data d;
    sam_runtime *rt = lit_plane(UV_TILED, &profile, &d);
    sam_error err;
    sam_image map;
    assert_int_equal(sam_image_create(&map, 8, 8, 3, &err), SAM_OK);
    for (int i = 0; i < 64; ++i)
        for (int c = 0; c < 3; ++c)
            map.pixels[3 * i + c] = i % 8 < 4 ? 0.25f : 0.9f; /* dark for u < 0.5 */
    assert_int_equal(sam_runtime_set_albedo_map(rt, &map, &err), SAM_OK);
    sam_image_destroy(&map);
    sam_render_view view;
    look(&view, 96, 40.0f, (float[3]){0, 40, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
    for (int mode = 0; mode <= 3; mode += 3) {
        view.diffusion = mode;
        sam_image img;
        render(rt, &view, &img);
        /* The view spans x = +-14.6 mm over 96 columns; columns 6, 23, 72
         * and 88 lie at x = -12.5, -7.5, 7.5, 12.5 mm, u = 0.375 (dark),
         * 0.625, 1.375 (dark when the map repeats, bright when clamped)
         * and 1.625, each 2.5 mm from a change of tone. */
        double q[4];
        const int col[4] = {6, 23, 72, 88};
        for (int i = 0; i < 4; ++i)
            q[i] = img.pixels[4 * (48 * 96 + col[i])];
        printf("diffusion %d: tiled map across the plane %.4f %.4f %.4f %.4f\n", mode, q[0], q[1], q[2], q[3]);
        /* Diffusion carries some light across the 2.5 mm to a change. */
        const double tolerance = mode ? 0.15 : 0.01;
        assert_true(fabs(q[2] / q[3] - 0.25 / 0.9) < tolerance * 0.25 / 0.9);
        assert_true(fabs(q[2] / q[0] - 1.0) < tolerance);
        assert_true(fabs(q[3] / q[1] - 1.0) < tolerance);
        sam_image_destroy(&img);
    }
    sam_runtime_destroy(rt);
    samfile_free(&d);
}

/* plane()'s grid (n odd) cut along x = 0 into two charts: the half x <= 0
 * at (u, v) = (0.02, 0.02) + k (x + size/2, z + size/2), the half x >= 0
 * turned over into (0.05 + k size/2, 0.02) + k (z + size/2, x), with
 * k = 0.031 per mm of a 20 mm plane: a UV seam down the middle, the two
 * sides' texels 0.03 of the atlas apart and running along different axes.
 * Built in skin at 1 mm per unit. */
#define SEAM_SCALE 0.031f

static void seamed_plane(int n, float size, sam_profile *profile, samfile_data *out)
{
    const int mid = (n - 1) / 2, left = mid + 1, right = n - mid;
    const uint32_t vc = (uint32_t)(n * (left + right));
    float *pos = malloc(vc * 3 * sizeof *pos), *uv = malloc(vc * 2 * sizeof *uv);
    uint32_t *tri = malloc((size_t)(n - 1) * (n - 1) * 6 * sizeof *tri);
    assert_non_null(pos);
    assert_non_null(uv);
    assert_non_null(tri);
    const float k = SEAM_SCALE * 20.0f / size;
    for (int j = 0; j < n; ++j)
        for (int side = 0; side < 2; ++side)
            for (int c = 0; c < (side ? right : left); ++c) {
                const int i = side ? mid + c : c;
                const uint32_t v = side ? (uint32_t)(n * left + j * right + c) : (uint32_t)(j * left + c);
                const float x = ((float)i / (float)(n - 1) - 0.5f) * size, z = ((float)j / (float)(n - 1) - 0.5f) * size;
                pos[3 * v] = x;
                pos[3 * v + 1] = 0.0f;
                pos[3 * v + 2] = z;
                uv[2 * v] = side ? 0.05f + k * (z + size) : 0.02f + k * (x + 0.5f * size);
                uv[2 * v + 1] = side ? 0.02f + k * x : 0.02f + k * (z + 0.5f * size);
            }
    size_t t = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const int side = i >= mid, c = side ? i - mid : i, row = side ? right : left;
            const uint32_t base = side ? (uint32_t)(n * left) : 0u;
            uint32_t a = base + (uint32_t)(j * row + c), b = a + 1, cc = a + (uint32_t)row, d = cc + 1;
            uint32_t quad[6] = {a, cc, d, a, d, b};
            memcpy(tri + t, quad, sizeof quad);
            t += 6;
        }
    build("seamed plane", vc, pos, uv, (uint32_t)(t / 3), tri, "skin", 1.0f, profile, out);
    free(pos);
    free(uv);
    free(tri);
}

/* The diffused atlas at surface point (x, z) of seamed_plane (`seamed`) or
 * of plane()'s UV_UNIT plane, both `size` mm across: the nearest texel. */
static const float *diffused_at(const sam_image *atlas, int seamed, float size, double x, double z)
{
    const double k = SEAM_SCALE * 20.0 / size;
    double u = (x + 0.5 * size) / size, v = (z + 0.5 * size) / size;
    if (seamed) {
        u = x < 0 ? 0.02 + k * (x + 0.5 * size) : 0.05 + k * (z + size);
        v = x < 0 ? 0.02 + k * (z + 0.5 * size) : 0.02 + k * x;
    }
    const uint32_t T = atlas->width;
    size_t tx = (size_t)fmin(floor(u * T), T - 1), ty = (size_t)fmin(floor(v * T), T - 1);
    return atlas->pixels + 4 * (ty * T + tx);
}

/* A spot of light on a UV seam: the blur follows the surface from one
 * chart into the other, so across the seam and along it the diffused light
 * matches the same plane with one chart (its atlas 1.6 times denser). The
 * blur that stopped at seams, using each texel's own value for the taps
 * across, erred by 0.215 on average here, and by up to 0.997. */
static void test_spot_across_a_seam(void **state)
{
    (void)state;
    const int n = 129;
    const float size = 20.0f;
    sam_image atlas[2];
    for (int seamed = 0; seamed < 2; ++seamed) {
        sam_profile profile;
        samfile_data d;
        sam_runtime *rt;
        sam_error err;
        if (seamed)
            seamed_plane(n, size, &profile, &d);
        else
            plane(n, size, UV_UNIT, "skin", &profile, &d);
        if (sam_runtime_create(&d, &profile, 1.0f, &rt, &err) != SAM_OK)
            fail_msg("%s", err.message);
        sam_light l = spot_from_above(8.0f);
        assert_int_equal(sam_runtime_set_lights(rt, &l, 1, &err), SAM_OK);
        assert_int_equal(sam_runtime_irradiance(rt, &err), SAM_OK);
        sam_render_view view;
        sam_image img;
        look(&view, 64, 40.0f, (float[3]){0, 30, 0.01f}, (float[3]){0, 0, 0}, (float[3]){0, 0, -1});
        render(rt, &view, &img);
        assert_int_equal(sam_runtime_read_atlas(rt, SAM_ATLAS_DIFFUSED, &atlas[seamed], &err), SAM_OK);
        sam_image_destroy(&img);
        sam_runtime_destroy(rt);
        samfile_free(&d);
    }
    /* Along x through the spot and along z beside the seam, 0.3-6 mm out:
     * each channel's relative error where it holds at least a thousandth
     * of its value at the spot. */
    double sum = 0, worst = 0;
    int count = 0;
    for (int line = 0; line < 4; ++line)
        for (int step = 0; step < 20; ++step) {
            const double r = 0.3 + 0.3 * step, sign = line % 2 ? -1 : 1;
            const double x = line < 2 ? sign * r : sign * 0.2, z = line < 2 ? 0.05 : r;
            const float *a = diffused_at(&atlas[0], 0, size, x, z), *b = diffused_at(&atlas[1], 1, size, x, z);
            const float *peak = diffused_at(&atlas[0], 0, size, 0.05, 0.05);
            for (int c = 0; c < 3; ++c) {
                if (!(a[c] > 1e-3f * peak[c]))
                    continue;
                const double e = fabs((double)b[c] / a[c] - 1.0);
                sum += e;
                worst = fmax(worst, e);
                count++;
            }
        }
    printf("spot on a UV seam against one chart: mean relative error %.4f over %d values, worst %.3f\n", sum / count,
           count, worst);
    assert_true(count > 100);
    assert_true(sum / count < 0.05);
    assert_true(worst < 0.2);
    sam_image_destroy(&atlas[0]);
    sam_image_destroy(&atlas[1]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stretch_matches_sphere),
        cmocka_unit_test(test_spot_matches_profile),
        cmocka_unit_test(test_spot_across_a_seam),
        cmocka_unit_test(test_optimizations_match),
        cmocka_unit_test(test_albedo_map),
        cmocka_unit_test(test_vertex_colors),
        cmocka_unit_test(test_albedo_maps),
        cmocka_unit_test(test_overlapping_uvs_refused),
        cmocka_unit_test(test_uvs_past_the_square),
        cmocka_unit_test(test_tiled_albedo_repeats),
    };
    return cmocka_run_group_tests(tests, sam_test_gl_setup, sam_test_gl_teardown);
}
