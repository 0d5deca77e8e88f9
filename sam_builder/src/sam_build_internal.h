/* Internal: the build context shared by the builder's source files. */
#ifndef SAM_BUILD_INTERNAL_H
#define SAM_BUILD_INTERNAL_H

#include "sam/sam_build.h"

/* R_d sampled on a uniform grid in r: RGB and their mean, linear interpolation. */
#define SAM_RD_TABLE_SIZE 16384

struct sam_build_context {
    const sam_mesh *mesh;
    const sam_profile *profile;
    float mm_per_unit;
    sam_build_settings settings;
    uint32_t candidates;     /* C resolved from settings */

    float *pos;              /* 3 * topo_count: topo positions in mm */
    float *fan_area;         /* topo_count: F' in mm^2 */
    float *pair_cdf;         /* ring-aligned: cumulative quad area up to ring entry k (mm^2) */
    float max_fan_area;      /* mm^2 */
    float max_edge;          /* longest ring edge, mm */

    float search_radius;     /* mm: R_d energy beyond it below the tolerance */
    float table_radius;      /* mm: the table covers [0, table_radius] */
    float table_inv_step;
    float (*table)[4];       /* SAM_RD_TABLE_SIZE + 1 entries: R, G, B, mean */
    float *envelope;         /* SAM_RD_TABLE_SIZE + 1: max of the mean over [j, end]: a non-increasing bound */
};

/* R_d at r mm: RGB and mean (table inside table_radius, exact beyond). */
void sam_build_rd(const sam_build_context *ctx, float r, float out[4]);

/* Mean R_d at r: the cheap estimate's profile term. */
float sam_build_rd_mean(const sam_build_context *ctx, float r);

/* The smallest radius beyond which every mean R_d (table) is below
 * `threshold`; table_radius when none is. */
float sam_build_bound_radius(const sam_build_context *ctx, float threshold);

/* The `samples` points (3 floats each) on vertex o's reduced fan that every
 * form factor of o shares: drawn from the stream (seed, o), so each K_oi is
 * the same whichever caller computes it, and candidates of one vertex are
 * ranked with common random numbers. */
void sam_build_receiver_points(const sam_build_context *ctx, uint32_t o, uint32_t samples, uint64_t seed,
                               float *points);

/* K_oi from o's shared points and a stream (seed, o, i) for points on F'_i. */
void sam_build_form_factor_from(const sam_build_context *ctx, uint32_t o, const float *points, uint32_t i,
                                uint32_t samples, uint64_t seed, float k[3], float *k_error);

#endif
