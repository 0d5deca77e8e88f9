/*
 * sam_profile_image: draws a material's diffusion profile to a PNG.
 * Left half: a point of light entering the material, seen from the lit side
 * (R_d(r), tonemapped). Right half: the energy per logarithmic radius,
 * 2 pi r^2 R_d(r) over ln r (so the area under each curve is the channel's
 * total reflectance), solid, with the 8-Gaussian texture-space fit, dotted.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_image.h"
#include "sam/sam_profile.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_profile_image MATERIAL -o OUT.png [--size N]\n"
            "\n"
            "Draws a diffusion profile: a point of light seen through the material (left) and\n"
            "the energy per log radius 2 pi r^2 R_d(r) per channel over r on a log axis from\n"
            "1/1000 of the radius holding 99%% of the energy to that radius: the profile solid, its\n"
            "8-Gaussian fit dotted (right).\n"
            "  MATERIAL   a preset (skin, marble, apple, chicken1, chicken2, cream, ketchup,\n"
            "             potato, skimmilk, skin1, skin2, wholemilk) or a profile file (.json, .txt)\n"
            "  -o OUT.png output image (written atomically)\n"
            "  --size N   height in pixels, 64..4096 (default 512); the width is 2N\n");
}

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

int main(int argc, char **argv)
{
    const char *material = NULL, *out = NULL;
    long size = 512;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "-o") && i + 1 < argc) {
            out = argv[++i];
        } else if (!strcmp(argv[i], "--size") && i + 1 < argc) {
            char *end;
            size = strtol(argv[++i], &end, 10);
            if (*end || size < 64 || size > 4096) {
                fprintf(stderr, "sam_profile_image: --size must be an integer in 64..4096, got \"%s\"\n",
                        argv[i]);
                return 2;
            }
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "sam_profile_image: unknown or incomplete option \"%s\" (see --help)\n", argv[i]);
            return 2;
        } else if (!material) {
            material = argv[i];
        } else {
            fprintf(stderr, "sam_profile_image: unexpected argument \"%s\" (see --help)\n", argv[i]);
            return 2;
        }
    }
    if (!material || !out) {
        usage(stderr);
        return 2;
    }
    sam_profile profile;
    sam_gaussian_fit fit;
    sam_error err;
    if (sam_profile_from_spec(material, &profile, &err) != SAM_OK ||
        sam_profile_fit_gaussians(&profile, &fit, &err) != SAM_OK) {
        fprintf(stderr, "sam_profile_image: %s\n", err.message);
        return 1;
    }
    /* Show the radius holding 99% of the energy: the visible glow. */
    float extent = sam_profile_radius(&profile, 0.01f);
    int h = (int)size, w = 2 * h;
    sam_image img;
    if (sam_image_create(&img, (uint32_t)w, (uint32_t)h, 3, &err) != SAM_OK) {
        fprintf(stderr, "sam_profile_image: %s\n", err.message);
        return 1;
    }

    /* Exposure: the brightest channel reaches 1 - e^-2 at a tenth of the extent. */
    float ref[3];
    sam_profile_eval(&profile, 0.1f * extent, ref);
    float exposure = 2.0f / fmaxf(fmaxf(ref[0], ref[1]), fmaxf(ref[2], 1e-30f));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < h; ++x) {
            float dx = (x + 0.5f - 0.5f * h) / (0.5f * h), dy = (y + 0.5f - 0.5f * h) / (0.5f * h);
            float r = sqrtf(dx * dx + dy * dy) * extent, rd[3], c[3];
            sam_profile_eval(&profile, r, rd);
            for (int k = 0; k < 3; ++k)
                c[k] = 1.0f - expf(-exposure * rd[k]);
            put(&img, x, y, c);
        }

    /* Plot r^2 R_d(r) (energy per ln r) over a log radius axis, normalised
     * by its largest value over all channels. */
    const float background[3] = {0.02f, 0.02f, 0.025f}, grid[3] = {0.08f, 0.08f, 0.09f};
    for (int y = 0; y < h; ++y)
        for (int x = h; x < w; ++x)
            put(&img, x, y, (x - h) % (h / 3) == 0 || y % (h / 8) == 0 ? grid : background);
    const float decades = 3.0f;
    double peak = 0;
    for (int x = 0; x < h; ++x) {
        float r = extent * powf(10.0f, decades * ((x + 0.5f) / h - 1.0f)), rd[3];
        sam_profile_eval(&profile, r, rd);
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
                sam_profile_eval(&profile, r, rd);
                float value = curve ? fit_eval(&fit, r, k) : rd[k];
                int y = h - 1 - margin - (int)lround(r * r * value / peak * (h - 2 * margin));
                if (curve && (x / 4) % 2) {
                    prev = -1; /* dotted */
                    continue;
                }
                int lo = prev < 0 ? y : (prev < y ? prev : y), hi = prev < 0 ? y : (prev > y ? prev : y);
                for (int yy = lo; yy <= hi; ++yy) {
                    put(&img, h + x, yy, colour);
                    put(&img, h + x, yy + 1, colour);
                }
                prev = y;
            }
        }
    }
    sam_status st = sam_image_write_png(out, &img, SAM_PNG_LINEAR, &err);
    sam_image_destroy(&img);
    if (st != SAM_OK) {
        fprintf(stderr, "sam_profile_image: %s\n", err.message);
        return 1;
    }
    float total[3];
    sam_profile_total_reflectance(&profile, total);
    fprintf(stderr,
            "sam_profile_image: %s: total diffuse reflectance (%.3f, %.3f, %.3f), 99%% of the energy "
            "within %.2f mm; wrote %s\n",
            profile.name, total[0], total[1], total[2], extent, out);
    return 0;
}
