/*
 * sam_profile_artist: materials as artists and measurements give them,
 * turned into the sum of Gaussians every part of SAM evaluates.
 *
 * Christensen and Burley, "Approximate Reflectance Profiles for Efficient
 * Subsurface Scattering" (Pixar technical memo 15-04, 2015): the
 * normalised diffusion profile
 *     R(r) = A (e^{-r/d} + e^{-r/(3d)}) / (8 pi d r),
 * whose energy 2 pi int r R dr is exactly the surface albedo A, with the
 * shape d = l / s from a mean free path l and their fit for diffuse surface
 * transmission s(A) = 1.9 - A + 3.5 (A - 0.8)^2 (their Sec. 5), or d given
 * directly as a scatter radius (Unity HDRP's "scattering distance").
 *
 * Both it and a tabulated R_d(r) become the 8-Gaussian fit with shared
 * variances (sam_profile_fit_radial) that minimises int r^3 (R - F)^2 dr:
 * Burley's 1/r peak at r = 0 has no finite eq.-10 error, and this measure,
 * the energy per radius r R weighted by r, keeps the tail that carries
 * light through thick parts (the same fit under int r^2 missed the energy
 * within 7 d of skin-like red by 3.4% of its albedo; this one by 0.8%).
 * Its error is kept in the profile (fit_source_error) as what a user can
 * read: the largest difference, over r, between the energy landing within
 * r of the fit and of the source, as a fraction of the total.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sam/sam_profile.h"
#include "sam_profile_internal.h"

typedef struct burley {
    double albedo[3], d[3];
} burley;

static void burley_eval(const void *user, double r, double out[3])
{
    const burley *b = user;
    for (int c = 0; c < 3; c++) {
        const double d = b->d[c];
        if (!(b->albedo[c] > 0)) {
            out[c] = 0;
            continue;
        }
        /* (e^{-x} + e^{-x/3}) / x tends to 1/x at 0; clamp the peak where
         * the fit's grid starts far below any Gaussian. */
        const double x = fmax(r / d, 1e-9);
        out[c] = b->albedo[c] * (exp(-x) + exp(-x / 3)) / (8 * SAM_PROFILE_PI * d * d * x);
    }
}

#define ENERGY_NODES 8192

/* max_r |E_fit(r) - E_f(r)| / E_f(inf) per channel, E(r) = 2 pi int_0^r s R(s) ds:
 * the fit's in closed form, f's by the trapezoid rule in ln r on
 * [r_lo, r_hi] (with f's flat value below r_lo) and `total` past it. */
static void energy_error(sam_profile_radial_fn f, const void *user, const double total[3],
                         const sam_gaussian_fit *fit, double r_lo, double r_hi, float out[3])
{
    double prev[3], e[3], worst[3] = {0, 0, 0};
    f(user, r_lo, prev);
    for (int c = 0; c < 3; c++)
        e[c] = SAM_PROFILE_PI * r_lo * r_lo * prev[c];
    const double h = log(r_hi / r_lo) / ENERGY_NODES;
    for (int k = 0; k <= ENERGY_NODES + 1; k++) {
        const double r = k <= ENERGY_NODES ? r_lo * exp(k * h) : INFINITY;
        if (k > 0 && k <= ENERGY_NODES) {
            double now[3];
            f(user, r, now);
            /* int r R dr = int r^2 R d(ln r) */
            const double r0 = r_lo * exp((k - 1) * h);
            for (int c = 0; c < 3; c++) {
                e[c] += SAM_PROFILE_PI * h * (r0 * r0 * prev[c] + r * r * now[c]);
                prev[c] = now[c];
            }
        }
        for (int c = 0; c < 3; c++) {
            double fit_e = 0;
            for (uint32_t i = 0; i < fit->count; i++)
                fit_e += fit->weight[i][c] * (isinf(r) ? 1.0 : -expm1(-r * r / (2 * fit->variance[i])));
            const double src = isinf(r) ? total[c] : e[c];
            if (total[c] > 0)
                worst[c] = fmax(worst[c], fabs(fit_e - src) / total[c]);
        }
    }
    for (int c = 0; c < 3; c++)
        out[c] = (float)worst[c];
}

static sam_status to_profile(const sam_gaussian_fit *fit, const char *name, sam_profile *out, sam_error *err)
{
    float variance[SAM_PROFILE_FIT_GAUSSIANS];
    float weight[SAM_PROFILE_FIT_GAUSSIANS][3];
    for (uint32_t i = 0; i < fit->count; i++) {
        variance[i] = fit->variance[i];
        for (int c = 0; c < 3; c++)
            weight[i][c] = fmaxf(fit->weight[i][c], 0.0f);
    }
    const float(*w)[3] = weight;
    sam_status st = sam_profile_gaussian_sum(fit->count, variance, w, out, err);
    if (st == SAM_OK)
        snprintf(out->name, sizeof out->name, "%s", name);
    return st;
}

double sam_profile_burley_shape(float albedo, float mean_free_path_mm)
{
    const double a = albedo, s = 1.9 - a + 3.5 * (a - 0.8) * (a - 0.8);
    return mean_free_path_mm / s;
}

sam_status sam_profile_burley(const float albedo[3], const float distance_mm[3], sam_burley_distance distance,
                              sam_profile *out, sam_error *err)
{
    if (!albedo || !distance_mm || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_burley: NULL argument");
    if (distance != SAM_BURLEY_MEAN_FREE_PATH && distance != SAM_BURLEY_SCATTER_RADIUS)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_burley: distance kind %d", (int)distance);
    const char *what = distance == SAM_BURLEY_MEAN_FREE_PATH ? "mean_free_path" : "scatter_radius";
    burley b;
    double total[3], lo = INFINITY, hi = 0;
    for (int c = 0; c < 3; c++) {
        const char *why = sam_profile_check_albedo(albedo[c]);
        if (why)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "albedo[%d] %g %s", c, (double)albedo[c], why);
        why = sam_profile_check_variance(distance_mm[c]);
        if (why)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s[%d] %g %s", what, c, (double)distance_mm[c], why);
        b.albedo[c] = total[c] = albedo[c];
        b.d[c] = distance == SAM_BURLEY_MEAN_FREE_PATH ? sam_profile_burley_shape(albedo[c], distance_mm[c])
                                                       : distance_mm[c];
        if (albedo[c] > 0) {
            /* The energy r R is spread from about d / 100 to 15 d. */
            lo = fmin(lo, 1e-4 * b.d[c] * b.d[c]);
            hi = fmax(hi, 36 * b.d[c] * b.d[c]);
        }
    }
    if (!(hi > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "albedo (0, 0, 0): the material reflects no light");
    sam_gaussian_fit fit;
    const double r_lo = 1e-4 * sqrt(lo), r_hi = 50 * sqrt(hi / 36);
    sam_status st = sam_profile_fit_radial(burley_eval, &b, total, 3, lo, hi, r_lo, r_hi, "burley", &fit, err);
    if (st != SAM_OK || (st = to_profile(&fit, "burley", out, err)) != SAM_OK)
        return st;
    energy_error(burley_eval, &b, total, &fit, r_lo, r_hi, out->fit_source_error);
    return SAM_OK;
}

/* A table read as R exponential in r between its points (as profiles
 * fall; linear where a point is 0), R(r_0) below the first and 0 past the
 * last. */
typedef struct table {
    uint32_t count;
    const float *r;
    const float (*rd)[3];
} table;

static double piece(double r0, double r1, double y0, double y1, double r)
{
    const double f = (r - r0) / (r1 - r0);
    return y0 > 0 && y1 > 0 ? y0 * pow(y1 / y0, f) : y0 + f * (y1 - y0);
}

static void table_eval(const void *user, double r, double out[3])
{
    const table *t = user;
    uint32_t hi = 0;
    while (hi < t->count && t->r[hi] < r)
        hi++;
    for (int c = 0; c < 3; c++)
        out[c] = hi == 0 ? t->rd[0][c]
                 : hi == t->count
                     ? 0
                     : piece(t->r[hi - 1], t->r[hi], t->rd[hi - 1][c], t->rd[hi][c], r);
}

/* int_{r0}^{r1} r R dr of one piece, exact: for R = y0 e^{b (r - r0)},
 * int r e^{b (r - r0)} dr = e^{b (r - r0)} (r / b - 1 / b^2). */
static double piece_moment(double r0, double r1, double y0, double y1)
{
    if (y0 > 0 && y1 > 0 && y0 != y1) {
        const double b = log(y1 / y0) / (r1 - r0);
        return y0 * ((y1 / y0) * (r1 / b - 1 / (b * b)) - (r0 / b - 1 / (b * b)));
    }
    const double slope = (y1 - y0) / (r1 - r0), a = y0 - slope * r0;
    return a * 0.5 * (r1 * r1 - r0 * r0) + slope * (r1 * r1 * r1 - r0 * r0 * r0) / 3;
}

/* 2 pi int r R dr of the table's interpolant: the disc below r_0 plus the
 * pieces. */
static void table_total(const table *t, double total[3])
{
    for (int c = 0; c < 3; c++) {
        double sum = 0.5 * (double)t->r[0] * t->r[0] * t->rd[0][c];
        for (uint32_t i = 0; i + 1 < t->count; i++)
            sum += piece_moment(t->r[i], t->r[i + 1], t->rd[i][c], t->rd[i + 1][c]);
        total[c] = 2 * SAM_PROFILE_PI * sum;
    }
}

sam_status sam_profile_table(uint32_t count, const float *radius_mm, const float (*rd)[3], sam_profile *out,
                             sam_error *err)
{
    if (!radius_mm || !rd || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_table: NULL argument");
    if (count < 2 || count > SAM_PROFILE_MAX_TABLE)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "a table of %u points, expected 2..%u", count,
                        SAM_PROFILE_MAX_TABLE);
    for (uint32_t i = 0; i < count; i++) {
        const char *why = sam_profile_check_weight(radius_mm[i]);
        if (why)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "radius_mm[%u] %g %s", i, (double)radius_mm[i], why);
        if (i > 0 && !(radius_mm[i] > radius_mm[i - 1]))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "radius_mm[%u] %g does not exceed radius_mm[%u] %g: radii must ascend", i,
                            (double)radius_mm[i], i - 1, (double)radius_mm[i - 1]);
        for (int c = 0; c < 3; c++)
            if ((why = sam_profile_check_weight(rd[i][c])) != NULL)
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "rd[%u][%d] %g %s", i, c, (double)rd[i][c], why);
    }
    table t = {count, radius_mm, rd};
    double total[3];
    table_total(&t, total);
    if (!(total[0] + total[1] + total[2] > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "the table reflects no light (every rd is 0)");
    /* Gaussians from a tenth of the first step to the table's end. */
    const double step = radius_mm[0] > 0 ? radius_mm[0] : radius_mm[1];
    const double lo = 0.01 * step * step, hi = 0.25 * (double)radius_mm[count - 1] * radius_mm[count - 1];
    const double r_lo = 1e-3 * step, r_hi = radius_mm[count - 1];
    sam_gaussian_fit fit;
    sam_status st = sam_profile_fit_radial(table_eval, &t, total, 3, lo, hi, r_lo, r_hi, "table", &fit, err);
    if (st != SAM_OK || (st = to_profile(&fit, "table", out, err)) != SAM_OK)
        return st;
    energy_error(table_eval, &t, total, &fit, r_lo, r_hi, out->fit_source_error);
    return SAM_OK;
}
