/* A picture of a profile (sam_profile_plot): a point of light, the curve
 * with labelled axes, and a back-lit sphere and wedge (sam_profile_preview.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sam/sam_image.h"
#include "sam_profile_internal.h"

static const float white[3] = {0.9f, 0.9f, 0.9f}, grey[3] = {0.45f, 0.45f, 0.47f};

static float fit_eval(const sam_gaussian_fit *fit, float r, int c)
{
    double sum = 0;
    for (uint32_t i = 0; i < fit->count; ++i)
        sum += fit->weight[i][c] * sam_profile_gaussian(fit->variance[i], r);
    return (float)sum;
}

static void put(sam_image *img, int x, int y, const float rgb[3])
{
    if (x < 0 || y < 0 || x >= (int)img->width || y >= (int)img->height)
        return;
    memcpy(img->pixels + 3 * ((size_t)y * img->width + (size_t)x), rgb, 3 * sizeof(float));
}

static void fill(sam_image *img, int x0, int y0, int x1, int y1, const float rgb[3])
{
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            put(img, x, y, rgb);
}

/* A length in mm as a short label: "0", "0.05", "2.5", "40"; two
 * significant digits below 0.01 mm ("0.0012"), where fixed decimals gave a
 * tiny profile's wedge the ticks "0.000 0.001 0.001". */
static void mm_label(char *buf, size_t n, double mm)
{
    if (mm <= 0)
        snprintf(buf, n, "0");
    else if (mm < 0.01)
        snprintf(buf, n, "%.2g", mm);
    else
        snprintf(buf, n, "%.*f", mm >= 10 ? 0 : mm >= 1 ? 1 : mm >= 0.1 ? 2 : 3, mm);
}

/* Text at (x, y) when it fits in max_w pixels; small pictures go without. */
static void text(sam_image *img, int x, int y, int max_w, int ts, const float rgb[3], const char *t)
{
    if (sam_image_text_width(t, ts) <= max_w)
        sam_image_draw_text(img, x, y, ts, rgb, t);
}

/* A label centred on x, kept inside [lo, hi). */
static void centred_label(sam_image *img, int x, int lo, int hi, int y, int ts, const char *label)
{
    const int w = sam_image_text_width(label, ts);
    int left = x - w / 2;
    left = left + w > hi ? hi - w : left;
    if (w <= hi - lo)
        sam_image_draw_text(img, left < lo ? lo : left, y, ts, grey, label);
}

/* Left panel: a point of light entering the material, seen from the lit
 * side, out to +-extent. */
static void draw_point(const sam_profile *profile, float extent, sam_image *img, int h)
{
    float ref[3];
    /* Exposure: the brightest channel reaches 1 - e^-2 at a tenth of the extent. */
    sam_profile_eval(profile, 0.1f * extent, ref);
    float exposure = 2.0f / fmaxf(fmaxf(ref[0], ref[1]), fmaxf(ref[2], 1e-30f));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < h; ++x) {
            float dx = (x + 0.5f - 0.5f * h) / (0.5f * h), dy = (y + 0.5f - 0.5f * h) / (0.5f * h);
            float r = sqrtf(dx * dx + dy * dy) * extent, rd[3], c[3];
            sam_profile_eval(profile, r, rd);
            for (int k = 0; k < 3; ++k)
                c[k] = 1.0f - expf(-exposure * rd[k]);
            put(img, x, y, c);
        }
}

/* Right panel: r^2 R_d(r) (energy per ln r) over three decades of r up to
 * the extent, normalised by its largest value, with decade ticks in mm. */
static void draw_curve(const sam_profile *profile, const sam_gaussian_fit *fit, float extent, sam_image *img,
                       int h, int ts)
{
    const int x0 = h + 6 * ts, x1 = 2 * h - 6 * ts, y0 = 30 * ts, y1 = h - 30 * ts, pw = x1 - x0;
    const float background[3] = {0.02f, 0.02f, 0.025f}, grid[3] = {0.1f, 0.1f, 0.11f};
    fill(img, h, 0, 2 * h, h, background);
    const double lo = log10(extent) - 3, hi = log10(extent);
    for (int d = (int)ceil(lo); d <= (int)floor(hi); ++d) {
        const int x = x0 + (int)lround((d - lo) / (hi - lo) * (pw - 1));
        fill(img, x, y0, x + 1, y1, grid);
        char label[32];
        snprintf(label, sizeof label, "%g", pow(10, d));
        centred_label(img, x, x0, x1, y1 + 4 * ts, ts, label);
    }
    for (int q = 0; q <= 4; ++q)
        fill(img, x0, y0 + q * (y1 - y0 - 1) / 4, x1, y0 + q * (y1 - y0 - 1) / 4 + 1, grid);
    text(img, x0, y1 + 16 * ts, pw, ts, white, "radius r, mm (log scale)");
    text(img, x0, 4 * ts, pw, ts, white, "energy per log radius r^2 R_d(r), by channel");
    text(img, x0, 16 * ts, pw, ts, grey, "solid: profile, dotted: 8-Gaussian fit");
    double peak = 0;
    for (int x = 0; x < pw; ++x) {
        float r = (float)pow(10, lo + (hi - lo) * (x + 0.5) / pw), rd[3];
        sam_profile_eval(profile, r, rd);
        for (int k = 0; k < 3; ++k)
            peak = fmax(peak, (double)r * r * rd[k]);
    }
    for (int curve = 0; curve < 2; ++curve)
        for (int k = 0; k < 3; ++k) {
            float colour[3] = {0.15f, 0.15f, 0.15f};
            colour[k] = curve ? 0.55f : 1.0f;
            int prev = -1;
            for (int x = 0; x < pw; ++x) {
                float r = (float)pow(10, lo + (hi - lo) * (x + 0.5) / pw), rd[3];
                sam_profile_eval(profile, r, rd);
                float value = curve ? fit_eval(fit, r, k) : rd[k];
                int y = y1 - 1 - (int)lround(r * r * value / peak * (y1 - y0 - 1));
                if (curve && (x / (4 * ts)) % 2) {
                    prev = -1; /* dotted */
                    continue;
                }
                int a = prev < 0 ? y : (prev < y ? prev : y), b = prev < 0 ? y : (prev > y ? prev : y);
                fill(img, x0 + x, a, x0 + x + 1, b + ts, colour);
                prev = y;
            }
        }
}

sam_status sam_profile_plot(const sam_profile *profile, uint32_t height, sam_image *img, float *extent_mm,
                            sam_error *err)
{
    memset(img, 0, sizeof *img);
    sam_gaussian_fit fit;
    if (height < 64 || height > 4096)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "profile plot: height %u outside 64..4096", height);
    sam_status st = sam_profile_fit_gaussians(profile, &fit, err);
    if (st != SAM_OK)
        return st;
    /* Show the radius holding 99% of the energy: the visible glow. */
    const float extent = sam_profile_radius(profile, 0.01f);
    const int h = (int)height, hb = h / 2, ts = h >= 256 ? h / 256 : 1;
    st = sam_image_create(img, 2 * (uint32_t)h, (uint32_t)(h + hb), 3, err);
    if (st != SAM_OK)
        return st;
    char line[160], a[32], b[32];
    draw_point(profile, extent, img, h);
    snprintf(line, sizeof line, "%s", profile->name);
    text(img, 4 * ts, 4 * ts, h - 8 * ts, ts, white, line);
    float total[3];
    sam_profile_total_reflectance(profile, total);
    snprintf(line, sizeof line, "albedo %.3f %.3f %.3f", total[0], total[1], total[2]);
    text(img, 4 * ts, 16 * ts, h - 8 * ts, ts, white, line);
    const float *source = profile->fit_source_error;
    if (source[0] > 0 || source[1] > 0 || source[2] > 0) {
        snprintf(line, sizeof line, "fitted to its source: %.1f%% %.1f%% %.1f%%\nof the energy at another radius",
                 100 * source[0], 100 * source[1], 100 * source[2]);
        text(img, 4 * ts, 28 * ts, h - 8 * ts, ts, grey, line);
    }
    mm_label(a, sizeof a, extent);
    snprintf(line, sizeof line, "a point of light, +-%s mm", a);
    text(img, 4 * ts, h - 14 * ts, h - 8 * ts, ts, white, line);
    draw_curve(profile, &fit, extent, img, h, ts);

    /* Below: the back-lit sphere (diameter half the extent: thin enough
     * to glow through) and the wedge (thickness 0 to the extent). */
    const float diameter = 0.5f * extent;
    const int label = 16 * ts, side = hb - label - 4 * ts;
    if (side >= 2 && !sam_profile_draw_sphere(profile, diameter, img, (h - side) / 2, h + label, side)) {
        sam_image_destroy(img);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "profile plot: out of memory for the sphere preview");
    }
    mm_label(a, sizeof a, diameter);
    snprintf(line, sizeof line, "a sphere %s mm across, lit from behind", a);
    text(img, 4 * ts, h + 4 * ts, h - 8 * ts, ts, white, line);
    const int wx0 = h + 6 * ts, wx1 = 2 * h - 6 * ts, wy1 = h + hb - 16 * ts;
    sam_profile_draw_wedge(profile, extent, img, wx0, h + label, wx1 - wx0, wy1 - h - label);
    mm_label(a, sizeof a, extent);
    snprintf(line, sizeof line, "a wedge lit from behind, 0 to %s mm thick", a);
    text(img, wx0, h + 4 * ts, wx1 - wx0, ts, white, line);
    for (int q = 0; q <= 4; ++q) {
        const int x = wx0 + q * (wx1 - wx0 - 1) / 4;
        fill(img, x, wy1, x + 1, wy1 + 3 * ts, grey);
        mm_label(b, sizeof b, extent * q / 4.0);
        centred_label(img, x, wx0, wx1, wy1 + 4 * ts, ts, b);
    }
    if (extent_mm)
        *extent_mm = extent;
    return SAM_OK;
}
