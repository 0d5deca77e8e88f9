/* Internal: the sam_truth object shared by the ground truth's source files. */
#ifndef SAM_TRUTH_INTERNAL_H
#define SAM_TRUTH_INTERNAL_H

#include "sam/sam_truth.h"

#include <embree3/rtcore.h>

/* One lit sample as the queries read it: 36 bytes, kept in tree order. */
typedef struct truth_sample {
    float p[3];  /* model units */
    float n[3];  /* unit */
    float l[3];  /* L_d dA */
} truth_sample;

/* A node of the tree over the lit samples: what a query needs to skip it,
 * or to count it as one sample. */
typedef struct truth_node {
    float lo[3], hi[3];      /* the samples' positions' box, model units */
    float nlo[3], nhi[3];    /* their normals' box */
    float centre[3];         /* centroid weighted by the sum of L_d dA's channels */
    float l[3];              /* sum of L_d dA */
    uint32_t begin, end;     /* samples [begin, end) of lit */
} truth_node;

struct sam_truth {
    /* The scene, copied: sam_truth_sample recomputes any sample. */
    uint32_t vertex_count, triangle_count;
    float *positions, *normals;
    uint32_t *triangles;
    double *area_cdf;        /* triangle_count: cumulative area, mm^2 */
    double total_area;       /* mm^2 */
    float mm_per_unit;
    sam_light *lights;
    size_t light_count;
    int has_environment;
    float sh[9][3];
    float environment_rho_dt;
    float (*rho_dt)(const void *user, float n_dot_l);
    const void *rho_dt_user;

    uint64_t sample_count;
    uint64_t seed;
    double shift[2];         /* the lattice's random shift, from the seed */
    uint32_t area_samples;
    int threads;             /* resolved: > 0 */
    void (*progress)(void *user, const char *stage, double fraction);
    void *progress_user;

    float ray_offset;        /* model units */
    RTCDevice device;
    RTCScene scene;
    char embree_message[256];

    float radius_mm;         /* R_d's radius of influence */
    float table_scale;       /* table intervals per mm */
    float (*rd_table)[3];    /* SAM_TRUTH_RD_TABLE_SIZE + 1 entries: R_d at k / table_scale mm */

    truth_sample *lit;       /* lit_count, in tree order */
    uint64_t lit_count;
    truth_node *nodes;       /* node_count: a complete binary tree, children of i at 2i+1, 2i+2 */
    uint32_t node_count;
    float tolerance;         /* settings.far_field_tolerance */
    float far_ratio;         /* exp(sqrt(8 tolerance)): the R_d ratio a far node may span */

    double seconds;
};

/* Shared progress of a parallel loop: the calling thread (OpenMP thread 0)
 * reports, about every 1/200 of the work. */
typedef struct truth_progress {
    const sam_truth *truth;
    const char *stage;
    uint64_t done, total, next;
} truth_progress;

void truth_progress_step(truth_progress *p);
/* The final report (fraction exactly 1), outside the parallel region. */
void truth_progress_finish(const truth_progress *p);

/* Builds the Embree scene of the copied mesh (the device already exists).
 * Errors: SAM_ERR_UNSUPPORTED naming rtcGetDeviceError's code. */
sam_status truth_embree_scene(sam_truth *t, sam_error *err);

/* Position, unit shading normal and L_d (without dA) of sample i. */
void truth_sample_at(const sam_truth *t, uint64_t i, float p[3], float n[3], float l_d[3]);

/* Places every sample, computes L_d and keeps the lit ones in t->lit (in
 * sample order; the grid sorts them). Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status truth_compute_samples(sam_truth *t, sam_error *err);

/* The R_d table and the tree over t->lit (reordered into tree order).
 * Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status truth_build_tree(sam_truth *t, const sam_profile *profile, sam_error *err);

#endif
