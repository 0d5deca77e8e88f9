/* A picture of a profile (sam_profile_plot). */
#include <math.h>
#include <string.h>

#include "sam/sam_image.h"
#include "sam/sam_profile.h"

static float fit_eval(const sam_gaussian_fit *fit, float r, int c)
{
    double sum = 0;
    for (uint32_t i = 0; i < fit->count; ++i) {
        double v = fit->variance[i];
        sum += fit->weight[i][c] * exp(-(double)r * r / (2 * v)) / (2 * 3.14159265358979323846 * v);
    }
    return (float)sum;
}

static void put(sam_image *img, int x, int y, const float rgb[3])
{
    if (x < 0 || y < 0 || x >= (int)img->width || y >= (int)img->height)
        return;
    memcpy(img->pixels + 3 * ((size_t)y * img->width + (size_t)x), rgb, 3 * sizeof(float));
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
    float extent = sam_profile_radius(profile, 0.01f);
    int h = (int)height, w = 2 * h;
    st = sam_image_create(img, (uint32_t)w, (uint32_t)h, 3, err);
    if (st != SAM_OK)
        return st;

    /* Exposure: the brightest channel reaches 1 - e^-2 at a tenth of the extent. */
    float ref[3];
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

    /* Plot r^2 R_d(r) (energy per ln r) over a log radius axis, normalised
     * by its largest value over all channels. */
    const float background[3] = {0.02f, 0.02f, 0.025f}, grid[3] = {0.08f, 0.08f, 0.09f};
    for (int y = 0; y < h; ++y)
        for (int x = h; x < w; ++x)
            put(img, x, y, (x - h) % (h / 3) == 0 || y % (h / 8) == 0 ? grid : background);
    const float decades = 3.0f;
    double peak = 0;
    for (int x = 0; x < h; ++x) {
        float r = extent * powf(10.0f, decades * ((x + 0.5f) / h - 1.0f)), rd[3];
        sam_profile_eval(profile, r, rd);
        for (int k = 0; k < 3; ++k)
            peak = fmax(peak, (double)r * r * rd[k]);
    }
    int margin = h / 16;
    for (int curve = 0; curve < 2; ++curve) {
        for (int k = 0; k < 3; ++k) {
            float colour[3] = {0.15f, 0.15f, 0.15f};
            colour[k] = curve ? 0.55f : 1.0f;
            int prev = -1;
            for (int x = 0; x < h; ++x) {
                float r = extent * powf(10.0f, decades * ((x + 0.5f) / h - 1.0f)), rd[3];
                sam_profile_eval(profile, r, rd);
                float value = curve ? fit_eval(&fit, r, k) : rd[k];
                int y = h - 1 - margin - (int)lround(r * r * value / peak * (h - 2 * margin));
                if (curve && (x / 4) % 2) {
                    prev = -1; /* dotted */
                    continue;
                }
                int lo = prev < 0 ? y : (prev < y ? prev : y), hi = prev < 0 ? y : (prev > y ? prev : y);
                for (int yy = lo; yy <= hi; ++yy) {
                    put(img, h + x, yy, colour);
                    put(img, h + x, yy + 1, colour);
                }
                prev = y;
            }
        }
    }
    if (extent_mm)
        *extent_mm = extent;
    return SAM_OK;
}
