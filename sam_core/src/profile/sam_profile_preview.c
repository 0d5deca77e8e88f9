/*
 * The material previews of sam_profile_plot: a sphere and a wedge lit from
 * behind, seen from the front, so that only light that went through the
 * material reaches the eye.
 *
 * Sphere: the radiance leaving a visible point x is
 *     L(x) = int_{lit back} E(y) R_d(|x - y|) dA(y),   E(y) = cos theta(y),
 * the distance-based transport that SAM's ground truth integrates on a
 * mesh (straight-line distance, every lit point reaches every point), here
 * by a midpoint rule over the back hemisphere in (theta, phi), with R_d
 * from a table in r.
 * Wedge: each column is a slab of its thickness t, lit uniformly from
 * behind: L = G(t), sam_profile_slab_transmission's closed form.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_image.h"
#include "sam_profile_internal.h"

#define THETA_STEPS 32
#define PHI_STEPS 64
#define TABLE_SIZE 4096
#define GRID 160

static void put(sam_image *img, int x, int y, const float rgb[3])
{
    if (x < 0 || y < 0 || x >= (int)img->width || y >= (int)img->height)
        return;
    memcpy(img->pixels + img->channels * ((size_t)y * img->width + (size_t)x), rgb, 3 * sizeof(float));
}

/* 1 - e^{-k L}: keeps every channel's order and never clips. */
static void expose(const double L[3], double k, float out[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = (float)-expm1(-k * L[c]);
}

static int compare_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* L at the visible point over (sx, sy), moved onto the disc's edge when
 * outside it so that the grid can be read bilinearly up to the rim. */
static void sphere_point(double sx, double sy, double radius, const double (*y)[4], int points,
                         const float (*table)[3], double step, double L[3])
{
    const double s = sqrt(sx * sx + sy * sy), edge = 0.999 * radius;
    if (s > edge)
        sx *= edge / s, sy *= edge / s;
    const double sz = sqrt(fmax(radius * radius - sx * sx - sy * sy, 0));
    L[0] = L[1] = L[2] = 0;
    for (int k = 0; k < points; k++) {
        const double dx = sx - y[k][0], dy = sy - y[k][1], dz = sz - y[k][2];
        const double at = fmin(sqrt(dx * dx + dy * dy + dz * dz) / step, TABLE_SIZE);
        const int i = at < TABLE_SIZE ? (int)at : TABLE_SIZE - 1;
        const double f = at - i;
        for (int c = 0; c < 3; c++)
            L[c] += y[k][3] * ((1 - f) * table[i][c] + f * table[i + 1][c]);
    }
}

int sam_profile_draw_sphere(const sam_profile *profile, float diameter_mm, sam_image *img, int x0, int y0, int side)
{
    enum { POINTS = THETA_STEPS * PHI_STEPS };
    static const double pi = 3.14159265358979323846;
    const double radius = 0.5 * diameter_mm;
    /* Transport is smooth inside the disc: a grid of at most GRID^2
     * points, read bilinearly, keeps large pictures fast. */
    const int n = side < GRID ? side : GRID;
    float(*table)[3] = malloc((TABLE_SIZE + 1) * sizeof *table);
    double *light = malloc((size_t)n * n * 3 * sizeof *light), *order = malloc((size_t)n * n * sizeof *order);
    double(*y)[4] = malloc(POINTS * sizeof *y);
    if (!table || !light || !order || !y || side < 2) {
        free(table);
        free(light);
        free(order);
        free(y);
        return 0;
    }
    const double step = 2 * radius / TABLE_SIZE;
    for (int i = 0; i <= TABLE_SIZE; i++)
        sam_profile_eval(profile, (float)(i * step), table[i]);
    /* The lit back hemisphere's points, irradiance times area as weight. */
    const double dt = 0.5 * pi / THETA_STEPS, dp = 2 * pi / PHI_STEPS;
    for (int i = 0; i < THETA_STEPS; i++)
        for (int j = 0; j < PHI_STEPS; j++) {
            const double t = (i + 0.5) * dt, p = (j + 0.5) * dp;
            double *q = y[i * PHI_STEPS + j];
            q[0] = radius * sin(t) * cos(p);
            q[1] = radius * sin(t) * sin(p);
            q[2] = -radius * cos(t);
            q[3] = cos(t) * radius * radius * sin(t) * dt * dp;
        }
    size_t inside = 0;
    for (int gy = 0; gy < n; gy++)
        for (int gx = 0; gx < n; gx++) {
            const double sx = ((gx + 0.5) / n * 2 - 1) * radius, sy = (1 - (gy + 0.5) / n * 2) * radius;
            double *L = light + 3 * ((size_t)gy * n + gx);
            const float(*ct)[3] = table;
            const double(*cy)[4] = y;
            sphere_point(sx, sy, radius, cy, POINTS, ct, step, L);
            if (sx * sx + sy * sy <= radius * radius)
                order[inside++] = fmax(L[0], fmax(L[1], L[2]));
        }
    /* The rim, where lit and seen points meet, outshines the rest: expose
     * for the 90th percentile, so the centre, lit through the whole
     * diameter, still shows. */
    qsort(order, inside, sizeof *order, compare_double);
    const double level = inside ? order[(size_t)(0.9 * (double)(inside - 1))] : 0;
    const double k = level > 0 ? 2 / level : 1;
    for (int py = 0; py < side; py++)
        for (int px = 0; px < side; px++) {
            const double u = (px + 0.5) / side * 2 - 1, v = (py + 0.5) / side * 2 - 1;
            if (u * u + v * v > 1)
                continue;
            const double gx = fmin(fmax((px + 0.5) * n / side - 0.5, 0), n - 1.001);
            const double gy = fmin(fmax((py + 0.5) * n / side - 0.5, 0), n - 1.001);
            const int ix = (int)gx, iy = (int)gy;
            const double fx = gx - ix, fy = gy - iy;
            double L[3];
            for (int c = 0; c < 3; c++) {
                const double *a = light + 3 * ((size_t)iy * n + ix) + c, *b = a + 3 * (size_t)n;
                L[c] = (1 - fy) * ((1 - fx) * a[0] + fx * a[3]) + fy * ((1 - fx) * b[0] + fx * b[3]);
            }
            float rgb[3];
            expose(L, k, rgb);
            put(img, x0 + px, y0 + py, rgb);
        }
    free(y);
    free(table);
    free(light);
    free(order);
    return 1;
}

void sam_profile_draw_wedge(const sam_profile *profile, float thickness_mm, sam_image *img, int x0, int y0, int w,
                            int h)
{
    float total[3];
    sam_profile_total_reflectance(profile, total);
    const double k = 2 / fmax(fmax(total[0], total[1]), fmax(total[2], 1e-30f));
    for (int px = 0; px < w; px++) {
        float g[3], rgb[3];
        sam_profile_slab_transmission(profile, thickness_mm * (px + 0.5f) / (float)w, g);
        const double L[3] = {g[0], g[1], g[2]};
        expose(L, k, rgb);
        for (int py = 0; py < h; py++)
            put(img, x0 + px, y0 + py, rgb);
    }
}
