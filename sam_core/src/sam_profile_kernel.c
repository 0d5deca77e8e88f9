/*
 * sam_profile_kernel: the separable screen-space kernel of Jimenez et al.
 * (eq. 1), fitted to the profile's own 1D marginals.
 *
 * A two-pass blur applies s(x) s(y); along one pass the right 1D kernel is
 * the marginal m(x) = int R(sqrt(x^2 + y^2)) dy of the radial profile. The
 * kernel is built from masses of that marginal over strips |x| <= X:
 *   M(X) = 2 pi int_0^X r R dr + 4 int_X^inf r R(r) asin(X/r) dr,
 * (a circle of radius r > X lies a fraction (2/pi) asin(X/r) inside the
 * strip). The first term is closed form (sam_profile_inner_d); the second
 * is a Simpson rule in t with r = X cosh t, which removes the square-root
 * kink at r = X and spaces nodes logarithmically for large r.
 *
 * Layout: taps at x_k = W tau_k |tau_k|, tau_k uniform in [-1, 1] (quadratic
 * spacing, dense near the centre, as in the paper's shader, whose kernel
 * table spans -3..3 and is scaled by the width). Each tap stands for the cell
 * between the midpoints to its neighbours (the outermost cells end at +-W),
 * and its weight is the mass of the kernel's density over that cell rather
 * than a point sample, so a profile narrower than the tap spacing still
 * keeps its energy in the right cells.
 *
 * Eq. 1 in millimetres: channel c uses p(x / (f_c + 0.001)), p = the 1D
 * marginal of the base channel (red, or the first non-zero one), normalised
 * over +-W, mixed with a delta: w = t_c Q_c + (1 - t_c) delta. So every
 * channel sums to 1 and the total reflectance is applied separately.
 *
 * Fit: W is where every channel's 1D marginal has at most
 * SAM_PROFILE_KERNEL_TAIL of its energy left outside +-W. (Eq. 2 cannot
 * choose W: it ignores how coarsely a wider kernel samples the centre, so it
 * always prefers the widest.) For each channel, eq. 3 (the sum of squared
 * differences between the kernel's cell masses and the channel's own
 * normalised marginal masses over a reference 33-tap layout) is minimised
 * over f_c by a log grid and golden-section refinement; for fixed f_c the
 * best strength t_c is a 1D least-squares solution, clamped to [0, 1]. The
 * base channel reproduces itself (f = 0.999, t = 1).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_profile.h"
#include "sam_profile_internal.h"

#define STRIP_NODES 192     /* Simpson intervals in t for one strip mass */
#define TABLE_SIZE 256      /* base-channel strip masses, log-spaced */
#define FIT_TAPS 33         /* reference layout of the fit */
#define FALLOFF_MIN 0.005
#define FALLOFF_MAX 20.0
#define FALLOFF_GRID 64

/* M(X) per channel (all three, or only `channel` when it is 0..2). */
static void strip_mass(const sam_profile *p, double X, double r_hi, int channel, double out[3])
{
    double inner[3];
    sam_profile_inner_d(p, X, inner);
    for (int c = 0; c < 3; c++)
        out[c] = inner[c];
    if (!(X > 0) || X >= r_hi)
        return;
    double t_max = acosh(r_hi / X), h = t_max / STRIP_NODES;
    double sum[3] = {0, 0, 0};
    for (int k = 1; k <= STRIP_NODES; k++) { /* the t = 0 node is zero */
        double t = k * h, ch = cosh(t), sh = sinh(t);
        double f = ch * sh * asin(1 / ch) * ((k == STRIP_NODES) ? 1 : (k % 2 ? 4 : 2));
        if (channel >= 0) {
            sum[channel] += f * sam_profile_eval_channel_d(p, channel, X * ch);
        } else {
            double R[3];
            sam_profile_eval_d(p, X * ch, R);
            for (int c = 0; c < 3; c++)
                sum[c] += f * R[c];
        }
    }
    for (int c = 0; c < 3; c++)
        out[c] += 4 * X * X * h / 3 * sum[c];
}

void sam_profile_marginal_mass(const sam_profile *profile, float x_mm, float out_rgb[3])
{
    double m[3];
    strip_mass(profile, fabs((double)x_mm), sam_profile_scale_max(profile), -1, m);
    for (int c = 0; c < 3; c++)
        out_rgb[c] = (float)m[c];
}

/* Half of a symmetric layout: tap j >= 0 at offset[j] covers
 * [bound[j], bound[j+1]] (and its mirror); the centre covers
 * [-bound[1], bound[1]]; bound[half + 1] = W. */
typedef struct half_layout {
    int half;
    double offset[SAM_KERNEL_MAX_TAPS / 2 + 1];
    double bound[SAM_KERNEL_MAX_TAPS / 2 + 2];
} half_layout;

static void make_layout(uint32_t taps, double width, half_layout *l)
{
    l->half = (int)(taps / 2);
    for (int j = 0; j <= l->half; j++) {
        double tau = (double)j / l->half;
        l->offset[j] = width * tau * tau;
    }
    l->bound[0] = 0;
    for (int j = 1; j <= l->half; j++)
        l->bound[j] = 0.5 * (l->offset[j - 1] + l->offset[j]);
    l->bound[l->half + 1] = width;
}

/* Normalised cell masses from strip masses at the bounds (mass[j] for one
 * side; the sum over the full kernel is 1). */
static void cell_masses(const half_layout *l, const double strip[], double mass[])
{
    double total = strip[l->half + 1];
    mass[0] = strip[1] / total;
    for (int j = 1; j <= l->half; j++)
        mass[j] = fmax(0.5 * (strip[j + 1] - strip[j]), 0) / total;
}

/* The channel's own normalised cell masses on layout l. */
static void target_masses(const sam_profile *p, const half_layout *l, double r_hi,
                          double mass[3][SAM_KERNEL_MAX_TAPS / 2 + 1])
{
    double strip[3][SAM_KERNEL_MAX_TAPS / 2 + 2];
    for (int j = 1; j <= l->half + 1; j++) {
        double m[3];
        strip_mass(p, l->bound[j], r_hi, -1, m);
        for (int c = 0; c < 3; c++)
            strip[c][j] = m[c];
    }
    for (int c = 0; c < 3; c++)
        if (strip[c][l->half + 1] > 0)
            cell_masses(l, strip[c], mass[c]);
        else
            memset(mass[c], 0, sizeof mass[c]);
}

/* The base channel's M(X) / M(inf) on a log grid, for the many scaled
 * lookups of the fit. */
typedef struct mass_table {
    double u0, du, x0;
    double v[TABLE_SIZE];
} mass_table;

static double table_lookup(const mass_table *t, double X)
{
    if (!(X > 0))
        return 0;
    double u = (log(X) - t->u0) / t->du;
    if (u <= 0)
        return t->v[0] * X / t->x0; /* the marginal is flat near 0 */
    if (u >= TABLE_SIZE - 1)
        return t->v[TABLE_SIZE - 1];
    int i = (int)u;
    double f = u - i;
    double p0 = t->v[i > 0 ? i - 1 : 0], p1 = t->v[i], p2 = t->v[i + 1];
    double p3 = t->v[i + 2 < TABLE_SIZE ? i + 2 : TABLE_SIZE - 1];
    /* Catmull-Rom in u = ln X */
    return p1 + 0.5 * f *
                    (p2 - p0 + f * (2 * p0 - 5 * p1 + 4 * p2 - p3 + f * (3 * (p1 - p2) + p3 - p0)));
}

/* Model cell masses of p(x / s), normalised over +-W. */
static void model_masses(const mass_table *t, const half_layout *l, double s, double mass[])
{
    double strip[SAM_KERNEL_MAX_TAPS / 2 + 2];
    for (int j = 1; j <= l->half + 1; j++)
        strip[j] = table_lookup(t, l->bound[j] / s);
    cell_masses(l, strip, mass);
}

/* Eq. 3 for channel scale s with the best strength (returned in *t_out). */
static double fit_error_at(const mass_table *table, const half_layout *l, const double target[],
                           double s, double *t_out)
{
    double q[SAM_KERNEL_MAX_TAPS / 2 + 1], ed = 0, dd = 0;
    model_masses(table, l, s, q);
    for (int j = 0; j <= l->half; j++) {
        double m = j ? 2 : 1, delta = j ? 0 : 1;
        ed += m * (target[j] - delta) * (q[j] - delta);
        dd += m * (q[j] - delta) * (q[j] - delta);
    }
    double t = dd > 0 ? ed / dd : 1;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    double e = 0;
    for (int j = 0; j <= l->half; j++) {
        double m = j ? 2 : 1, delta = j ? 0 : 1;
        double diff = target[j] - (t * q[j] + (1 - t) * delta);
        e += m * diff * diff;
    }
    *t_out = t;
    return e;
}

static void fit_channel(const mass_table *table, const half_layout *l, const double target[],
                        double *falloff, double *strength)
{
    double lo = log(FALLOFF_MIN + 0.001), hi = log(FALLOFF_MAX + 0.001);
    double step = (hi - lo) / (FALLOFF_GRID - 1), best_e = INFINITY, best_u = lo, t;
    for (int i = 0; i < FALLOFF_GRID; i++) {
        double u = lo + i * step, e = fit_error_at(table, l, target, exp(u), &t);
        if (e < best_e) {
            best_e = e;
            best_u = u;
        }
    }
    double a = fmax(lo, best_u - step), b = fmin(hi, best_u + step);
    const double g = 0.5 * (sqrt(5.0) - 1);
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    double e1 = fit_error_at(table, l, target, exp(x1), &t);
    double e2 = fit_error_at(table, l, target, exp(x2), &t);
    for (int i = 0; i < 48; i++) {
        if (e1 < e2) {
            b = x2;
            x2 = x1;
            e2 = e1;
            x1 = b - g * (b - a);
            e1 = fit_error_at(table, l, target, exp(x1), &t);
        } else {
            a = x1;
            x1 = x2;
            e1 = e2;
            x2 = a + g * (b - a);
            e2 = fit_error_at(table, l, target, exp(x2), &t);
        }
    }
    double u = e1 < e2 ? x1 : x2;
    if (fmin(e1, e2) > best_e)
        u = best_u;
    fit_error_at(table, l, target, exp(u), strength);
    *falloff = exp(u) - 0.001;
}

/* Smallest W at which every non-zero channel keeps at least
 * 1 - SAM_PROFILE_KERNEL_TAIL of its energy inside the strip |x| <= W. */
static double kernel_width(const sam_profile *p, const double total[3], double r_hi)
{
    double lo = 0, hi = sam_profile_radius_d(p, SAM_PROFILE_KERNEL_TAIL);
    for (int i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi), m[3];
        int inside = 1;
        strip_mass(p, mid, r_hi, -1, m);
        for (int c = 0; c < 3; c++)
            if (total[c] > 0 && total[c] - m[c] > SAM_PROFILE_KERNEL_TAIL * total[c])
                inside = 0;
        if (inside)
            hi = mid;
        else
            lo = mid;
    }
    return hi;
}

static int validate_taps(uint32_t taps)
{
    return taps >= 9 && taps <= SAM_KERNEL_MAX_TAPS && taps % 2 == 1;
}

sam_status sam_profile_separable_kernel(const sam_profile *profile, uint32_t taps,
                                        sam_separable_kernel *kernel, sam_error *err)
{
    if (!profile || !kernel)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "sam_profile_separable_kernel: NULL argument");
    if (!validate_taps(taps))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "separable kernel: %u taps, expected an odd count in 9..%d", taps,
                        SAM_KERNEL_MAX_TAPS);
    double total[3];
    sam_profile_total_d(profile, total);
    int base = total[0] > 0 ? 0 : (total[1] > 0 ? 1 : 2);
    if (!(total[base] > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "separable kernel: profile '%.64s' reflects nothing", profile->name);

    double r_hi = sam_profile_scale_max(profile);
    double W = kernel_width(profile, total, r_hi);
    half_layout ref;
    make_layout(FIT_TAPS, W, &ref);
    double target[3][SAM_KERNEL_MAX_TAPS / 2 + 1];
    target_masses(profile, &ref, r_hi, target);

    mass_table table;
    double x_lo = ref.bound[1] / (FALLOFF_MAX + 0.001) / 2;
    double x_hi = fmax(r_hi, W / (FALLOFF_MIN + 0.001));
    table.x0 = x_lo;
    table.u0 = log(x_lo);
    table.du = (log(x_hi) - table.u0) / (TABLE_SIZE - 1);
    for (int i = 0; i < TABLE_SIZE; i++) {
        double m[3];
        strip_mass(profile, exp(table.u0 + i * table.du), r_hi, base, m);
        table.v[i] = m[base] / total[base];
    }

    memset(kernel, 0, sizeof *kernel);
    kernel->taps = taps;
    kernel->width_mm = (float)W;
    half_layout l;
    make_layout(taps, W, &l);
    int h = l.half;
    for (int j = 0; j <= h; j++) {
        kernel->offset_mm[h + j] = (float)l.offset[j];
        kernel->offset_mm[h - j] = -(float)l.offset[j];
    }
    for (int c = 0; c < 3; c++) {
        double f = 1, t = 0, q[SAM_KERNEL_MAX_TAPS / 2 + 1];
        if (total[c] > 0)
            fit_channel(&table, &ref, target[c], &f, &t);
        kernel->falloff[c] = (float)f;
        kernel->strength[c] = (float)t;
        model_masses(&table, &l, f + 0.001, q);
        for (int j = 0; j <= h; j++) {
            double w = t * q[j] + (j ? 0 : 1 - t);
            kernel->weight[h + j][c] = (float)w;
            kernel->weight[h - j][c] = (float)w;
        }
    }
    return SAM_OK;
}

sam_status sam_profile_separable_kernel_direct(const sam_profile *profile, uint32_t taps,
                                               sam_separable_kernel *kernel, sam_error *err)
{
    /* The eq.-1 kernel's layout and width, then each channel's own cell
     * masses in place of the reshaped red channel. */
    sam_status st = sam_profile_separable_kernel(profile, taps, kernel, err);
    if (st != SAM_OK)
        return st;
    half_layout l;
    make_layout(taps, kernel->width_mm, &l);
    double target[3][SAM_KERNEL_MAX_TAPS / 2 + 1];
    target_masses(profile, &l, sam_profile_scale_max(profile), target);
    int h = l.half;
    for (int c = 0; c < 3; c++) {
        double sum = target[c][0];
        for (int j = 1; j <= h; j++)
            sum += 2 * target[c][j];
        for (int j = 0; j <= h; j++) {
            /* A channel with no energy keeps only its centre tap. */
            double w = sum > 0 ? target[c][j] / sum : (j == 0);
            kernel->weight[h + j][c] = (float)w;
            kernel->weight[h - j][c] = (float)w;
        }
        kernel->strength[c] = 1.0f;
        kernel->falloff[c] = 1.0f;
    }
    return SAM_OK;
}

float sam_profile_kernel_error(const sam_profile *profile, const sam_separable_kernel *kernel,
                               int channel)
{
    if (!profile || !kernel || channel < 0 || channel > 2 || !validate_taps(kernel->taps) ||
        !(kernel->width_mm > 0) || !isfinite(kernel->width_mm))
        return NAN;
    half_layout l;
    make_layout(kernel->taps, kernel->width_mm, &l);
    double target[3][SAM_KERNEL_MAX_TAPS / 2 + 1];
    target_masses(profile, &l, sam_profile_scale_max(profile), target);
    int h = l.half;
    double num = 0, den = 0;
    for (int k = 0; k < (int)kernel->taps; k++) {
        double tk = target[channel][abs(k - h)];
        double d = tk - kernel->weight[k][channel];
        num += d * d;
        den += tk * tk;
    }
    if (den == 0)
        return num == 0 ? 0.0f : INFINITY;
    return (float)sqrt(num / den);
}
