/*
 * sam_profile_fit: the 8-Gaussian fit with variances shared by R, G and B
 * (texture-space diffusion blurs the irradiance once per Gaussian and only
 * the weights differ per channel), and its error (d'Eon et al. eq. 10).
 *
 * Method.
 * 1. A Gaussian sum with at most 8 distinct variances carrying weight is
 *    reproduced exactly (equal variances merged, ascending).
 * 2. Otherwise a range of variances is taken from a per-channel fit: for a
 *    dipole, d'Eon App. A turns each pole z of each channel into Gaussians of
 *    variance {0.2304, 0.7225, 2.6569, 13.6} v0, v0 = z^2 / (1 + sigma_tr z),
 *    with weights alpha'/(4 pi) C_i(sigma_tr z) e^{-sigma_tr z}; the range is
 *    [min, max] over those whose |weight| is at least 1e-3 of the channel's
 *    total reflectance. The seed text of App. A stops after C_3, so C_4 is
 *    taken as 2 pi - C_1 - C_2 - C_3, which keeps each pole's power (the
 *    per-pole form of eq. 9). A Gaussian sum of more than 8 uses the range
 *    of its own variances.
 * 3. Eight variances start geometrically spaced over that range. For fixed
 *    variances eq. 6 is quadratic in the weights: the Gram matrix
 *    int r G(v_i) G(v_j) dr = 1 / (4 pi^2 (v_i + v_j)) is exact, the
 *    projections int r R G(v_j) dr use a Simpson rule on a log grid. Each
 *    channel's weights are solved with w >= 0 and sum w = R_d (eq. 9) as an
 *    equality constraint, by a primal active-set method, so the fit keeps
 *    the total reflectance exactly (up to float rounding).
 * 4. A coordinate search on the 8 log-variances (steps halving from 0.5 to
 *    1/256 in ln v) lowers the sum over channels of the squared eq.-10
 *    errors, re-solving the constrained weights at every trial.
 *
 * Measured eq.-10 errors, worst of R, G, B (test_profile prints all):
 *   skin 0 (6 Gaussians, exact)   apple 0.107%     chicken1 0.182%
 *   chicken2 0.164%               cream 0.240%     ketchup 0.221%
 *   marble 0.170%                 potato 0.070%    skimmilk 0.274%
 *   skin1 0.131%                  skin2 0.140%     wholemilk 0.168%
 * The worst is skimmilk's blue channel; SAM_PROFILE_FIT_ERROR_BOUND (0.5%)
 * is what the tests hold every preset and channel to. For comparison d'Eon
 * report 0.093% for marble's green with 8 variances free per channel; this
 * method fitting that channel alone (a grey profile) reaches 0.073%, so the
 * extra error above (marble 0.109% / 0.122% / 0.170%) is the price of
 * sharing the variances across channels.
 */
#include <math.h>
#include <string.h>

#include "sam/sam_profile.h"
#include "sam_profile_internal.h"

#define FIT_NODES 256      /* Simpson intervals of the fit's radial rule */
#define ERROR_NODES 1024   /* ... and of the error measurement */
#define MIN_SEPARATION 0.05 /* ln v; closer variances make the Gram singular */

typedef struct fit_problem {
    int measure; /* 1: int r (R - F)^2 dr (eq. 10), 3: int r^3 (R - F)^2 dr */
    double r[FIT_NODES + 1], w[FIT_NODES + 1]; /* w includes the measure's r^measure */
    double R[3][FIT_NODES + 1];
    double total[3];
    double power[3]; /* int r^measure R^2 dr, the denominator of the error squared */
    double lnv_lo, lnv_hi;
} fit_problem;

/* int_0^inf r^measure G(v_i, r) G(v_j, r) dr, exact. */
static double gram(int measure, double vi, double vj)
{
    if (measure == 1)
        return 1 / (4 * SAM_PROFILE_PI * SAM_PROFILE_PI * (vi + vj));
    const double a = 0.5 / vi + 0.5 / vj; /* int r^3 e^{-a r^2} dr = 1 / (2 a^2) */
    return 1 / (2 * a * a) / (4 * SAM_PROFILE_PI * SAM_PROFILE_PI * vi * vj);
}

/* Solves the n x n system a x = b (row-major, n <= 9) by Gaussian
 * elimination with partial pivoting; returns 0 when it is singular. */
static int solve_linear(int n, double a[9][9], double b[9], double x[9])
{
    double scale = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            scale = fmax(scale, fabs(a[i][j]));
    for (int col = 0; col < n; col++) {
        int piv = col;
        for (int i = col + 1; i < n; i++)
            if (fabs(a[i][col]) > fabs(a[piv][col]))
                piv = i;
        if (!(fabs(a[piv][col]) > 1e-14 * scale))
            return 0;
        if (piv != col) {
            for (int j = 0; j < n; j++) {
                double t = a[col][j];
                a[col][j] = a[piv][j];
                a[piv][j] = t;
            }
            double t = b[col];
            b[col] = b[piv];
            b[piv] = t;
        }
        for (int i = col + 1; i < n; i++) {
            double f = a[i][col] / a[col][col];
            for (int j = col; j < n; j++)
                a[i][j] -= f * a[col][j];
            b[i] -= f * b[col];
        }
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (int j = i + 1; j < n; j++)
            s -= a[i][j] * x[j];
        x[i] = s / a[i][i];
    }
    return 1;
}

/* Minimises 0.5 w'Hw - g'w subject to sum(w) = total and w >= 0 (n <= 8)
 * with a primal active-set method. The problem is first scaled to a unit
 * diagonal (y_i = w_i sqrt(H_ii)), which turns the Gram matrix of Gaussians
 * into sech((ln v_i - ln v_j)/2) and keeps the KKT systems well conditioned.
 * Returns 0 when a KKT system is singular. */
static int solve_weights(int n, const double H[8][8], const double g[8], double total, double w[8])
{
    double s[8], Hs[8][8], gs[8], y[8], gmax = 0;
    int active[8] = {0};
    for (int i = 0; i < n; i++)
        s[i] = 1 / sqrt(H[i][i]);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++)
            Hs[i][j] = H[i][j] * s[i] * s[j];
        gs[i] = g[i] * s[i];
        gmax = fmax(gmax, fabs(gs[i]));
        y[i] = total / n / s[i]; /* feasible start: equal weights */
    }
    /* In y the constraint is sum_i s_i y_i = total. */
    for (int iter = 0; iter < 100; iter++) {
        int free_idx[8], m = 0;
        for (int i = 0; i < n; i++)
            if (!active[i])
                free_idx[m++] = i;
        double K[9][9], rhs[9], sol[9];
        for (int a = 0; a < m; a++) {
            for (int b = 0; b < m; b++)
                K[a][b] = Hs[free_idx[a]][free_idx[b]];
            K[a][m] = s[free_idx[a]];
            K[m][a] = s[free_idx[a]];
            rhs[a] = gs[free_idx[a]];
        }
        K[m][m] = 0;
        rhs[m] = total;
        if (!solve_linear(m + 1, K, rhs, sol))
            return 0;
        double alpha = 1;
        int block = -1;
        for (int a = 0; a < m; a++) {
            int i = free_idx[a];
            if (sol[a] < 0) {
                double t = y[i] / (y[i] - sol[a]);
                if (t < alpha) {
                    alpha = t;
                    block = i;
                }
            }
        }
        for (int a = 0; a < m; a++) {
            int i = free_idx[a];
            y[i] += alpha * (sol[a] - y[i]);
        }
        if (block >= 0) {
            y[block] = 0;
            active[block] = 1;
            continue;
        }
        /* At the minimum on this face: release the active bound with the
         * most negative multiplier lambda_i = (Hy - g)_i + nu s_i, if any. */
        double nu = sol[m], worst = -1e-12 * (gmax > 0 ? gmax : 1);
        int release = -1;
        for (int i = 0; i < n; i++) {
            if (!active[i])
                continue;
            double lambda = -gs[i] + nu * s[i];
            for (int j = 0; j < n; j++)
                lambda += Hs[i][j] * y[j];
            if (lambda < worst) {
                worst = lambda;
                release = i;
            }
        }
        if (release < 0)
            break;
        active[release] = 0;
    }
    for (int i = 0; i < n; i++)
        w[i] = y[i] > 0 ? y[i] * s[i] : 0;
    return 1;
}

/* int r R_c G(v) dr for the three channels. */
static void project(const fit_problem *fp, double v, double c[3])
{
    c[0] = c[1] = c[2] = 0;
    for (int k = 0; k <= FIT_NODES; k++) {
        double gw = fp->w[k] * sam_profile_gaussian(v, fp->r[k]);
        for (int ch = 0; ch < 3; ch++)
            c[ch] += gw * fp->R[ch][k];
    }
}

/* Sum over channels of the squared relative eq.-10 error for the variances
 * exp(lnv) given their projections c; the weights go to w when not NULL. */
static double objective(const fit_problem *fp, const double lnv[8], const double c[8][3],
                        double w[8][3])
{
    double v[8], H[8][8], sum = 0;
    for (int i = 0; i < 8; i++)
        v[i] = exp(lnv[i]);
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++)
            H[i][j] = gram(fp->measure, v[i], v[j]);
    for (int ch = 0; ch < 3; ch++) {
        double g[8], x[8] = {0};
        if (fp->total[ch] > 0) {
            for (int i = 0; i < 8; i++)
                g[i] = c[i][ch];
            if (!solve_weights(8, H, g, fp->total[ch], x))
                return INFINITY;
            double e = fp->power[ch];
            for (int i = 0; i < 8; i++) {
                e -= 2 * x[i] * g[i];
                for (int j = 0; j < 8; j++)
                    e += x[i] * H[i][j] * x[j];
            }
            sum += fmax(e, 0) / fp->power[ch];
        }
        if (w)
            for (int i = 0; i < 8; i++)
                w[i][ch] = x[i];
    }
    return sum;
}

/* d'Eon App. A weight curves C_1..C_4 at x = sigma_tr |z|. */
static void deon_curves(double x, double out[4])
{
    /* (1 - e^{-a x}) / x, continuous at x = 0 (no absorption). */
#define ONE_MINUS_EXP_OVER_X(a) (x > 1e-12 ? -expm1(-(a) * x) / x : (a))
    out[0] = -0.3454 + 1.2422 * ONE_MINUS_EXP_OVER_X(0.7452);
    out[1] = 5.34071 * (ONE_MINUS_EXP_OVER_X(0.716) * (0.9029 * x - 0.7401) +
                        0.90295 * exp(-0.7165 * x));
    out[2] = 10.2416 * (ONE_MINUS_EXP_OVER_X(1.0961) * (0.2420 * x + 0.1804) -
                        0.00244 * exp(-1.0961 * x) * (0.2041 * x + 0.1752));
#undef ONE_MINUS_EXP_OVER_X
    out[3] = 2 * SAM_PROFILE_PI - out[0] - out[1] - out[2];
}

/* The variance range [lo, hi] of the per-channel App. A fit of a dipole. */
static void deon_range(const sam_profile *p, const double total[3], double *lo, double *hi)
{
    static const double spread[4] = {0.2304, 0.7225, 2.6569, 13.6};
    *lo = INFINITY;
    *hi = 0;
    for (int ch = 0; ch < 3; ch++) {
        sam_dipole_channel d;
        sam_profile_dipole_channel(p, ch, &d);
        double zs[2] = {d.z_r, d.z_v};
        for (int k = 0; k < 2; k++) {
            double x = d.sigma_tr * zs[k], curves[4];
            double v0 = zs[k] * zs[k] / (1 + x);
            deon_curves(x, curves);
            for (int i = 0; i < 4; i++) {
                double weight = d.alpha / (4 * SAM_PROFILE_PI) * curves[i] * exp(-x);
                if (fabs(weight) >= 1e-3 * total[ch]) {
                    *lo = fmin(*lo, spread[i] * v0);
                    *hi = fmax(*hi, spread[i] * v0);
                }
            }
        }
    }
}

/* Copies a Gaussian sum with <= 8 distinct weighted variances; returns 0
 * when it has more. */
static int fit_exact(const sam_profile *p, sam_gaussian_fit *fit)
{
    memset(fit, 0, sizeof *fit);
    for (uint32_t i = 0; i < p->gaussian_count && i < SAM_PROFILE_MAX_GAUSSIANS; i++) {
        const float *wi = p->weight[i];
        if (wi[0] + wi[1] + wi[2] <= 0)
            continue;
        uint32_t k = 0;
        while (k < fit->count && fit->variance[k] < p->variance[i])
            k++;
        if (k < fit->count && fit->variance[k] == p->variance[i]) {
            for (int c = 0; c < 3; c++)
                fit->weight[k][c] += wi[c];
            continue;
        }
        if (fit->count == SAM_PROFILE_FIT_GAUSSIANS)
            return 0;
        memmove(&fit->variance[k + 1], &fit->variance[k], (fit->count - k) * sizeof(float));
        memmove(&fit->weight[k + 1], &fit->weight[k], (fit->count - k) * sizeof fit->weight[0]);
        fit->variance[k] = p->variance[i];
        memcpy(fit->weight[k], wi, sizeof fit->weight[k]);
        fit->count++;
    }
    return 1;
}

static void eval_profile(const void *user, double r, double out[3])
{
    sam_profile_eval_d(user, r, out);
}

sam_status sam_profile_fit_gaussians(const sam_profile *profile, sam_gaussian_fit *fit,
                                     sam_error *err)
{
    if (!profile || !fit)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_fit_gaussians: NULL argument");
    if (profile->kind != SAM_PROFILE_DIPOLE &&
        (profile->kind != SAM_PROFILE_GAUSSIAN_SUM || profile->gaussian_count < 1 ||
         profile->gaussian_count > SAM_PROFILE_MAX_GAUSSIANS))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "sam_profile_fit_gaussians: profile '%.64s' has kind %d and %u gaussians",
                        profile->name, (int)profile->kind, profile->gaussian_count);
    if (profile->kind == SAM_PROFILE_GAUSSIAN_SUM && fit_exact(profile, fit))
        return SAM_OK;
    double total[3], lo, hi;
    sam_profile_total_d(profile, total);
    if (profile->kind == SAM_PROFILE_DIPOLE) {
        deon_range(profile, total, &lo, &hi);
    } else {
        lo = INFINITY;
        hi = 0;
        for (uint32_t i = 0; i < profile->gaussian_count; i++) {
            lo = fmin(lo, profile->variance[i]);
            hi = fmax(hi, profile->variance[i]);
        }
    }
    return sam_profile_fit_radial(eval_profile, profile, total, 1, lo, hi, 1e-4 * sam_profile_scale_min(profile),
                                  sam_profile_scale_max(profile), profile->name, fit, err);
}

sam_status sam_profile_fit_radial(sam_profile_radial_fn f, const void *user, const double total[3], int measure,
                                  double var_lo, double var_hi, double r_lo, double r_hi, const char *name,
                                  sam_gaussian_fit *fit, sam_error *err)
{
    fit_problem fp;
    fp.measure = measure;
    memcpy(fp.total, total, sizeof fp.total);
    double lnlo = log(var_lo), lnhi = log(var_hi);
    /* Too narrow a range would crowd the start below MIN_SEPARATION. */
    if (lnhi - lnlo < 7 * 2 * MIN_SEPARATION) {
        double mid = 0.5 * (lnlo + lnhi);
        lnlo = mid - 7 * MIN_SEPARATION;
        lnhi = mid + 7 * MIN_SEPARATION;
    }
    fp.lnv_lo = lnlo - log(16.0);
    fp.lnv_hi = lnhi + log(16.0);
    r_lo = fmin(r_lo, 1e-4 * exp(0.5 * fp.lnv_lo));
    r_hi = fmax(r_hi, 10 * exp(0.5 * fp.lnv_hi));
    sam_profile_radial_rule(r_lo, r_hi, FIT_NODES, fp.r, fp.w);
    fp.power[0] = fp.power[1] = fp.power[2] = 0;
    for (int k = 0; k <= FIT_NODES; k++) {
        if (measure == 3)
            fp.w[k] *= fp.r[k] * fp.r[k];
        double R[3];
        f(user, fp.r[k], R);
        for (int ch = 0; ch < 3; ch++) {
            fp.R[ch][k] = R[ch];
            fp.power[ch] += fp.w[k] * R[ch] * R[ch];
        }
    }

    double lnv[8], c[8][3];
    for (int i = 0; i < 8; i++) {
        lnv[i] = lnlo + (lnhi - lnlo) * i / 7.0;
        project(&fp, exp(lnv[i]), c[i]);
    }
    double best = objective(&fp, lnv, c, NULL);
    for (double step = 0.5; step > 1.0 / 256;) {
        int improved = 0;
        for (int i = 0; i < 8; i++) {
            for (int dir = -1; dir <= 1; dir += 2) {
                double x = lnv[i] + dir * step;
                int ok = x >= fp.lnv_lo && x <= fp.lnv_hi;
                for (int j = 0; j < 8 && ok; j++)
                    if (j != i && fabs(x - lnv[j]) < MIN_SEPARATION)
                        ok = 0;
                if (!ok)
                    continue;
                double keep_lnv = lnv[i], keep_c[3];
                memcpy(keep_c, c[i], sizeof keep_c);
                lnv[i] = x;
                project(&fp, exp(x), c[i]);
                double f = objective(&fp, lnv, c, NULL);
                if (f < best) {
                    best = f;
                    improved = 1;
                    break;
                }
                lnv[i] = keep_lnv;
                memcpy(c[i], keep_c, sizeof keep_c);
            }
        }
        if (!improved)
            step *= 0.5;
    }
    double w[8][3];
    if (!isfinite(objective(&fp, lnv, c, w)))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "profile '%.64s': the 8-Gaussian fit found no solvable set of variances", name);

    memset(fit, 0, sizeof *fit);
    fit->count = SAM_PROFILE_FIT_GAUSSIANS;
    int order[8];
    for (int i = 0; i < 8; i++) {
        int k = i;
        while (k > 0 && lnv[order[k - 1]] > lnv[i]) {
            order[k] = order[k - 1];
            k--;
        }
        order[k] = i;
    }
    for (int i = 0; i < 8; i++) {
        fit->variance[i] = (float)exp(lnv[order[i]]);
        for (int ch = 0; ch < 3; ch++)
            fit->weight[i][ch] = (float)w[order[i]][ch];
    }
    return SAM_OK;
}

float sam_profile_fit_error(const sam_profile *profile, const sam_gaussian_fit *fit, int channel)
{
    if (!profile || !fit || channel < 0 || channel > 2 || fit->count > SAM_PROFILE_FIT_GAUSSIANS)
        return NAN;
    double lo = sam_profile_scale_min(profile), hi = sam_profile_scale_max(profile);
    for (uint32_t i = 0; i < fit->count; i++) {
        double v = fit->variance[i];
        if (!(v > 0) || !isfinite(v))
            return NAN;
        lo = fmin(lo, sqrt(v));
        hi = fmax(hi, 10 * sqrt(v));
    }
    double r[ERROR_NODES + 1], w[ERROR_NODES + 1], num = 0, den = 0;
    sam_profile_radial_rule(1e-4 * lo, hi, ERROR_NODES, r, w);
    for (int k = 0; k <= ERROR_NODES; k++) {
        double R = sam_profile_eval_channel_d(profile, channel, r[k]), F = 0;
        for (uint32_t i = 0; i < fit->count; i++)
            F += fit->weight[i][channel] * sam_profile_gaussian(fit->variance[i], r[k]);
        num += w[k] * (R - F) * (R - F);
        den += w[k] * R * R;
    }
    if (den == 0)
        return num == 0 ? 0.0f : INFINITY;
    return (float)sqrt(num / den);
}
