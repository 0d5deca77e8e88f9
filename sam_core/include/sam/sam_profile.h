/*
 * sam_profile: radial diffusion profiles R_d(r) of translucent materials.
 *
 * A profile maps a distance r in millimetres to an RGB reflectance density in
 * mm^-2, so that 2*pi * integral_0^inf r R_d(r) dr is the total diffuse
 * reflectance. Two kinds exist:
 *   - a sum of Gaussians  R(r) = sum_i w_i G(v_i, r),
 *     G(v, r) = exp(-r^2 / 2v) / (2 pi v), variances v in mm^2
 *     (the d'Eon/Luebke six-Gaussian skin preset, or a user file);
 *   - the dipole of Jensen et al. 2001 from sigma_s', sigma_a (mm^-1) and eta
 *     (the measured media presets, or a user "custom dipole").
 * Materials as artists and measurements give them (Christensen and
 * Burley's normalised diffusion from a surface albedo and a mean free path
 * or scatter radius per channel; a tabulated R_d(r)) become a sum of eight
 * Gaussians fitted to them, which records its fit error.
 * Every profile also gives its total diffuse reflectance, a radius of
 * influence, an 8-Gaussian fit for texture-space diffusion (d'Eon App. A for
 * dipoles, exact for sums of <= 8 Gaussians) and 1D separable kernels for
 * screen-space diffusion (Jimenez et al., separable SSS: eq. 1, each
 * channel's marginal, or the best separable fit of eq. 2).
 *
 * A sam_profile is a plain value: no heap memory, copy it freely, no destroy.
 * Evaluation functions are pure and thread-safe.
 */
#ifndef SAM_PROFILE_H
#define SAM_PROFILE_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SAM_PROFILE_MAX_GAUSSIANS 32
#define SAM_PROFILE_FIT_GAUSSIANS 8
#define SAM_PROFILE_NAME_SIZE 64
#define SAM_KERNEL_MAX_TAPS 33
#define SAM_PROFILE_MAX_TABLE 4096 /* points of a tabulated R_d(r) */

/* Bound on the relative RMS error (d'Eon eq. 10) of the 8-Gaussian fit that
 * every preset meets in every channel (measured: at most 0.274%, skimmilk
 * blue; see sam_profile_fit.c). */
#define SAM_PROFILE_FIT_ERROR_BOUND 0.005f

/* Fraction of each channel's 1D (marginal) energy that a separable kernel
 * leaves outside its tap range +-width_mm. */
#define SAM_PROFILE_KERNEL_TAIL 0.01

typedef enum sam_profile_kind {
    SAM_PROFILE_GAUSSIAN_SUM = 0,
    SAM_PROFILE_DIPOLE = 1
} sam_profile_kind;

typedef struct sam_profile {
    sam_profile_kind kind;
    char name[SAM_PROFILE_NAME_SIZE]; /* preset name, "custom", or the file's "name" or base name */

    /* SAM_PROFILE_GAUSSIAN_SUM */
    uint32_t gaussian_count;                        /* 1..SAM_PROFILE_MAX_GAUSSIANS */
    float variance[SAM_PROFILE_MAX_GAUSSIANS];      /* mm^2, > 0 */
    float weight[SAM_PROFILE_MAX_GAUSSIANS][3];     /* RGB, >= 0 */

    /* SAM_PROFILE_DIPOLE */
    float sigma_s_prime[3]; /* reduced scattering, mm^-1, > 0 */
    float sigma_a[3];       /* absorption, mm^-1, >= 0 */
    float eta;              /* relative index of refraction, > 0 */

    /* A sum of Gaussians fitted to another material (sam_profile_burley,
     * sam_profile_table): per channel, the largest difference over r
     * between the energy landing within r of the fit and of that material,
     * as a fraction of the channel's total; 0 otherwise. */
    float fit_source_error[3];
} sam_profile;

/* A fit with shared variances: one blur per Gaussian, RGB weights. */
typedef struct sam_gaussian_fit {
    uint32_t count;                              /* number of Gaussians used, <= 8 */
    float variance[SAM_PROFILE_FIT_GAUSSIANS];   /* mm^2, ascending */
    float weight[SAM_PROFILE_FIT_GAUSSIANS][3];  /* RGB */
} sam_gaussian_fit;

/* A 1D separable kernel for two-pass screen-space blurring. */
typedef struct sam_separable_kernel {
    uint32_t taps;                              /* odd, 9..33 */
    float offset_mm[SAM_KERNEL_MAX_TAPS];       /* ascending, centre tap at taps/2 is 0 */
    float weight[SAM_KERNEL_MAX_TAPS][3];       /* RGB; each channel sums to 1 */
    float width_mm;                             /* Jimenez "width": tap range is +-width_mm */
    float strength[3];                          /* Jimenez "strength" per channel */
    float falloff[3];                           /* Jimenez "falloff" per channel */
} sam_separable_kernel;

/* Number of built-in presets and the i-th name (NULL past the end).
 * Presets: "skin" (d'Eon six Gaussians) and the Jensen 2001 media of
 * DESIGN.md ("apple", "chicken1", ..., "wholemilk"). */
size_t sam_profile_preset_count(void);
const char *sam_profile_preset_name(size_t index);

/* Fills `out` with a preset, name compared case-insensitively.
 * Errors: SAM_ERR_INVALID_ARGUMENT (unknown name; the message lists the
 * valid names). */
sam_status sam_profile_preset(const char *name, sam_profile *out, sam_error *err);

/* A custom dipole, named "custom". Errors: SAM_ERR_INVALID_ARGUMENT naming
 * the parameter and value (non-finite, sigma_s' <= 0, sigma_a < 0, eta <= 0
 * or eta outside about (0.733, 3.85), where Jensen's F_dr(eta) leaves
 * (-1, 1) and the dipole's boundary term breaks down). */
sam_status sam_profile_dipole(const float sigma_s_prime[3], const float sigma_a[3], float eta,
                              sam_profile *out, sam_error *err);

/* A sum of `count` Gaussians, named "custom"; `variance` has count elements
 * (mm^2), `weight` count RGB triples. Errors: SAM_ERR_INVALID_ARGUMENT
 * (count outside 1..32, a variance not > 0, a weight < 0, a non-finite
 * value, or every weight zero). */
sam_status sam_profile_gaussian_sum(uint32_t count, const float *variance, const float (*weight)[3],
                                    sam_profile *out, sam_error *err);

/* How sam_profile_burley reads its distances. */
typedef enum sam_burley_distance {
    SAM_BURLEY_MEAN_FREE_PATH = 0, /* the volume mean free path l: d = l / s(A) */
    SAM_BURLEY_SCATTER_RADIUS = 1  /* d itself (Unity HDRP's "scattering distance") */
} sam_burley_distance;

/* Christensen and Burley's (2015) normalised diffusion,
 *   R(r) = A (e^{-r/d} + e^{-r/3d}) / (8 pi d r)   per channel,
 * whose total diffuse reflectance is exactly the surface albedo A, as a sum
 * of eight Gaussians (shared variances) fitted to its energy per radius
 * r R(r), weighted by r (int r^3 (R - F)^2 dr), with the total kept
 * exactly. `albedo` in [0, 1] (not all 0), `distance_mm` > 0, read as
 * `distance` says. The profile is named "burley"; its fit_source_error
 * holds the fit's error: the largest difference over r between the energy
 * within r of the fit and of Burley's profile, as a fraction of the
 * channel's total (0.3% for a grey material, 1.7% for skin-like channels
 * whose shapes differ tenfold; see docs/materials.md). Takes a few
 * milliseconds.
 * Errors: SAM_ERR_INVALID_ARGUMENT naming the parameter and value. */
sam_status sam_profile_burley(const float albedo[3], const float distance_mm[3], sam_burley_distance distance,
                              sam_profile *out, sam_error *err);

/* Burley's shape d = l / s(A) for mean free path l (mm) and surface albedo
 * A, with their fit for diffuse surface transmission
 * s = 1.9 - A + 3.5 (A - 0.8)^2. */
double sam_profile_burley_shape(float albedo, float mean_free_path_mm);

/* A measured profile: R_d at `count` radii (2..SAM_PROFILE_MAX_TABLE;
 * `radius_mm` ascending, >= 0; `rd` RGB mm^-2, >= 0, not all 0), read as
 * exponential between its points (linear where one is 0), R_d(r_0) below
 * the first and 0 past the last,
 * as a sum of eight Gaussians fitted like sam_profile_burley's (total
 * reflectance: the interpolant's, exactly). Named "table".
 * Errors: SAM_ERR_INVALID_ARGUMENT naming the point and value. */
sam_status sam_profile_table(uint32_t count, const float *radius_mm, const float (*rd)[3], sam_profile *out,
                             sam_error *err);

/* Loads a user profile from a file. A name ending in ".json" (any case), or
 * a file whose first non-blank character is '{', is JSON:
 *   {"type": "gaussians", "name": "my_skin",
 *    "gaussians": [{"variance": 0.0064, "weight": [0.233, 0.455, 0.649]}, ...]}
 *   {"type": "dipole", "sigma_s_prime": [r, g, b], "sigma_a": [r, g, b], "eta": 1.3}
 * ("kind" is accepted for "type", so sam_profile_to_json's output loads
 * back; "name" is optional; any other key is an error.) Otherwise text:
 * '#' starts a comment; either 1..32 lines "gaussian <variance_mm2> <w_r>
 * <w_g> <w_b>", or a line "dipole" followed by "sigma_s_prime r g b",
 * "sigma_a r g b" and "eta x" lines; optionally "name <word>".
 * Values must be finite floats with variance > 0, weights >= 0 (not all 0),
 * sigma_s' > 0, sigma_a >= 0, eta > 0 and |F_dr(eta)| < 1 (eta in about
 * (0.733, 3.85)); eta is required in files. The name defaults to the file
 * name without directory and extension (at most 63 bytes).
 * Errors: SAM_ERR_IO (cannot read), SAM_ERR_FORMAT naming the file and the
 * key path (e.g. "gaussians[2].weight[1]") or line, and the value found. */
sam_status sam_profile_load(const char *path, sam_profile *out, sam_error *err);

/* Parses a JSON profile held in memory (`size` bytes, no NUL needed), in
 * the file format above or as written by sam_profile_to_json (e.g. the
 * "material" of a .sam's INFO chunk). `name` is used in messages (may be
 * NULL). Errors: SAM_ERR_FORMAT naming the key and value,
 * SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_profile_parse_json(const char *text, size_t size, const char *name, sam_profile *out,
                                  sam_error *err);

/* A preset name, else a path to a profile file (sam_profile_load).
 * Errors: those of sam_profile_load; SAM_ERR_IO when the spec is neither a
 * preset nor a readable file (the message lists the presets). */
sam_status sam_profile_from_spec(const char *spec, sam_profile *out, sam_error *err);

/* R_d(r) in mm^-2 for r >= 0 (mm; a negative r is read as |r|). */
void sam_profile_eval(const sam_profile *profile, float r_mm, float out_rgb[3]);

/* The per-channel terms of a dipole profile, for evaluators that mirror
 * sam_profile_eval elsewhere (GPU shaders):
 *   R_d(r) = alpha / (4 pi) * (P(z_r) + P(z_v)),
 *   P(z) = z (1 + sigma_tr d) e^{-sigma_tr d} / d^3,  d = sqrt(r^2 + z^2).
 * All zero for a sum of Gaussians. */
typedef struct sam_dipole_terms {
    float alpha[3];    /* reduced albedo sigma_s' / sigma_t' */
    float sigma_tr[3]; /* mm^-1 */
    float z_r[3];      /* mm */
    float z_v[3];      /* mm */
} sam_dipole_terms;
void sam_profile_dipole_terms(const sam_profile *profile, sam_dipole_terms *out);

/* Total diffuse reflectance 2 pi int r R_d(r) dr per channel (closed form). */
void sam_profile_total_reflectance(const sam_profile *profile, float out_rgb[3]);

/* The light a slab of thickness t_mm lets through when one face is lit
 * uniformly: G(t) = 2 pi int_t^inf s R_d(s) ds per channel, from the
 * profile's own R_d with the entry-to-exit distance s = sqrt(t^2 + rho^2)
 * (the law SAM's form factors use); G(0) is the total diffuse reflectance
 * and G falls to 0 as t grows. The local-thickness technique (sam_runtime.h)
 * scales the back side's light by it. Closed form (exact for both kinds); a
 * negative t is read as |t|. */
void sam_profile_slab_transmission(const sam_profile *profile, float t_mm, float out_rgb[3]);

/* Smallest radius (mm) beyond which the remaining radial energy
 * 2 pi int_r^inf s R_d(s) ds is at most `tolerance` times the channel's
 * total, maximised over the non-zero channels. tolerance in (0, 1); 0 for
 * tolerance >= 1, +infinity for tolerance <= 0 or NaN. Bisection on the
 * closed-form remaining energy, so the bound holds to float rounding. */
float sam_profile_radius(const sam_profile *profile, float tolerance);

/* The 8-Gaussian fit with variances shared by R, G and B: exact for a sum
 * of <= 8 distinct Gaussians (count may then be < 8), otherwise a fit
 * seeded by d'Eon App. A whose weights keep each channel's total
 * reflectance (eq. 9); error below SAM_PROFILE_FIT_ERROR_BOUND for the
 * presets. Takes a few milliseconds. Errors: SAM_ERR_INVALID_ARGUMENT. */
sam_status sam_profile_fit_gaussians(const sam_profile *profile, sam_gaussian_fit *fit,
                                     sam_error *err);

/* Relative RMS power error of a fit against the profile (d'Eon eq. 10)
 * for one channel (0..2), by numerical integration. 0 when both are zero in
 * that channel; NaN for an invalid channel or fit. */
float sam_profile_fit_error(const sam_profile *profile, const sam_gaussian_fit *fit, int channel);

/* The separable kernel with `taps` samples (odd, 9..33; callers use 17):
 * Jimenez eq. 1 on the 1D marginal of the profile's red channel, with
 * width, strength and falloff fitted to each channel's own marginal (see
 * sam_profile_kernel.c). Offsets are in mm, quadratically spaced over
 * +-width_mm; every channel's weights sum to 1 (the total reflectance is
 * applied separately). Takes a few milliseconds.
 * Errors: SAM_ERR_INVALID_ARGUMENT (taps, or a profile with no energy). */
sam_status sam_profile_separable_kernel(const sam_profile *profile, uint32_t taps,
                                        sam_separable_kernel *kernel, sam_error *err);

/* The direct alternative to eq. 1: the same taps, offsets and width, and
 * each channel's weights the masses of its own normalised 1D marginal over
 * the tap cells (so each channel sums to 1; strength and falloff are 1).
 * Where eq. 1 reuses red's shape for green and blue (34% and 43% eq.-3
 * error for skin), this matches every channel to within the 1% tail.
 * Matching the marginal makes one pass exact across a straight edge, but
 * its 2D product s(x) s(y) is not the best separable approximation of the
 * 2D kernel: for skin (17 taps) its 2D error (sam_profile_kernel_error_2d)
 * is about 0.50 / 0.22 / 0.12 in R / G / B, against 0.41 / 0.17 / 0.09 for
 * sam_profile_separable_kernel_fit2d. Takes a few milliseconds.
 * Errors: those of sam_profile_separable_kernel. */
sam_status sam_profile_separable_kernel_direct(const sam_profile *profile, uint32_t taps,
                                               sam_separable_kernel *kernel, sam_error *err);

/* The separable kernel of Jimenez eq. 2: the same taps, offsets and width
 * as the two above, and each channel's weights s the non-negative,
 * symmetric, energy-conserving (sum 1) minimiser of ||S - s s^T||_F, where
 * S_ab is the mass of the channel's profile, normalised by its total
 * reflectance, over cell a times cell b (the 2D kernel that the two passes
 * approximate). S comes from sam_profile_fit_gaussians (a Gaussian's mass
 * over a rectangle is a product of erf differences): exact for sums of at
 * most 8 Gaussians (skin), within that fit's error (< 0.3%) for dipoles.
 * Strength and falloff are 1. Deterministic; takes about 1.5 ms plus
 * sam_profile_fit_gaussians (up to about 25 ms for the dipole presets).
 * Errors: those of sam_profile_separable_kernel and
 * sam_profile_fit_gaussians. */
sam_status sam_profile_separable_kernel_fit2d(const sam_profile *profile, uint32_t taps,
                                              sam_separable_kernel *kernel, sam_error *err);

/* Relative error (Jimenez eq. 3, as sqrt(sum (T_k - w_k)^2 / sum T_k^2)) of
 * one channel (0..2) of a kernel against the target tap weights T_k: the
 * mass of the channel's normalised 1D marginal over each tap's cell (between
 * the midpoints to its neighbours, the outer cells ending at +-width_mm).
 * NaN for an invalid channel or kernel. */
float sam_profile_kernel_error(const sam_profile *profile, const sam_separable_kernel *kernel,
                               int channel);

/* Relative RMS error of a kernel's 2D product against the exact 2D kernel
 * for one channel (0..2): sqrt(sum_ab (S_ab - w_a w_b)^2 / sum_ab S_ab^2)
 * over all pairs of tap cells (the cells of sam_profile_kernel_error), S_ab
 * the mass of the channel's profile, normalised by its total reflectance,
 * over cell a times cell b. S is integrated from the profile itself (in
 * polar coordinates: the radial integral is closed form, the angle a
 * Gauss-Legendre rule per edge piece), to about 1e-13 relative for the
 * presets, sharp peaks included. 0 when the channel and its weights are all
 * zero, +infinity when only the channel is zero; NaN for an invalid channel
 * or kernel. Takes about 2 ms for 33 taps. */
float sam_profile_kernel_error_2d(const sam_profile *profile, const sam_separable_kernel *kernel,
                                  int channel);

/* Energy of the profile inside the strip |x| <= x_mm, i.e. the mass of its
 * 1D marginal int R(sqrt(x^2 + y^2)) dy over [-x_mm, x_mm] (what one pass of
 * a separable blur sees); tends to the total reflectance for large x_mm.
 * Numerical (Simpson rule), relative accuracy about 1e-7. */
void sam_profile_marginal_mass(const sam_profile *profile, float x_mm, float out_rgb[3]);

/* Writes a JSON object describing the profile (kind, name, parameters) into
 * buf (size n), e.g. for a .sam INFO chunk. Returns the length it needed
 * (excluding NUL), like snprintf. */
size_t sam_profile_to_json(const sam_profile *profile, char *buf, size_t n);

struct sam_image;

/* Draws `profile` into a new 2 height x 3/2 height RGB image (linear; the
 * caller destroys it with sam_image_destroy), labelled: top left, a point
 * of light seen through the material out to the radius holding 99% of the
 * energy (the extent); top right, the energy per log radius r^2 R_d(r) per
 * channel over three decades of r up to the extent, the profile solid and
 * its 8-Gaussian fit dotted, with ticks in mm; below, the material on a
 * sphere half the extent across and a wedge from 0 to the extent thick,
 * both lit from behind and seen from the front (sam_profile_preview.c).
 * `extent_mm` (may be NULL) gets the extent. Takes about a second at
 * height 512. `img` is zeroed on failure. Errors: SAM_ERR_INVALID_ARGUMENT
 * (height outside 64..4096), and those of sam_profile_fit_gaussians and
 * sam_image_create, SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_profile_plot(const sam_profile *profile, uint32_t height, struct sam_image *img, float *extent_mm,
                            sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
