/*
 * Internal: double-precision evaluation, energy integrals and a radial
 * quadrature rule shared by the sam_profile_*.c files (presets and closed
 * forms, loaders, the Gaussian fit, the separable kernel).
 */
#ifndef SAM_PROFILE_INTERNAL_H
#define SAM_PROFILE_INTERNAL_H

#include <math.h>

#include "sam/sam_profile.h"

#define SAM_PROFILE_PI 3.14159265358979323846

/* Derived constants of one channel of a Jensen 2001 dipole. */
typedef struct sam_dipole_channel {
    double alpha;    /* reduced albedo alpha' = sigma_s' / sigma_t' */
    double sigma_tr; /* effective transport coefficient, mm^-1 */
    double z_r;      /* real source depth, mm */
    double z_v;      /* virtual source height, mm */
} sam_dipole_channel;

/* G(v, r) = exp(-r^2 / 2v) / (2 pi v), unit energy over the plane. */
static inline double sam_profile_gaussian(double v, double r)
{
    return exp(-r * r / (2 * v)) / (2 * SAM_PROFILE_PI * v);
}

/* Fresnel diffuse reflectance F_dr(eta) (Jensen 2001's fit). */
double sam_profile_fdr(double eta);

void sam_profile_dipole_channel(const sam_profile *p, int channel, sam_dipole_channel *d);

/* R_d(r) of one channel / of all three, in double precision. */
double sam_profile_eval_channel_d(const sam_profile *p, int channel, double r);
void sam_profile_eval_d(const sam_profile *p, double r, double out[3]);

/* 2 pi int_0^inf s R(s) ds (closed form). */
void sam_profile_total_d(const sam_profile *p, double out[3]);

/* 2 pi int_r^inf s R(s) ds and 2 pi int_0^r s R(s) ds, both in closed form
 * and each free of cancellation in its own range. */
void sam_profile_outer_d(const sam_profile *p, double r, double out[3]);
void sam_profile_inner_d(const sam_profile *p, double r, double out[3]);

/* Radius (double) where the remaining energy fraction of every non-zero
 * channel is <= tolerance; 0 when every channel is zero. */
double sam_profile_radius_d(const sam_profile *p, double tolerance);

/* Smallest length scale of the profile (mm): below it R is flat. */
double sam_profile_scale_min(const sam_profile *p);

/* A radius beyond which the profile holds a negligible (1e-12) fraction of
 * its energy: the upper end of every quadrature. */
double sam_profile_scale_max(const sam_profile *p);

/* Composite Simpson rule on a logarithmic grid r_k = r_lo e^{k h},
 * k = 0..n (n even, n + 1 nodes written to r and w) such that
 * sum_k w[k] f(r[k]) approximates int_0^inf r f(r) dr for an f that is flat
 * below r_lo and negligible beyond r_hi. */
void sam_profile_radial_rule(double r_lo, double r_hi, int n, double *r, double *w);

/* A radial function to fit: out[c] = f_c(r) for r >= 0 (mm). */
typedef void (*sam_profile_radial_fn)(const void *user, double r_mm, double out[3]);

/* The shared-variance 8-Gaussian fit of sam_profile_fit_gaussians (see
 * sam_profile_fit.c) for any radial function: the weights keep `total`
 * (2 pi int r f dr per channel) exactly, the variances start geometrically
 * over [var_lo, var_hi] (mm^2) and move within 16 times past it, and f is
 * integrated on a log grid over at least [r_lo, r_hi]. `measure` 1
 * minimises d'Eon eq. 10, int r (f - F)^2 dr; 3 minimises
 * int r^3 (f - F)^2 dr, the error of the energy per radius r f weighted by
 * r: finite for a profile with a 1/r peak (Christensen-Burley), and it
 * holds the tail, which carries the light through thick parts. `name` is
 * for messages. Errors: SAM_ERR_INVALID_ARGUMENT (no solvable set of
 * variances). */
sam_status sam_profile_fit_radial(sam_profile_radial_fn f, const void *user, const double total[3], int measure,
                                  double var_lo, double var_hi, double r_lo, double r_hi, const char *name,
                                  sam_gaussian_fit *fit, sam_error *err);

struct sam_image;

/* The previews of sam_profile_plot (sam_profile_preview.c), drawn into an
 * RGB image at pixel (x0, y0), the rest of the image untouched. A sphere
 * `diameter_mm` across, lit from behind and seen from the front, in a
 * side x side square (side >= 2); returns 0 when out of memory. */
int sam_profile_draw_sphere(const sam_profile *profile, float diameter_mm, struct sam_image *img, int x0, int y0,
                            int side);

/* A wedge lit from behind, seen from the front: its thickness grows from 0
 * at the left of the w x h strip to `thickness_mm` at the right. */
void sam_profile_draw_wedge(const sam_profile *profile, float thickness_mm, struct sam_image *img, int x0, int y0,
                            int w, int h);

/* Checks of one parameter; NULL when valid, else what is wrong with it
 * ("must be > 0", ...), for messages that add the file, key or line. */
const char *sam_profile_check_variance(double v);
const char *sam_profile_check_weight(double w);
const char *sam_profile_check_sigma_s_prime(double s);
const char *sam_profile_check_sigma_a(double s);
const char *sam_profile_check_eta(double eta);
const char *sam_profile_check_albedo(double a);

#endif
