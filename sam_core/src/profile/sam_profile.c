/*
 * sam_profile: presets, constructors, evaluation, closed-form energies,
 * the radius of influence and the JSON description.
 *
 * Energies. For a Gaussian G(v, r) the energy beyond r is e^{-r^2/2v}. For a
 * dipole pole (1 + sigma d) e^{-sigma d} / d^3 with d = sqrt(r^2 + z^2), the
 * integrand s ds = d dd and (1 + sigma d) e^{-sigma d} / d^2 is the
 * derivative of -e^{-sigma d} / d, so
 *   2 pi int_r^inf s R(s) ds = alpha'/2 sum_poles z e^{-sigma_tr d(r)} / d(r),
 * which at r = 0 gives Jensen's total alpha'/2 (e^{-sigma_tr z_r} +
 * e^{-sigma_tr z_v}). The radius of influence is found by bisection on that
 * closed-form remaining fraction (no numerical integration).
 */
#include "sam/sam_profile.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "sam_profile_internal.h"

typedef struct jensen_medium {
    const char *name;
    float sigma_s_prime[3]; /* mm^-1 */
    float sigma_a[3];       /* mm^-1 */
} jensen_medium;

/* Jensen et al. 2001, Fig. 5 (eta = 1.3 for all). */
static const jensen_medium jensen_media[] = {
    {"apple", {2.29f, 2.39f, 1.97f}, {0.0030f, 0.0034f, 0.046f}},
    {"chicken1", {0.15f, 0.21f, 0.38f}, {0.015f, 0.077f, 0.19f}},
    {"chicken2", {0.19f, 0.25f, 0.32f}, {0.018f, 0.088f, 0.20f}},
    {"cream", {7.38f, 5.47f, 3.15f}, {0.0002f, 0.0028f, 0.0163f}},
    {"ketchup", {0.18f, 0.07f, 0.03f}, {0.061f, 0.97f, 1.45f}},
    {"marble", {2.19f, 2.62f, 3.00f}, {0.0021f, 0.0041f, 0.0071f}},
    {"potato", {0.68f, 0.70f, 0.55f}, {0.0024f, 0.0090f, 0.12f}},
    {"skimmilk", {0.70f, 1.22f, 1.90f}, {0.0014f, 0.0025f, 0.0142f}},
    {"skin1", {0.74f, 0.88f, 1.01f}, {0.032f, 0.17f, 0.48f}},
    {"skin2", {1.09f, 1.59f, 1.79f}, {0.013f, 0.070f, 0.145f}},
    {"wholemilk", {2.55f, 3.21f, 3.77f}, {0.0011f, 0.0024f, 0.014f}},
};
#define JENSEN_MEDIA_COUNT (sizeof jensen_media / sizeof jensen_media[0])
#define JENSEN_ETA 1.3f

/* d'Eon & Luebke's six-Gaussian skin (GPU Gems 3, ch. 14). */
static const float skin_variance[6] = {0.0064f, 0.0484f, 0.187f, 0.567f, 1.99f, 7.41f};
static const float skin_weight[6][3] = {
    {0.233f, 0.455f, 0.649f}, {0.100f, 0.336f, 0.344f}, {0.118f, 0.198f, 0.0f},
    {0.113f, 0.007f, 0.007f}, {0.358f, 0.004f, 0.0f},   {0.078f, 0.0f, 0.0f},
};

size_t sam_profile_preset_count(void)
{
    return 1 + JENSEN_MEDIA_COUNT;
}

const char *sam_profile_preset_name(size_t index)
{
    if (index == 0)
        return "skin";
    if (index - 1 < JENSEN_MEDIA_COUNT)
        return jensen_media[index - 1].name;
    return NULL;
}

static int ascii_lower(int c)
{
    return (c >= 'A' && c <= 'Z') ? c - 'A' + 'a' : c;
}

static int equal_ignoring_case(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (ascii_lower((unsigned char)*a) != ascii_lower((unsigned char)*b))
            return 0;
    return *a == *b;
}

static void set_name(sam_profile *p, const char *name)
{
    snprintf(p->name, sizeof p->name, "%s", name);
}

sam_status sam_profile_preset(const char *name, sam_profile *out, sam_error *err)
{
    if (!name || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_preset: NULL argument");
    if (equal_ignoring_case(name, "skin")) {
        const float(*w)[3] = skin_weight;
        sam_status s = sam_profile_gaussian_sum(6, skin_variance, w, out, err);
        if (s == SAM_OK)
            set_name(out, "skin");
        return s;
    }
    for (size_t i = 0; i < JENSEN_MEDIA_COUNT; i++) {
        if (equal_ignoring_case(name, jensen_media[i].name)) {
            sam_status s = sam_profile_dipole(jensen_media[i].sigma_s_prime,
                                              jensen_media[i].sigma_a, JENSEN_ETA, out, err);
            if (s == SAM_OK)
                set_name(out, jensen_media[i].name);
            return s;
        }
    }
    char list[512];
    size_t len = 0;
    list[0] = 0;
    for (size_t i = 0; i < sam_profile_preset_count(); i++) {
        int k = snprintf(list + len, sizeof list - len, "%s%s", i ? ", " : "",
                         sam_profile_preset_name(i));
        if (k < 0 || (size_t)k >= sizeof list - len)
            break;
        len += (size_t)k;
    }
    return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "unknown profile preset '%.100s' (valid: %s)",
                    name, list);
}

/* Values must also survive the conversion to float, the stored type. */
static int finite_float(double v)
{
    return isfinite(v) && fabs(v) <= FLT_MAX;
}

/* What must be > 0 must stay so as a float: 1e-300 would become 0. */
static const char *positive(double v)
{
    return !(v > 0) ? "must be > 0" : v < FLT_MIN ? "is too small for a 32-bit float (below 1.2e-38)" : NULL;
}

const char *sam_profile_check_variance(double v)
{
    if (!finite_float(v))
        return "is not a finite float";
    return positive(v);
}

const char *sam_profile_check_weight(double w)
{
    if (!finite_float(w))
        return "is not a finite float";
    return w >= 0 ? NULL : "must be >= 0";
}

const char *sam_profile_check_albedo(double a)
{
    if (!finite_float(a))
        return "is not a finite float";
    return a >= 0 && a <= 1 ? NULL : "must lie in [0, 1]";
}

const char *sam_profile_check_sigma_s_prime(double s)
{
    if (!finite_float(s))
        return "is not a finite float";
    return positive(s);
}

const char *sam_profile_check_sigma_a(double s)
{
    if (!finite_float(s))
        return "is not a finite float";
    return s >= 0 ? NULL : "must be >= 0";
}

double sam_profile_fdr(double eta)
{
    return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
}

const char *sam_profile_check_eta(double eta)
{
    if (!finite_float(eta))
        return "is not a finite float";
    const char *not_positive = positive(eta);
    if (not_positive)
        return not_positive;
    /* The boundary term A = (1 + F_dr)/(1 - F_dr) is positive only for
     * |F_dr| < 1; outside, the virtual source lands on the wrong side. */
    double fdr = sam_profile_fdr(eta);
    if (!(fdr > -1 && fdr < 1))
        return "must lie in about (0.733, 3.85), where Jensen's F_dr(eta) is in (-1, 1)";
    return NULL;
}

sam_status sam_profile_dipole(const float sigma_s_prime[3], const float sigma_a[3], float eta,
                              sam_profile *out, sam_error *err)
{
    static const char rgb[3] = {'r', 'g', 'b'};
    if (!sigma_s_prime || !sigma_a || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_dipole: NULL argument");
    for (int c = 0; c < 3; c++) {
        const char *why = sam_profile_check_sigma_s_prime(sigma_s_prime[c]);
        if (why)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "dipole sigma_s_prime.%c = %g %s",
                            rgb[c], (double)sigma_s_prime[c], why);
        why = sam_profile_check_sigma_a(sigma_a[c]);
        if (why)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "dipole sigma_a.%c = %g %s", rgb[c],
                            (double)sigma_a[c], why);
    }
    const char *why = sam_profile_check_eta(eta);
    if (why)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "dipole eta = %g %s", (double)eta, why);
    memset(out, 0, sizeof *out);
    out->kind = SAM_PROFILE_DIPOLE;
    set_name(out, "custom");
    memcpy(out->sigma_s_prime, sigma_s_prime, sizeof out->sigma_s_prime);
    memcpy(out->sigma_a, sigma_a, sizeof out->sigma_a);
    out->eta = eta;
    return SAM_OK;
}

sam_status sam_profile_gaussian_sum(uint32_t count, const float *variance, const float (*weight)[3],
                                    sam_profile *out, sam_error *err)
{
    if (!variance || !weight || !out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_profile_gaussian_sum: NULL argument");
    if (count < 1 || count > SAM_PROFILE_MAX_GAUSSIANS)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "gaussian sum: %u gaussians, expected 1..%d", count,
                        SAM_PROFILE_MAX_GAUSSIANS);
    double sum = 0;
    for (uint32_t i = 0; i < count; i++) {
        const char *why = sam_profile_check_variance(variance[i]);
        if (why)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "gaussian %u: variance %g %s", i,
                            (double)variance[i], why);
        for (int c = 0; c < 3; c++) {
            why = sam_profile_check_weight(weight[i][c]);
            if (why)
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "gaussian %u: weight[%d] %g %s",
                                i, c, (double)weight[i][c], why);
            sum += weight[i][c];
        }
    }
    if (!(sum > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "gaussian sum: all %u gaussians have zero weight in every channel", count);
    memset(out, 0, sizeof *out);
    out->kind = SAM_PROFILE_GAUSSIAN_SUM;
    set_name(out, "custom");
    out->gaussian_count = count;
    memcpy(out->variance, variance, count * sizeof *variance);
    memcpy(out->weight, weight, count * sizeof *weight);
    return SAM_OK;
}

/* ---------------------------------------------------------------------- */
/* Evaluation and energies                                                */

void sam_profile_dipole_channel(const sam_profile *p, int channel, sam_dipole_channel *d)
{
    double ss = p->sigma_s_prime[channel], sa = p->sigma_a[channel];
    double st = ss + sa;
    double fdr = sam_profile_fdr(p->eta);
    double a = (1 + fdr) / (1 - fdr);
    d->alpha = ss / st;
    d->sigma_tr = sqrt(3 * sa * st);
    d->z_r = 1 / st;
    d->z_v = d->z_r * (1 + 4 * a / 3);
}

void sam_profile_dipole_terms(const sam_profile *p, sam_dipole_terms *out)
{
    memset(out, 0, sizeof *out);
    if (p->kind != SAM_PROFILE_DIPOLE)
        return;
    for (int c = 0; c < 3; c++) {
        sam_dipole_channel d;
        sam_profile_dipole_channel(p, c, &d);
        out->alpha[c] = (float)d.alpha;
        out->sigma_tr[c] = (float)d.sigma_tr;
        out->z_r[c] = (float)d.z_r;
        out->z_v[c] = (float)d.z_v;
    }
}

/* z (1 + sigma d) e^{-sigma d} / d^3 */
static double pole(double z, double sigma, double r)
{
    double d = sqrt(r * r + z * z);
    return z * (1 + sigma * d) * exp(-sigma * d) / (d * d * d);
}

double sam_profile_eval_channel_d(const sam_profile *p, int channel, double r)
{
    if (p->kind == SAM_PROFILE_DIPOLE) {
        sam_dipole_channel d;
        sam_profile_dipole_channel(p, channel, &d);
        return d.alpha / (4 * SAM_PROFILE_PI) *
               (pole(d.z_r, d.sigma_tr, r) + pole(d.z_v, d.sigma_tr, r));
    }
    double sum = 0;
    for (uint32_t i = 0; i < p->gaussian_count; i++)
        if (p->weight[i][channel] != 0)
            sum += p->weight[i][channel] * sam_profile_gaussian(p->variance[i], r);
    return sum;
}

void sam_profile_eval_d(const sam_profile *p, double r, double out[3])
{
    if (p->kind == SAM_PROFILE_DIPOLE) {
        for (int c = 0; c < 3; c++)
            out[c] = sam_profile_eval_channel_d(p, c, r);
        return;
    }
    out[0] = out[1] = out[2] = 0;
    for (uint32_t i = 0; i < p->gaussian_count; i++) {
        double g = sam_profile_gaussian(p->variance[i], r);
        for (int c = 0; c < 3; c++)
            out[c] += p->weight[i][c] * g;
    }
}

void sam_profile_eval(const sam_profile *profile, float r_mm, float out_rgb[3])
{
    double v[3];
    sam_profile_eval_d(profile, fabs((double)r_mm), v);
    for (int c = 0; c < 3; c++)
        out_rgb[c] = (float)v[c];
}

void sam_profile_total_d(const sam_profile *p, double out[3])
{
    if (p->kind == SAM_PROFILE_DIPOLE) {
        for (int c = 0; c < 3; c++) {
            sam_dipole_channel d;
            sam_profile_dipole_channel(p, c, &d);
            out[c] = 0.5 * d.alpha * (exp(-d.sigma_tr * d.z_r) + exp(-d.sigma_tr * d.z_v));
        }
        return;
    }
    out[0] = out[1] = out[2] = 0;
    for (uint32_t i = 0; i < p->gaussian_count; i++)
        for (int c = 0; c < 3; c++)
            out[c] += p->weight[i][c];
}

void sam_profile_total_reflectance(const sam_profile *profile, float out_rgb[3])
{
    double t[3];
    sam_profile_total_d(profile, t);
    for (int c = 0; c < 3; c++)
        out_rgb[c] = (float)t[c];
}

void sam_profile_outer_d(const sam_profile *p, double r, double out[3])
{
    if (p->kind == SAM_PROFILE_DIPOLE) {
        for (int c = 0; c < 3; c++) {
            sam_dipole_channel d;
            sam_profile_dipole_channel(p, c, &d);
            double dr = sqrt(r * r + d.z_r * d.z_r), dv = sqrt(r * r + d.z_v * d.z_v);
            out[c] = 0.5 * d.alpha *
                     (d.z_r * exp(-d.sigma_tr * dr) / dr + d.z_v * exp(-d.sigma_tr * dv) / dv);
        }
        return;
    }
    out[0] = out[1] = out[2] = 0;
    for (uint32_t i = 0; i < p->gaussian_count; i++) {
        double e = exp(-r * r / (2.0 * p->variance[i]));
        for (int c = 0; c < 3; c++)
            out[c] += p->weight[i][c] * e;
    }
}

void sam_profile_slab_transmission(const sam_profile *profile, float t_mm, float out_rgb[3])
{
    /* Through a slab of thickness t, s^2 = t^2 + rho^2 turns the plane's
     * integral of R_d(s) into the energy beyond radius t. */
    double g[3];
    sam_profile_outer_d(profile, fabs((double)t_mm), g);
    for (int c = 0; c < 3; c++)
        out_rgb[c] = (float)g[c];
}

/* z (e^{-sigma z}/z - e^{-sigma d}/d) rewritten with d - z = r^2/(d + z)
 * and expm1, so that small r loses no digits. */
static double pole_inner(double z, double sigma, double r)
{
    double d = sqrt(r * r + z * z);
    double dz = r * r / (d + z);
    return exp(-sigma * z) * (dz - z * expm1(-sigma * dz)) / d;
}

void sam_profile_inner_d(const sam_profile *p, double r, double out[3])
{
    if (p->kind == SAM_PROFILE_DIPOLE) {
        for (int c = 0; c < 3; c++) {
            sam_dipole_channel d;
            sam_profile_dipole_channel(p, c, &d);
            out[c] = 0.5 * d.alpha *
                     (pole_inner(d.z_r, d.sigma_tr, r) + pole_inner(d.z_v, d.sigma_tr, r));
        }
        return;
    }
    out[0] = out[1] = out[2] = 0;
    for (uint32_t i = 0; i < p->gaussian_count; i++) {
        double e = -expm1(-r * r / (2.0 * p->variance[i]));
        for (int c = 0; c < 3; c++)
            out[c] += p->weight[i][c] * e;
    }
}

/* Largest remaining-energy fraction over the non-zero channels. */
static double remaining_fraction(const sam_profile *p, const double total[3], double r)
{
    double outer[3], worst = 0;
    sam_profile_outer_d(p, r, outer);
    for (int c = 0; c < 3; c++)
        if (total[c] > 0 && outer[c] / total[c] > worst)
            worst = outer[c] / total[c];
    return worst;
}

double sam_profile_scale_min(const sam_profile *p)
{
    double s = INFINITY;
    if (p->kind == SAM_PROFILE_DIPOLE) {
        for (int c = 0; c < 3; c++) {
            sam_dipole_channel d;
            sam_profile_dipole_channel(p, c, &d);
            s = fmin(s, d.z_r);
            if (d.sigma_tr > 0)
                s = fmin(s, 1 / d.sigma_tr);
        }
        return s;
    }
    for (uint32_t i = 0; i < p->gaussian_count; i++)
        if (p->weight[i][0] + p->weight[i][1] + p->weight[i][2] > 0)
            s = fmin(s, sqrt((double)p->variance[i]));
    return s;
}

double sam_profile_radius_d(const sam_profile *p, double tolerance)
{
    double total[3];
    sam_profile_total_d(p, total);
    if (!(total[0] > 0 || total[1] > 0 || total[2] > 0))
        return 0;
    /* The fraction is 1 at r = 0 and decreases monotonically: bracket by
     * doubling from the profile's own scale, then bisect. */
    double lo = 0, hi = sam_profile_scale_min(p);
    while (remaining_fraction(p, total, hi) > tolerance) {
        lo = hi;
        hi *= 2;
        if (hi > 1e30)
            return hi;
    }
    for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; i++) {
        double mid = 0.5 * (lo + hi);
        if (remaining_fraction(p, total, mid) > tolerance)
            lo = mid;
        else
            hi = mid;
    }
    return hi;
}

float sam_profile_radius(const sam_profile *profile, float tolerance)
{
    if (!(tolerance > 0))
        return INFINITY;
    if (tolerance >= 1)
        return 0;
    double total[3];
    sam_profile_total_d(profile, total);
    float r = (float)sam_profile_radius_d(profile, tolerance);
    /* Rounding to float may land just inside the bound; step outwards. */
    while (r > 0 && isfinite(r) && remaining_fraction(profile, total, r) > tolerance)
        r = nextafterf(r, INFINITY);
    return r;
}

double sam_profile_scale_max(const sam_profile *p)
{
    return sam_profile_radius_d(p, 1e-12);
}

void sam_profile_radial_rule(double r_lo, double r_hi, int n, double *r, double *w)
{
    double h = log(r_hi / r_lo) / n;
    for (int k = 0; k <= n; k++) {
        double rk = r_lo * exp(k * h);
        double c = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        r[k] = rk;
        w[k] = c * h / 3 * rk * rk; /* r dr = r^2 du with u = ln r */
    }
    w[0] += 0.5 * r_lo * r_lo; /* int_0^r_lo r f(r) dr with f flat there */
}

/* ---------------------------------------------------------------------- */
/* JSON description                                                        */

typedef struct json_out {
    char *buf;
    size_t n;
    size_t len; /* length needed so far */
} json_out;

static void put(json_out *o, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void put(json_out *o, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *dst = o->len < o->n ? o->buf + o->len : NULL;
    size_t room = o->len < o->n ? o->n - o->len : 0;
    int k = vsnprintf(dst, room, fmt, ap);
    va_end(ap);
    if (k > 0)
        o->len += (size_t)k;
}

/* The shortest decimal form that reads back as the same float. */
static void put_float(json_out *o, float v)
{
    char tmp[32];
    for (int prec = 6; prec <= 9; prec++) {
        snprintf(tmp, sizeof tmp, "%.*g", prec, (double)v);
        if (strtof(tmp, NULL) == v)
            break;
    }
    put(o, "%s", tmp);
}

static void put_rgb(json_out *o, const char *key, const float v[3])
{
    put(o, "\"%s\":[", key);
    for (int c = 0; c < 3; c++) {
        put(o, "%s", c ? "," : "");
        put_float(o, v[c]);
    }
    put(o, "]");
}

static void put_string(json_out *o, const char *s)
{
    put(o, "\"");
    for (; *s; s++) {
        unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\')
            put(o, "\\%c", ch);
        else if (ch < 0x20)
            put(o, "\\u%04x", ch);
        else
            put(o, "%c", ch);
    }
    put(o, "\"");
}

size_t sam_profile_to_json(const sam_profile *profile, char *buf, size_t n)
{
    json_out o = {buf, buf ? n : 0, 0};
    if (o.n > 0)
        buf[0] = 0;
    char name[SAM_PROFILE_NAME_SIZE];
    memcpy(name, profile->name, sizeof name);
    name[sizeof name - 1] = 0;
    if (profile->kind == SAM_PROFILE_DIPOLE) {
        put(&o, "{\"kind\":\"dipole\",\"name\":");
        put_string(&o, name);
        put(&o, ",");
        put_rgb(&o, "sigma_s_prime", profile->sigma_s_prime);
        put(&o, ",");
        put_rgb(&o, "sigma_a", profile->sigma_a);
        put(&o, ",\"eta\":");
        put_float(&o, profile->eta);
        put(&o, "}");
    } else {
        put(&o, "{\"kind\":\"gaussians\",\"name\":");
        put_string(&o, name);
        put(&o, ",\"gaussians\":[");
        uint32_t count = profile->gaussian_count;
        if (count > SAM_PROFILE_MAX_GAUSSIANS)
            count = SAM_PROFILE_MAX_GAUSSIANS;
        for (uint32_t i = 0; i < count; i++) {
            put(&o, "%s{\"variance\":", i ? "," : "");
            put_float(&o, profile->variance[i]);
            put(&o, ",");
            put_rgb(&o, "weight", profile->weight[i]);
            put(&o, "}");
        }
        put(&o, "]}");
    }
    return o.len;
}
