/*
 * sam_brdf: Kelemen/Szirmay-Kalos specular lobe and its rho_dt.
 *
 * Albedo integral. Fix l = (s, 0, mu) with mu = n.l, s = sqrt(1 - mu^2), and
 * integrate over the half vector H instead of v: v = 2 (l.H) H - l and
 * dv = 4 (l.H) dH, so with f_r = D F / (4 (l.H)^2)
 *
 *   A = int D(H) (n.H) * F(l.H) * (n.v) / ((l.H)(n.H)) dH
 *     = int D(H) (n.H) * F(l.H) * (2 - mu / ((l.H)(n.H))) dH   over n.v > 0,
 *
 * because n.v = 2 (l.H)(n.H) - mu. The second factor lies in [0, 2], so the
 * integrand is bounded for every l, including grazing. The Beckmann measure
 * D (n.H) dH is du dphi / (2 pi) under tan^2(theta_H) = -m^2 ln(1 - u) (the
 * inverse CDF of D), which absorbs the sharp peak of small roughness.
 *
 * Horizon. With H = (sin t cos p, sin t sin p, cos t), n.v > 0 reads
 * mu cos 2t + s cos p sin 2t > 0, i.e. t < (atan2(s cos p, mu) + pi/2) / 2,
 * so each azimuth p integrates u over [0, u_max(p)] with a smooth integrand
 * that vanishes at the end. u_max changes fastest near p = pi/2 (the plane
 * perpendicular to incidence, a step as mu -> 0), so the azimuth range
 * [0, pi] (the other half is the mirror image) is split there and each half
 * gets its own Gauss-Legendre rule.
 *
 * Accuracy, measured against orders 256 and 2000: order 64 is within 3.6e-5
 * for all mu in [0, 1] and m in [1/64, 1] (the worst cases are mu < 0.003,
 * where the azimuthal step sharpens), within 6.1e-6 for mu >= 0.01; order 32
 * within 3.1e-5 for mu >= 0.01. On a grid of mu in [0, 1], m in [0.001, 2],
 * the albedo at F0 = 1 stays below 1 and reaches it only as mu -> 0.
 */
#include "sam/sam_brdf.h"

#include <math.h>

#define BRDF_PI 3.14159265358979323846

/* Gauss-Legendre nodes and weights mapped to [0, 1]. */
typedef struct gauss_rule {
    uint32_t n;
    double x[SAM_BRDF_MAX_QUADRATURE_ORDER];
    double w[SAM_BRDF_MAX_QUADRATURE_ORDER];
} gauss_rule;

/* Legendre P_n(z) and its derivative by the three-term recurrence. */
static void legendre(uint32_t n, double z, double *p, double *dp)
{
    double p0 = 1.0, p1 = z;
    for (uint32_t k = 2; k <= n; k++) {
        double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    *p = p1;
    *dp = n * (z * p1 - p0) / (z * z - 1.0);
}

/* Roots of P_n by Newton's method from the usual asymptotic initial guess,
 * which lies close enough to each root that every iteration converges to
 * its own root in a few steps. */
static void gauss_rule_init(gauss_rule *rule, uint32_t n)
{
    rule->n = n;
    for (uint32_t i = 0; i < n; i++) {
        double z = cos(BRDF_PI * (i + 0.75) / (n + 0.5));
        double p, dp;
        for (int it = 0; it < 100; it++) {
            legendre(n, z, &p, &dp);
            double dz = p / dp;
            z -= dz;
            if (fabs(dz) < 1e-15)
                break;
        }
        legendre(n, z, &p, &dp);
        rule->x[i] = 0.5 * (1.0 - z);
        rule->w[i] = 1.0 / ((1.0 - z * z) * dp * dp); /* 2/((1-z^2) P'^2), halved for [0,1] */
    }
}

static double beckmann(double c, double m)
{
    if (c <= 0.0)
        return 0.0;
    if (c > 1.0)
        c = 1.0;
    double c2 = c * c;
    double tan2 = (1.0 - c2) / c2;
    /* (tan2 / m) / m rather than tan2 / (m * m): m^2 may underflow when
     * tan2 is 0, and 0/0 would be NaN where the answer is the peak. */
    return exp(-(tan2 / m) / m) / (BRDF_PI * m * m * c2 * c2);
}

static double schlick(double c, double f0)
{
    double b = 1.0 - (c < 0.0 ? 0.0 : c > 1.0 ? 1.0 : c);
    double b2 = b * b;
    return f0 + (1.0 - f0) * b2 * b2 * b;
}

static int params_valid(float roughness, float f0)
{
    return isfinite(roughness) && roughness > 0.0f && f0 >= 0.0f && f0 <= 1.0f;
}

float sam_brdf_beckmann(float n_dot_h, float roughness)
{
    if (!isfinite(n_dot_h) || !isfinite(roughness) || roughness <= 0.0f)
        return NAN;
    return (float)beckmann(n_dot_h, roughness);
}

float sam_brdf_fresnel_schlick(float v_dot_h, float f0)
{
    if (!isfinite(v_dot_h) || !(f0 >= 0.0f && f0 <= 1.0f))
        return NAN;
    return (float)schlick(v_dot_h, f0);
}

float sam_brdf_ks_eval(float n_dot_l, float n_dot_v, float n_dot_h, float v_dot_h, float roughness,
                       float f0)
{
    if (!isfinite(n_dot_l) || !isfinite(n_dot_v) || !isfinite(n_dot_h) || !isfinite(v_dot_h) ||
        !params_valid(roughness, f0))
        return NAN;
    if (n_dot_l <= 0.0f || n_dot_v <= 0.0f || n_dot_h <= 0.0f || v_dot_h <= 0.0f)
        return 0.0f;
    double vh = v_dot_h;
    return (float)(beckmann(n_dot_h, roughness) * schlick(vh, f0) / (4.0 * vh * vh));
}

static double dot3(const float a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

float sam_brdf_ks_eval_dir(const float n[3], const float l[3], const float v[3], float roughness,
                           float f0)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(n[k]) || !isfinite(l[k]) || !isfinite(v[k]))
            return NAN;
    if (!params_valid(roughness, f0))
        return NAN;
    const double ld[3] = {l[0], l[1], l[2]};
    const double vd[3] = {v[0], v[1], v[2]};
    if (dot3(n, ld) <= 0.0 || dot3(n, vd) <= 0.0)
        return 0.0f;
    const double h[3] = {ld[0] + vd[0], ld[1] + vd[1], ld[2] + vd[2]};
    double hh = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    if (!(hh > 0.0))
        return 0.0f;
    double len = sqrt(hh);
    double n_dot_h = dot3(n, h) / len;
    double v_dot_h = dot3(v, h) / len;
    if (n_dot_h <= 0.0 || v_dot_h <= 0.0)
        return 0.0f;
    return (float)(beckmann(n_dot_h, roughness) * schlick(v_dot_h, f0) / hh);
}

/* The albedo integral of the file comment with one rule in every dimension. */
static double albedo_quadrature(double mu, double m, double f0, const gauss_rule *rule)
{
    double s = sqrt(fmax(0.0, 1.0 - mu * mu));
    double sum = 0.0;
    for (int half = 0; half < 2; half++) {
        for (uint32_t i = 0; i < rule->n; i++) {
            double phi = (half + rule->x[i]) * (0.5 * BRDF_PI);
            double c = cos(phi);
            double theta_max = 0.5 * (atan2(s * c, mu) + 0.5 * BRDF_PI);
            double x = tan(theta_max) / m;
            double u_max = -expm1(-x * x);
            double inner = 0.0;
            for (uint32_t j = 0; j < rule->n; j++) {
                double u = u_max * rule->x[j];
                double tan2 = -log1p(-u) * m * m;
                double cos_t = 1.0 / sqrt(1.0 + tan2);
                double sin_t = sqrt(tan2) * cos_t;
                double l_dot_h = s * sin_t * c + mu * cos_t;
                if (l_dot_h <= 0.0)
                    continue;
                double g = 2.0 - mu / (l_dot_h * cos_t);
                if (g <= 0.0)
                    continue;
                inner += rule->w[j] * schlick(l_dot_h, f0) * g;
            }
            sum += rule->w[i] * (0.5 * BRDF_PI) * u_max * inner;
        }
    }
    /* 2 for the mirrored azimuths [pi, 2pi], 1/(2 pi) from the measure. */
    return sum / BRDF_PI;
}

static double clamp01(double x)
{
    return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
}

double sam_brdf_ks_albedo(float n_dot_l, float roughness, float f0, uint32_t order)
{
    if (isnan(n_dot_l) || !params_valid(roughness, f0) || order < 1 ||
        order > SAM_BRDF_MAX_QUADRATURE_ORDER)
        return NAN;
    gauss_rule rule;
    gauss_rule_init(&rule, order);
    return albedo_quadrature(clamp01(n_dot_l), roughness, f0, &rule);
}

/* The albedo is at most 1 mathematically; quadrature rounding may overshoot
 * by an ulp at the grazing limit with F0 = 1, which the clamp absorbs. */
static float rho_dt_from_albedo(double albedo)
{
    return (float)clamp01(1.0 - albedo);
}

float sam_brdf_rho_dt(float n_dot_l, float roughness, float f0)
{
    double albedo = sam_brdf_ks_albedo(n_dot_l, roughness, f0, SAM_BRDF_QUADRATURE_ORDER);
    return isnan(albedo) ? NAN : rho_dt_from_albedo(albedo);
}

sam_status sam_brdf_rho_dt_table(uint32_t size_ndotl, uint32_t size_roughness, float f0,
                                 float roughness_max, float *out, sam_error *err)
{
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "rho_dt table: output buffer is NULL");
    if (size_ndotl < 2 || size_ndotl > SAM_BRDF_MAX_TABLE_SIZE || size_roughness < 2 ||
        size_roughness > SAM_BRDF_MAX_TABLE_SIZE)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "rho_dt table: size %u x %u (N.L x roughness), each must be in 2..%u",
                        size_ndotl, size_roughness, SAM_BRDF_MAX_TABLE_SIZE);
    if (!isfinite(roughness_max) || roughness_max <= 0.0f)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "rho_dt table: roughness_max %g, expected a finite value > 0",
                        (double)roughness_max);
    if (!(f0 >= 0.0f && f0 <= 1.0f))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "rho_dt table: F0 %g, expected a value in [0, 1]", (double)f0);
    gauss_rule rule;
    gauss_rule_init(&rule, SAM_BRDF_QUADRATURE_ORDER);
    for (uint32_t j = 0; j < size_roughness; j++) {
        /* Rounded to float as a caller's sam_brdf_rho_dt argument would be,
         * so the table equals the function at its documented samples. */
        float m = (float)((j + 0.5) / size_roughness * roughness_max);
        if (!(m > 0.0f))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "rho_dt table: roughness_max %g is too small for %u rows "
                            "(first sample rounds to 0)",
                            (double)roughness_max, size_roughness);
        for (uint32_t i = 0; i < size_ndotl; i++) {
            float mu = (float)((i + 0.5) / size_ndotl);
            out[(size_t)j * size_ndotl + i] =
                rho_dt_from_albedo(albedo_quadrature(mu, m, f0, &rule));
        }
    }
    return SAM_OK;
}

/* One axis of GL_LINEAR with GL_CLAMP_TO_EDGE: texel centres at (k + 0.5) / size. */
static void linear_taps(float coord, uint32_t size, uint32_t *k0, uint32_t *k1, double *t)
{
    double x = clamp01(coord) * size - 0.5;
    double f = floor(x);
    *t = x - f;
    long lo = (long)f, hi = lo + 1;
    long last = (long)size - 1;
    *k0 = (uint32_t)(lo < 0 ? 0 : lo > last ? last : lo);
    *k1 = (uint32_t)(hi < 0 ? 0 : hi > last ? last : hi);
}

float sam_brdf_rho_dt_table_lookup(const float *table, uint32_t size_ndotl,
                                   uint32_t size_roughness, float roughness_max, float n_dot_l,
                                   float roughness)
{
    if (isnan(n_dot_l) || isnan(roughness))
        return NAN;
    uint32_t i0, i1, j0, j1;
    double ti, tj;
    linear_taps(n_dot_l, size_ndotl, &i0, &i1, &ti);
    linear_taps(roughness / roughness_max, size_roughness, &j0, &j1, &tj);
    const float *r0 = table + (size_t)j0 * size_ndotl;
    const float *r1 = table + (size_t)j1 * size_ndotl;
    double a = r0[i0] + ti * (r0[i1] - r0[i0]);
    double b = r1[i0] + ti * (r1[i1] - r1[i0]);
    return (float)(a + tj * (b - a));
}
