/*
 * sam_thickness: per-vertex local thickness for the local-thickness
 * translucency technique (Barre-Brisebois and Bouchard, GDC 2011, as
 * shipped in Frostbite), which the runtime renders as SAM_TECHNIQUE_THICKNESS
 * (sam_runtime_set_thickness).
 *
 * The talk bakes thickness as ambient occlusion of the inverted normals.
 * Here every vertex casts the same fixed set of rays (Embree) into the
 * hemisphere around its inverted normal -n, from o = p - e n, just inside
 * the surface (e = `offset` times the bounding-box diagonal), and records
 * how deep below the vertex's tangent plane each ray's first hit lies:
 *
 *     t(v) = mm_per_unit * (1/N) sum_k (e + d_k cos theta_k),
 *
 * d_k the distance from o to the first hit along ray k (a miss, or a hit
 * beyond the cap C = the bounding-box diagonal, counts as C), theta_k the
 * ray's angle from -n. The N = strata^2 directions are a cosine-weighted
 * rule (sam_thickness_directions), so t is the cosine-weighted mean depth
 * of the far surface, an AO-like local average as the talk's bake is.
 *
 * Why this mean: the runtime turns t into light through the profile's slab
 * transmission G(t) (sam_profile_slab_transmission), which is defined for a
 * slab of normal thickness t. Every ray through a slab of depth D hits the
 * far face at depth exactly D, so a slab-like part (a thin shell such as an
 * ear) gets D for any ray count, where the plain mean of the hit distances
 * would be 2D (the cosine-weighted mean of 1/cos theta is 2) and their
 * harmonic mean 1.5D. Grazing rays, which leave finite parts through their
 * sides or miss, weigh by cos theta and barely move it. A curved part reads
 * thinner than its diameter: on a sphere of radius R the chord is
 * 2R cos theta, and t = R (exactly, for the rule below, up to e and the
 * tessellation). A thin part backed by a thick one (an ear modelled as a
 * bump on a head) reads thick: the mean follows the long rays, where light
 * follows the short ones. Misses count as the thickest the object can be,
 * as unoccluded rays do in the talk's inverted AO: no light.
 *
 * The result is a pure function of the inputs: each vertex's rays, their
 * order and the sum are fixed, so it is bit-identical for any thread count.
 *
 * Scans hold cracks and sheets a hair behind the surface: there every ray
 * of a vertex hits at once, and t reads a few hundredths of a millimetre
 * among neighbours of 6 to 16 mm (the Chinese dragon scan), a lone vertex
 * that G(t) turns into a white firefly. sam_thickness_ring_median, the
 * median of each vertex's t and its ring's, removes such lone vertices and
 * keeps a thin part several vertices wide; the programs apply it.
 *
 * Order: sam_thickness_compute, then sam_thickness_ring_median (optional).
 */
#ifndef SAM_THICKNESS_H
#define SAM_THICKNESS_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SAM_THICKNESS_MAX_STRATA 32

/* The surface thickness is measured on: the render vertices and triangles
 * of a closed mesh, as sam_mesh and samfile_data hold them. */
typedef struct sam_thickness_surface {
    uint32_t vertex_count;     /* >= 1 */
    const float *positions;    /* 3 * vertex_count, model units, finite */
    const float *normals;      /* 3 * vertex_count, pointing out (normalised here; not zero) */
    uint32_t triangle_count;   /* >= 1 */
    const uint32_t *triangles; /* 3 * triangle_count vertex indices < vertex_count */
} sam_thickness_surface;

/* What a vertex's rays are summed into. */
typedef enum sam_thickness_statistic {
    SAM_THICKNESS_MEAN = 0,   /* the cosine-weighted mean depth above: the technique's t */
    SAM_THICKNESS_THROUGH = 1 /* the mean depth of the rays within 30 degrees of -n (ring 0's when none
                               * is): how deep the far surface lies straight through. An ear modelled as
                               * a bump on a head reads as thin as the ear itself, where the mean over
                               * the hemisphere follows the long rays into the head */
} sam_thickness_statistic;

typedef struct sam_thickness_settings {
    uint32_t strata; /* rays per vertex = strata^2, 1..32 (default 8: 64 rays) */
    sam_thickness_statistic statistic; /* default SAM_THICKNESS_MEAN */
    float offset;    /* ray origins' depth below the surface, times the bounding-box diagonal, in
                      * (0, 0.01] (default 1e-4: clear of the vertex's own triangles in float, far
                      * thinner than any part the technique can tell from another) */
    int threads;     /* OpenMP threads, 0 = all cores (does not change the result) */
} sam_thickness_settings;

/* Called from the calling thread with the vertices done and the total, at
 * least every 4096 vertices; returning non-zero cancels the computation,
 * which then fails with SAM_ERR_INVALID_ARGUMENT "cancelled". May be NULL.
 * sam_build_progress_fn's shape, so the same progress bars fit. */
typedef int (*sam_thickness_progress_fn)(void *user, uint64_t done, uint64_t total);

/* Fills the defaults documented on sam_thickness_settings. Cannot fail. */
void sam_thickness_default_settings(sam_thickness_settings *settings);

/* The rule's directions in the frame where +z is the inverted normal:
 * strata^2 unit vectors written to `xyz` (3 floats each, caller's array),
 * ring i (0..strata-1) at cos^2 theta = 1 - (i + 0.5) / strata, the
 * midpoint of each equal-probability band of the cosine-weighted density,
 * so the rule averages anything linear in cos^2 theta exactly; strata
 * evenly spaced azimuths per ring, each ring turned by the golden fraction
 * of a step from the last, so no spoke lines up with another or with the
 * frame's axes. strata outside 1..32 writes nothing. Testing aid, for
 * tests that predict t. */
void sam_thickness_directions(uint32_t strata, float *xyz);

/* Local thickness in mm of every vertex of `surface` into `thickness_mm`
 * (vertex_count floats, the caller's), as described above; `settings` NULL
 * means the defaults. Takes about vertex_count * strata^2 Embree rays.
 * Errors: SAM_ERR_INVALID_ARGUMENT naming the value (no vertices or
 * triangles, a NULL array, a triangle index out of range, a position not
 * finite, a zero normal, mm_per_unit not finite and > 0, a setting out of
 * range; "cancelled" by `progress`), SAM_ERR_OUT_OF_MEMORY,
 * SAM_ERR_UNSUPPORTED (Embree failed, with its message). */
sam_status sam_thickness_compute(const sam_thickness_surface *surface, float mm_per_unit,
                                 const sam_thickness_settings *settings, sam_thickness_progress_fn progress,
                                 void *user, float *thickness_mm, sam_error *err);

/* The median of each vertex's thickness and its 1-ring's (`ring_offsets`,
 * vertex_count + 1 entries, and `ring`, the neighbours, as a .sam stores
 * them: samfile_data's adjacency_offsets and adjacency) into `out`; an even
 * count takes the mean of the middle two. `thickness_mm` and `out` are
 * vertex_count floats each, the caller's, and must not be the same array.
 * Errors: SAM_ERR_INVALID_ARGUMENT (a NULL array, the same array twice,
 * offsets that fall, a ring index out of range), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_thickness_ring_median(uint32_t vertex_count, const uint32_t *ring_offsets, const uint32_t *ring,
                                     const float *thickness_mm, float *out, sam_error *err);

#ifdef __cplusplus
}
#endif

#endif
