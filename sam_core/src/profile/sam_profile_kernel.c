/*
 * sam_profile_kernel: the separable screen-space kernels of Jimenez et al.:
 * eq. 1 fitted to the profile's own 1D marginals, the marginals themselves
 * ("direct"), and the best separable fit of the 2D kernel (eq. 2, "fit2d").
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
 *
 * 2D. The marginal makes one pass exact across a straight edge, but the
 * two passes apply s s^T, and the 2D kernel S (S_ab = mass of the
 * normalised profile over cell a times cell b) is not of rank one: the
 * marginal's product misses it by a relative RMS of 0.50 / 0.22 / 0.12 for
 * skin (17 taps, R / G / B). fit2d minimises ||S - s s^T||_F itself with
 * sum s = 1 (energy conserving, like the other kernels) and s >= 0: 0.41 /
 * 0.17 / 0.09. Its S comes from the 8-Gaussian fit, whose cell masses are
 * products of erf differences: exact for skin, within the fit's 0.3% for
 * dipoles. The measure (sam_profile_kernel_error_2d) integrates the
 * profile itself instead, so it also sees that fit's error. Measured 2D
 * errors, R / G / B, marginal -> fit2d (17 taps):
 *   skin     0.498 0.215 0.122 -> 0.410 0.171 0.094
 *   apple    0.320 0.319 0.235 -> 0.274 0.272 0.202
 *   cream    0.350 0.327 0.289 -> 0.270 0.261 0.244
 *   ketchup  0.114 0.072 0.059 -> 0.104 0.065 0.049
 * and below 0.30 for every dipole preset and tap count (test_profile prints
 * them all). Jimenez et al. report the first eigenvalue of skin's S holding
 * about 80% of its energy, i.e. a best rank-one error near sqrt(0.2) =
 * 0.447; fit2d stays below that at 9, 17 and 33 taps.
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
    double strip[3][SAM_KERNEL_MAX_TAPS / 2 + 2] = {{0}};
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
    double strip[SAM_KERNEL_MAX_TAPS / 2 + 2] = {0};
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

/* What every variant shares: the checks, the width and the offsets (the
 * rest of `kernel` zero). Returns the channel totals and, where r_hi_out and
 * width_out are not NULL, the quadrature's upper radius and the width in
 * double precision (the kernel stores a float). */
static sam_status kernel_layout(const sam_profile *profile, uint32_t taps,
                                sam_separable_kernel *kernel, const char *function,
                                double total[3], double *r_hi_out, double *width_out,
                                sam_error *err)
{
    if (!profile || !kernel)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "%s: NULL argument", function);
    if (!validate_taps(taps))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "separable kernel: %u taps, expected an odd count in 9..%d", taps,
                        SAM_KERNEL_MAX_TAPS);
    sam_profile_total_d(profile, total);
    if (!(total[0] > 0 || total[1] > 0 || total[2] > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "separable kernel: profile '%.64s' reflects nothing", profile->name);
    double r_hi = sam_profile_scale_max(profile);
    double width = kernel_width(profile, total, r_hi);
    memset(kernel, 0, sizeof *kernel);
    kernel->taps = taps;
    kernel->width_mm = (float)width;
    half_layout l;
    make_layout(taps, width, &l);
    int h = l.half;
    for (int j = 0; j <= h; j++) {
        kernel->offset_mm[h + j] = (float)l.offset[j];
        kernel->offset_mm[h - j] = -(float)l.offset[j];
    }
    if (r_hi_out)
        *r_hi_out = r_hi;
    if (width_out)
        *width_out = width;
    return SAM_OK;
}

/* Writes one channel's half weights w[0..half] into both sides. */
static void store_channel(sam_separable_kernel *kernel, int channel, const double w[])
{
    int h = (int)(kernel->taps / 2);
    for (int j = 0; j <= h; j++) {
        kernel->weight[h + j][channel] = (float)w[j];
        kernel->weight[h - j][channel] = (float)w[j];
    }
}

sam_status sam_profile_separable_kernel(const sam_profile *profile, uint32_t taps,
                                        sam_separable_kernel *kernel, sam_error *err)
{
    double total[3], r_hi, W;
    sam_status st = kernel_layout(profile, taps, kernel, "sam_profile_separable_kernel", total,
                                  &r_hi, &W, err);
    if (st != SAM_OK)
        return st;
    int base = total[0] > 0 ? 0 : (total[1] > 0 ? 1 : 2);
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

    half_layout l;
    make_layout(taps, W, &l);
    for (int c = 0; c < 3; c++) {
        double f = 1, t = 0, q[SAM_KERNEL_MAX_TAPS / 2 + 1];
        if (total[c] > 0)
            fit_channel(&table, &ref, target[c], &f, &t);
        kernel->falloff[c] = (float)f;
        kernel->strength[c] = (float)t;
        model_masses(&table, &l, f + 0.001, q);
        for (int j = 0; j <= l.half; j++)
            q[j] = t * q[j] + (j ? 0 : 1 - t);
        store_channel(kernel, c, q);
    }
    return SAM_OK;
}

sam_status sam_profile_separable_kernel_direct(const sam_profile *profile, uint32_t taps,
                                               sam_separable_kernel *kernel, sam_error *err)
{
    double total[3], r_hi;
    sam_status st = kernel_layout(profile, taps, kernel, "sam_profile_separable_kernel_direct",
                                  total, &r_hi, NULL, err);
    if (st != SAM_OK)
        return st;
    /* The cells of the stored (float) width, which the error measures see. */
    half_layout l;
    make_layout(taps, kernel->width_mm, &l);
    double target[3][SAM_KERNEL_MAX_TAPS / 2 + 1];
    target_masses(profile, &l, r_hi, target);
    int h = l.half;
    for (int c = 0; c < 3; c++) {
        double sum = target[c][0];
        for (int j = 1; j <= h; j++)
            sum += 2 * target[c][j];
        for (int j = 0; j <= h; j++)
            /* A channel with no energy keeps only its centre tap. */
            target[c][j] = sum > 0 ? target[c][j] / sum : (j == 0);
        store_channel(kernel, c, target[c]);
        kernel->strength[c] = 1.0f;
        kernel->falloff[c] = 1.0f;
    }
    return SAM_OK;
}

/* The 2D fit: Jimenez eq. 2 over the tap cells. */

typedef double cell_matrix[SAM_KERNEL_MAX_TAPS / 2 + 1][SAM_KERNEL_MAX_TAPS / 2 + 1];

#define FIT2D_ITERATIONS 500
#define FIT2D_BACKTRACKS 60

/* Mass of a zero-mean 1D Gaussian of variance v over [lo, hi], 0 <= lo <=
 * hi; erfc differences in the tail, where erf differences lose digits. */
static double gaussian_interval_mass(double v, double lo, double hi)
{
    double s = sqrt(2 * v), a = lo / s, b = hi / s;
    return a > 0.5 ? 0.5 * (erfc(a) - erfc(b)) : 0.5 * (erf(b) - erf(a));
}

/* T[i][j]: mass of the channel's fit, normalised by `total`, over full cell
 * i times full cell j (half indices; cell 0 spans both sides of 0). A 2D
 * Gaussian's mass over a rectangle is the product of its 1D masses. */
static void fit_cell_masses(const sam_gaussian_fit *fit, const half_layout *l, int channel,
                            double total, cell_matrix T)
{
    int n = l->half + 1;
    memset(T, 0, sizeof(cell_matrix));
    for (uint32_t k = 0; k < fit->count; k++) {
        double w = fit->weight[k][channel] / total, g[SAM_KERNEL_MAX_TAPS / 2 + 1];
        if (w == 0)
            continue;
        for (int j = 0; j < n; j++)
            g[j] = (j ? 1 : 2) * gaussian_interval_mass(fit->variance[k], l->bound[j],
                                                        l->bound[j + 1]);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                T[i][j] += w * g[i] * g[j];
    }
}

/* f(u) = sum_ab (S_ab - s_a s_b)^2 with s the full kernel (mult[j] copies
 * of the half weight u[j]), and, where g is not NULL, its gradient in the
 * metric diag(mult): in that metric a gradient step and the projection
 * below act on the full kernel, so its mirrored taps stay equal. */
static double fit2d_objective(int n, const double mult[], const cell_matrix T, const double u[],
                              double g[])
{
    double f = 0;
    for (int i = 0; i < n; i++) {
        double gi = 0;
        for (int j = 0; j < n; j++) {
            double d = T[i][j] - u[i] * u[j];
            f += mult[i] * mult[j] * d * d;
            gi += mult[j] * d * u[j];
        }
        if (g)
            g[i] = -4 * gi;
    }
    return f;
}

/* Nearest point (metric diag(mult)) to y with u >= 0 and sum mult u = 1:
 * u = max(y - tau, 0), tau from the values in descending order. */
static void project_weights(int n, const double mult[], const double y[], double u[])
{
    int order[SAM_KERNEL_MAX_TAPS / 2 + 1];
    for (int i = 0; i < n; i++) {
        int k = i;
        for (; k > 0 && y[order[k - 1]] < y[i]; k--)
            order[k] = order[k - 1];
        order[k] = i;
    }
    /* The first value always passes, and the ones that pass are a prefix. */
    double sm = 0, smy = 0, tau = 0;
    for (int k = 0; k < n; k++) {
        int i = order[k];
        sm += mult[i];
        smy += mult[i] * y[i];
        double t = (smy - 1) / sm;
        if (!(y[i] > t))
            break;
        tau = t;
    }
    for (int i = 0; i < n; i++)
        u[i] = fmax(y[i] - tau, 0);
}

/* Half weights u[0..n-1] minimising f subject to u >= 0 and energy
 * conservation (sum mult u = 1): projected gradient descent with Beck and
 * Teboulle's backtracking, started from the row sums of T (the mass of
 * cell x [-W, W], the 1D marginal up to its tail). f is quartic, not
 * convex, but from random starts every preset reaches the same minimum as
 * from this one (to float rounding of the weights). The problem is well
 * conditioned: 18 to 28 iterations until a step moves u by less than 1e-13
 * relative, so FIT2D_ITERATIONS only guards against a bad input; the step
 * doubles after each accepted one so that it tracks the local curvature. */
static void fit2d_channel(const cell_matrix T, int n, double u[])
{
    double mult[SAM_KERNEL_MAX_TAPS / 2 + 1], g[SAM_KERNEL_MAX_TAPS / 2 + 1];
    double y[SAM_KERNEL_MAX_TAPS / 2 + 1], trial[SAM_KERNEL_MAX_TAPS / 2 + 1];
    double sum = 0, norm2 = 0;
    for (int i = 0; i < n; i++)
        mult[i] = i ? 2 : 1;
    for (int i = 0; i < n; i++) {
        u[i] = 0;
        for (int j = 0; j < n; j++)
            u[i] += mult[j] * T[i][j];
        sum += mult[i] * u[i];
    }
    for (int i = 0; i < n; i++) {
        u[i] /= sum;
        norm2 += mult[i] * u[i] * u[i];
    }
    /* The Hessian is about 4 (|s|^2 + 2 s s^T - S), at most 12 |s|^2. */
    double step = 1 / (12 * norm2), f = fit2d_objective(n, mult, T, u, g);
    for (int it = 0; it < FIT2D_ITERATIONS; it++) {
        double move = 0;
        int accepted = 0;
        for (int k = 0; k < FIT2D_BACKTRACKS && !accepted; k++) {
            for (int i = 0; i < n; i++)
                y[i] = u[i] - step * g[i];
            project_weights(n, mult, y, trial);
            double lin = 0;
            move = 0;
            for (int i = 0; i < n; i++) {
                double d = trial[i] - u[i];
                lin += mult[i] * g[i] * d;
                move += mult[i] * d * d;
            }
            /* The quadratic model at this step bounds f: the step is short
             * enough (Beck and Teboulle). */
            accepted = fit2d_objective(n, mult, T, trial, NULL) <= f + lin + move / (2 * step);
            if (!accepted)
                step *= 0.5;
        }
        if (!accepted)
            break;
        memcpy(u, trial, (size_t)n * sizeof *u);
        f = fit2d_objective(n, mult, T, u, g);
        norm2 = 0;
        for (int i = 0; i < n; i++)
            norm2 += mult[i] * u[i] * u[i];
        if (move <= 1e-26 * norm2)
            break;
        step *= 2;
    }
}

sam_status sam_profile_separable_kernel_fit2d(const sam_profile *profile, uint32_t taps,
                                              sam_separable_kernel *kernel, sam_error *err)
{
    double total[3];
    sam_status st = kernel_layout(profile, taps, kernel, "sam_profile_separable_kernel_fit2d",
                                  total, NULL, NULL, err);
    if (st != SAM_OK)
        return st;
    sam_gaussian_fit fit;
    st = sam_profile_fit_gaussians(profile, &fit, err);
    if (st != SAM_OK)
        return st;
    half_layout l;
    make_layout(taps, kernel->width_mm, &l);
    for (int c = 0; c < 3; c++) {
        double u[SAM_KERNEL_MAX_TAPS / 2 + 1] = {0};
        if (total[c] > 0) {
            cell_matrix T;
            fit_cell_masses(&fit, &l, c, total[c], T);
            fit2d_channel(T, l.half + 1, u);
        } else {
            u[0] = 1; /* a channel with no energy keeps only its centre tap */
        }
        store_channel(kernel, c, u);
        kernel->strength[c] = 1.0f;
        kernel->falloff[c] = 1.0f;
    }
    return SAM_OK;
}

/* Positive half of the 16-point Gauss-Legendre rule on [-1, 1] (exact for
 * polynomials up to degree 31). */
static const double gl16_node[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                                    0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                                    0.9445750230732326, 0.9894009349916499};
static const double gl16_weight[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                                      0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                                      0.0622535239386479, 0.0271524594117541};

/* Mass of one channel of the profile over [x0, x1] x [y0, y1] (0 <= x0 < x1,
 * 0 <= y0 < y1), in polar coordinates: along a ray the radial integral
 * int r R dr is closed form (sam_profile_inner_d, _outer_d), so however
 * peaked R is only the angle is integrated numerically. The ray at angle t
 * enters at r0 = max(x0 / cos t, y0 / sin t) and leaves at r1 = min(x1 /
 * cos t, y1 / sin t); each switches edge at a corner's angle, which splits
 * the angle range into pieces where both are smooth, one Gauss-Legendre rule
 * each. Near the origin int_0^r is free of cancellation, away from it
 * int_r^inf: the rectangle's nearest point picks the form. */
static double rect_mass(const sam_profile *p, int channel, double total, double x0, double x1,
                        double y0, double y1)
{
    double near[3];
    sam_profile_outer_d(p, hypot(x0, y0), near);
    int tail = near[channel] < 0.5 * total;
    void (*energy)(const sam_profile *, double, double[3]) =
        tail ? sam_profile_outer_d : sam_profile_inner_d;
    double a[4] = {atan2(y0, x1), atan2(y0, x0), atan2(y1, x1), atan2(y1, x0)};
    if (a[1] > a[2]) {
        double t = a[1];
        a[1] = a[2];
        a[2] = t;
    }
    double sum = 0;
    for (int k = 0; k < 3; k++) {
        double mid = 0.5 * (a[k] + a[k + 1]), half = 0.5 * (a[k + 1] - a[k]);
        if (!(half > 0))
            continue;
        for (int i = 0; i < 16; i++) {
            double t = mid + half * (i < 8 ? -gl16_node[i] : gl16_node[i - 8]);
            double c = cos(t), s = sin(t), e0[3], e1[3];
            energy(p, fmax(x0 / c, y0 / s), e0);
            energy(p, fmin(x1 / c, y1 / s), e1);
            double d = tail ? e0[channel] - e1[channel] : e1[channel] - e0[channel];
            sum += gl16_weight[i % 8] * half * d;
        }
    }
    return sum / (2 * SAM_PROFILE_PI);
}

/* As fit_cell_masses, from the profile itself: the upper triangle of one
 * quadrant, as the profile is radially symmetric. */
static void exact_cell_masses(const sam_profile *p, const half_layout *l, int channel,
                              double total, cell_matrix T)
{
    for (int i = 0; i <= l->half; i++)
        for (int j = i; j <= l->half; j++)
            T[i][j] = T[j][i] = (i ? 1 : 2) * (j ? 1 : 2) *
                                rect_mass(p, channel, total, l->bound[i], l->bound[i + 1],
                                          l->bound[j], l->bound[j + 1]) /
                                total;
}

/* Whether the error measures can read the arguments. */
static int measurable(const sam_profile *profile, const sam_separable_kernel *kernel, int channel)
{
    return profile && kernel && channel >= 0 && channel <= 2 && validate_taps(kernel->taps) &&
           kernel->width_mm > 0 && isfinite(kernel->width_mm);
}

float sam_profile_kernel_error_2d(const sam_profile *profile, const sam_separable_kernel *kernel,
                                  int channel)
{
    if (!measurable(profile, kernel, channel))
        return NAN;
    half_layout l;
    make_layout(kernel->taps, kernel->width_mm, &l);
    double total[3];
    sam_profile_total_d(profile, total);
    cell_matrix T = {{0}};
    if (total[channel] > 0)
        exact_cell_masses(profile, &l, channel, total[channel], T);
    int h = l.half;
    double num = 0, den = 0;
    for (int a = 0; a < (int)kernel->taps; a++)
        for (int b = 0; b < (int)kernel->taps; b++) {
            double t = T[abs(a - h)][abs(b - h)];
            double d = t - (double)kernel->weight[a][channel] * kernel->weight[b][channel];
            num += d * d;
            den += t * t;
        }
    if (den == 0)
        return num == 0 ? 0.0f : INFINITY;
    return (float)sqrt(num / den);
}

float sam_profile_kernel_error(const sam_profile *profile, const sam_separable_kernel *kernel,
                               int channel)
{
    if (!measurable(profile, kernel, channel))
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
