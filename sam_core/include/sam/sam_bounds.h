/*
 * sam_bounds: where a cluster of surface points lies against a receiving
 * point, from the cluster's box of positions and box of unit normals alone.
 * The ground truth skips and merges its samples with it and the builder
 * chooses its cuts with it, so both apply the same front/back rules
 * (eq. 13-14 of the SAM paper) to whole clusters.
 */
#ifndef SAM_BOUNDS_H
#define SAM_BOUNDS_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Ranges over every point x in [lo, hi] with normal m in [nlo, nhi], for a
 * receiver at p with unit normal n, computed box corner by corner (so each
 * range contains the members' values up to float rounding). */
typedef struct sam_bounds_range {
    float near2, far2;  /* squared distance from p to the box's nearest and farthest points */
    float dn_lo, dn_hi; /* (x - p).n: eq. 13 holds for every member when dn_hi < 0, none when dn_lo >= 0 */
    float nn_lo, nn_hi; /* m.n: eq. 14 holds for every member when nn_hi < 0, none when nn_lo >= 0 */
} sam_bounds_range;

/* Fills `out`. No argument may be NULL; all are 3 floats. */
void sam_bounds_classify(const float lo[3], const float hi[3], const float nlo[3], const float nhi[3],
                         const float p[3], const float n[3], sam_bounds_range *out);

#ifdef __cplusplus
}
#endif

#endif
