/*
 * sam_truth: the ground truth of translucency (SAM paper Sec. 5.1), on the
 * CPU: the back-side integral of eq. 7,
 *
 *   L_o-(x_o) = integral over A_- of R_d(|x_i - x_o|) L_d(x_i) dx_i,
 *
 * where A_- is the back side of x_o by eq. 13-14: the points x_i with
 * (x_i - x_o) . n_o < 0 and n_i . n_o < 0.
 *
 * Method. sam_truth_create spreads `sample_count` samples uniformly in area
 * over the mesh, each standing for dA = (total area in mm^2) / sample_count,
 * and computes L_d (eq. 4) at each exactly as the runtime's irradiance pass
 * does (shaders/irradiance.comp), but with exact visibility:
 *   L_d = sum over lights of E_l(x, n) rho_dt(c_l) V_l(x)
 *       + E_env(n) environment_rho_dt
 * with E_l from sam_light_irradiance (unoccluded, exact for point, spot,
 * directional and polygonal area lights), c_l the cosine the runtime gives
 * rho_dt (n . l for point and spot lights, -n . direction for directional
 * ones, the cosine towards the mean of the polygon's vertices for area
 * lights, clamped to [0, 1]), V_l the visibility by Embree rays (only for
 * lights whose `shadow` flag is set: a light that casts no shadow in the
 * scene casts none here), and E_env the environment's SH-9 irradiance
 * (sam_light_sh9_irradiance; the runtime shadows the environment nowhere,
 * nor does this). The normal n of a sample is the barycentric interpolation
 * of the vertex normals, renormalised: what the runtime shades with.
 * Visibility: point and spot lights one ray to the light, directional lights
 * one ray against the light's direction, area lights `area_light_samples`
 * stratified points on the polygon, whose visible fraction, weighted by each
 * point's unoccluded contribution (cos cos / r^2), multiplies the exact
 * unoccluded irradiance (a ratio estimator: exact when the light is fully
 * visible or fully hidden). Rays start at the sample moved along its
 * triangle's geometric normal (turned to the side of the shading normal) by
 * SAM_TRUTH_RAY_OFFSET times the mesh's bounding-box diagonal.
 *
 * Sample placement. Sample i sits at the point of a randomly shifted
 * rank-1 lattice: u_i = (i + s_0) / N picks the triangle through the area
 * CDF (so triangle t gets its share of samples to within one) and, rescaled
 * inside t's interval, the first coordinate inside t; the second is
 * frac(s_1 + i phi) (phi the golden ratio). (u, v) maps onto the triangle
 * with the area-preserving map b = (1 - sqrt u, sqrt u (1 - v), sqrt u v).
 * The shifts s_0, s_1 come from `seed`. Each sample is uniform in area, so
 * the estimate is unbiased; the samples of a triangle form a lattice, not
 * independent draws, so the error of a smooth integrand falls much faster
 * than Monte Carlo's N^-1/2 (the paper's truth sums texture-space texels, a
 * regular grid, for the same reason). The per-sample random numbers of the
 * area lights' points come from a stream seeded by (seed, i). Every sample
 * and every query is computed independently and summed in a fixed order, so
 * the same scene, seed and count give bit-identical results on any number
 * of threads.
 *
 * Default sample count (sample_count = 0): mean spacing h = sqrt(v) / 4,
 * v the smallest variance of the profile's 8-Gaussian fit
 * (sam_profile_fit_gaussians) whose weight is at least
 * SAM_TRUTH_RELEVANT_WEIGHT of its channel's total in some channel; so
 * N = 16 * total area (mm^2) / v, clamped to
 * [SAM_TRUTH_MIN_SAMPLES, SAM_TRUTH_MAX_SAMPLES]. On a 60 mm slab 1.5 mm
 * thick under a two-Gaussian profile (v = 0.5 and 2 mm^2), that spacing
 * (about 250k samples) gave 0.13% RMS error against the closed form over 8
 * seeds, twice the spacing 1.1%, and independent uniform samples 5.6% at
 * the same count. Skin (v = 0.0064 mm^2) asks for 2500 samples per mm^2,
 * so anything above about 1700 mm^2 gets the upper bound.
 *
 * Queries. Only samples whose L_d is non-zero are kept, in a complete
 * binary tree of median splits (leaves of 16 samples) that stores each
 * node's box of positions, box of normals, sum of L_d dA and centroid. A
 * query descends it and skips nodes out of the profile's radius of
 * influence (sam_profile_radius with SAM_TRUTH_RADIUS_TOLERANCE), wholly
 * in front of its tangent plane (eq. 13) or with every normal facing its
 * way (eq. 14), and tests every sample of the leaves it reaches. With
 * far_field_tolerance > 0, a node wholly on the back side and in reach
 * whose R_d changes by a ratio of at most exp(sqrt(8 tolerance)) between
 * its nearest and its farthest point counts as one sample of its summed
 * L_d dA at its centroid. Evaluating a falloff at the centroid instead of
 * averaging it errs to second order, about (ln ratio)^2 / 8 of the node's
 * contribution for an exponential, so each node stays within about the
 * tolerance (tests/test_truth.c measures it on a marble ball; the
 * hierarchical idea of Jensen and Buhler 2002). R_d comes from a table of
 * SAM_TRUTH_RD_TABLE_SIZE + 1 entries over [0, radius] with linear
 * interpolation: its error is at most 6.5e-5 of R_d(0) for the presets
 * (2.8e-4 for cream, the sharpest peak).
 *
 * Cost: create is one ray per sample per shadowed point, spot or
 * directional light and area_light_samples rays per shadowed area light;
 * an exact query costs one test per lit sample within the radius (the far
 * field makes wide profiles much cheaper: see sam_compare's README
 * section for measured times). Measured exact on 2
 * busy cores, a point and an area light (17 rays per sample), 20k
 * triangles: 0.5-0.9 million samples/s; queries at the vertices of a
 * 60 mm ear 2 mm thick: skin (4.2M samples) about 700/s, marble (1.1M
 * samples, 48 mm radius) about 2100/s; a 46 mm marble sphere, which the
 * radius spans whole, about 140/s. Memory: 36 bytes per sample during
 * create, 36 bytes per lit sample after.
 *
 * Units: positions in model units; distances in R_d in mm (mm_per_unit);
 * dA in mm^2; light irradiance as sam_light.h gives it. The result is in the
 * units of L_d (R_d in mm^-2 times mm^2): the runtime's T of eq. 12.
 *
 * A sam_truth owns its samples and Embree scene; the caller owns it and
 * frees it with sam_truth_destroy. It copies the mesh, lights and SH of the
 * scene given to sam_truth_create and keeps no pointer into them, except
 * rho_dt and rho_dt_user, which sam_truth_sample calls again: they must
 * stay valid as long as it may be called. Calls on one sam_truth must not
 * run concurrently (queries parallelise themselves and update the time
 * counter). No globals.
 */
#ifndef SAM_TRUTH_H
#define SAM_TRUTH_H

#include "sam/sam_common.h"
#include "sam/sam_light.h"
#include "sam/sam_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Remaining radial energy fraction beyond the radius of influence. */
#define SAM_TRUTH_RADIUS_TOLERANCE 1e-4f
/* Bounds of the automatic sample count. */
#define SAM_TRUTH_MIN_SAMPLES (1ull << 16)
#define SAM_TRUTH_MAX_SAMPLES (1ull << 22)
/* A fit Gaussian counts for the automatic count above this share of its channel. */
#define SAM_TRUTH_RELEVANT_WEIGHT 0.05f
/* Visibility points per area light per sample when the settings give 0. */
#define SAM_TRUTH_DEFAULT_AREA_SAMPLES 16u
/* Ray origin offset, relative to the bounding-box diagonal. */
#define SAM_TRUTH_RAY_OFFSET 1e-5f
/* R_d table intervals over [0, radius]. */
#define SAM_TRUTH_RD_TABLE_SIZE 16384

typedef struct sam_truth_scene {
    uint32_t vertex_count;
    const float *positions;      /* 3 * vertex_count, model units, finite */
    const float *normals;        /* 3 * vertex_count, unit (finite, non-zero; renormalised) */
    uint32_t triangle_count;
    const uint32_t *triangles;   /* 3 * triangle_count indices < vertex_count */
    float mm_per_unit;           /* > 0 */
    const sam_profile *profile;
    const sam_light *lights;     /* light_count entries; may be NULL when light_count is 0 */
    size_t light_count;
    const float (*sh)[3];        /* the environment's radiance SH-9 (sh[9][3]) or NULL: no environment */
    float environment_rho_dt;    /* what the runtime multiplies the SH irradiance by
                                  * (sam_runtime_environment_rho_dt); finite, >= 0 */
    /* rho_dt for a light at cosine n_dot_l (sam_runtime_rho_dt); NULL = 1.
     * Called from several threads at once during sam_truth_create. */
    float (*rho_dt)(const void *user, float n_dot_l);
    const void *rho_dt_user;
} sam_truth_scene;

typedef struct sam_truth_settings {
    uint64_t sample_count;        /* surface samples, uniform in area, <= UINT32_MAX;
                                   * 0 = automatic (see the overview) */
    uint64_t seed;                /* same seed + count = same result on any thread count */
    uint32_t area_light_samples;  /* visibility points per area light per sample; 0 = 16 */
    int threads;                  /* >= 0; 0 = OpenMP's default */
    /* 0: every sample is summed (exact). In [0, 0.5): distant groups of
     * samples are summed as one where that errs by about this fraction of
     * their contribution (see Queries above). */
    float far_field_tolerance;
    /* May be NULL. Called from the calling thread only, with stage
     * "irradiance" (sam_truth_create) or "translucency" (queries) and a
     * fraction in [0, 1] that ends at exactly 1. */
    void (*progress)(void *user, const char *stage, double fraction);
    void *progress_user;
} sam_truth_settings;

typedef struct sam_truth sam_truth;

/* Zero sample count (automatic), seed 1, 16 area-light points, default
 * threads, no progress. */
void sam_truth_default_settings(sam_truth_settings *settings);

/* Places the samples and computes their L_d (the expensive part: one ray
 * per shadowed point/spot/directional light and area_light_samples per
 * shadowed area light, per sample). `*out` receives a new sam_truth (NULL
 * on failure) that the caller frees with sam_truth_destroy; `scene` and
 * `settings` are only read during the call.
 * Errors: SAM_ERR_INVALID_ARGUMENT naming the value (a NULL scene, settings,
 * out or array; a count of 0; a non-finite or zero normal, non-finite
 * position, or index out of range, with its element; mm_per_unit not > 0;
 * a light with an unknown type, non-finite or negative color/intensity, or
 * an area light with vertex_count outside 3..SAM_AREA_LIGHT_MAX_VERTICES;
 * environment_rho_dt not finite and >= 0; a sample count above UINT32_MAX;
 * negative threads; far_field_tolerance outside [0, 0.5); a profile whose fit fails; a mesh of zero area),
 * SAM_ERR_OUT_OF_MEMORY, SAM_ERR_UNSUPPORTED (Embree failed: the message
 * gives rtcGetDeviceError's code). */
sam_status sam_truth_create(const sam_truth_scene *scene, const sam_truth_settings *settings,
                            sam_truth **out, sam_error *err);

/* Frees everything; NULL is allowed. */
void sam_truth_destroy(sam_truth *truth);

/* Accessors; each gives 0 for a NULL truth.
 * The number of surface samples (the resolved automatic count). */
uint64_t sam_truth_sample_count(const sam_truth *truth);

/* Samples whose L_d is non-zero: the only ones queries visit. */
uint64_t sam_truth_lit_sample_count(const sam_truth *truth);

/* dA of one sample, mm^2. */
double sam_truth_sample_area(const sam_truth *truth);

/* Seconds spent so far in sam_truth_create, the queries and sam_truth_sample. */
double sam_truth_seconds(const sam_truth *truth);

/* Sample `index` (< sam_truth_sample_count) as create placed it: position
 * (model units), normal (unit) and L_d (eq. 4, without dA), recomputed by
 * the same code and random numbers as in create, so it is bit-identical to
 * what the queries sum. Any of the outputs may be NULL. For tests and
 * visualisation; costs one sample's rays. Not for concurrent use with
 * queries on the same truth.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL truth, index out of range). */
sam_status sam_truth_sample(sam_truth *truth, uint64_t index, float position[3], float normal[3],
                            float l_d[3], sam_error *err);

/* Eq. 7 at `count` query points (positions in model units, normals unit or
 * zero; 3 * count floats each): out_rgb[3 q + c] = sum over the lit samples
 * i on the back side of query q ((x_i - x_o) . n_o < 0 and
 * n_i . n_o < 0) within the radius of influence of
 * R_d(|x_i - x_o| mm) L_d(x_i) dA. Query normals are renormalised; a zero
 * normal (an uncovered G-buffer texel) gives 0. Parallel over queries;
 * progress reported as "translucency".
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL truth or array, count 0, a
 * non-finite position or normal: the message names the query and value);
 * out_rgb is left unspecified on failure. */
sam_status sam_truth_translucency(sam_truth *truth, size_t count, const float *positions, const float *normals,
                                  float *out_rgb, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
