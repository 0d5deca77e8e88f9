/* Internal: the build context shared by the builder's source files. */
#ifndef SAM_BUILD_INTERNAL_H
#define SAM_BUILD_INTERNAL_H

#include <math.h>

#include "sam/sam_bounds.h"
#include "sam/sam_build.h"
#include "sam/sam_rng.h"

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
    float *fan_reach;        /* 2 * topo_count: how far the fan's corners lie from the vertex (mm), and
                              * their interpolated normals from its normal (sam_build_fan_side) */
    float *pair_cdf;         /* ring-aligned: cumulative quad area up to ring entry k (mm^2) */
    float max_fan_area;      /* mm^2 */
    float max_edge;          /* longest ring edge, mm */

    float search_radius;     /* mm: R_d energy beyond it below the tolerance */
    float table_radius;      /* mm: the table covers [0, table_radius] */
    float table_inv_step;
    float (*table)[4];       /* SAM_RD_TABLE_SIZE + 1 entries: R, G, B, mean */
    float *envelope;         /* SAM_RD_TABLE_SIZE + 1: max of the mean over [j, end]: a non-increasing bound */
};

/* R_d at r mm: RGB and mean (table inside table_radius, exact beyond).
 * This and the next two are inline: the cut's refinement asks them of
 * every node and member it passes, and as calls into another file they
 * took a fifth of its time (docs/performance.md). */
static inline void sam_build_rd(const sam_build_context *ctx, float r, float out[4])
{
    if (r >= ctx->table_radius) {
        sam_profile_eval(ctx->profile, r, out);
        out[3] = (out[0] + out[1] + out[2]) / 3.0f;
        return;
    }
    const float x = r * ctx->table_inv_step;
    const int j = (int)x;
    const float f = x - (float)j;
    const float *a = ctx->table[j], *b = ctx->table[j + 1];
    for (int c = 0; c < 4; ++c)
        out[c] = a[c] + f * (b[c] - a[c]);
}

/* R_d (RGB and mean) at the nearest and farthest points of a part that
 * lies within `reach` mm of a point `d` mm away: how much it may change
 * across the part. */
static inline void sam_build_rd_span(const sam_build_context *ctx, float d, float reach, float near[4], float far[4])
{
    sam_build_rd(ctx, fmaxf(d - reach, 0.0f), near);
    sam_build_rd(ctx, d + reach, far);
}

/* Mean R_d at r: the cheap estimate's profile term. */
static inline float sam_build_rd_mean(const sam_build_context *ctx, float r)
{
    if (r >= ctx->table_radius) {
        float rgb[3];
        sam_profile_eval(ctx->profile, r, rgb);
        return (rgb[0] + rgb[1] + rgb[2]) / 3.0f;
    }
    const float x = r * ctx->table_inv_step;
    const int j = (int)x;
    const float f = x - (float)j;
    return ctx->table[j][3] + f * (ctx->table[j + 1][3] - ctx->table[j][3]);
}

/* sam_build_is_back_side (eq. 13-14), inline. */
static inline int sam_build_behind(const sam_build_context *ctx, uint32_t o, uint32_t i)
{
    const float *po = ctx->pos + 3 * (size_t)o, *pi = ctx->pos + 3 * (size_t)i;
    const float *no = ctx->mesh->topo_normals + 3 * (size_t)o, *ni = ctx->mesh->topo_normals + 3 * (size_t)i;
    const float d = (pi[0] - po[0]) * no[0] + (pi[1] - po[1]) * no[1] + (pi[2] - po[2]) * no[2];
    const float c = ni[0] * no[0] + ni[1] * no[1] + ni[2] * no[2];
    return d < 0.0f && c < 0.0f;
}

/* How much of vertex i's reduced fan is behind receiver o (eq. 13-14 asked
 * of the fan's points, each with the vertex normals interpolated there, as
 * sam_build_fan_point places them; sam_build_fan_back_side). */
typedef enum sam_build_fan {
    SAM_BUILD_FAN_NONE, /* no point of it */
    SAM_BUILD_FAN_PART, /* some points may be */
    SAM_BUILD_FAN_ALL   /* every point */
} sam_build_fan;

/* The corners of topo vertex t's reduced fan that ring entry k adds, in
 * mm: the midpoint of the edge to ring[k] (p[0]) and the centroid of the
 * triangle (t, ring[k - 1], ring[k]) (p[1]; for the first entry, which
 * has no triangle before it, a point of that edge), with the vertex
 * normals interpolated there (n[0], n[1], not of unit length). With the
 * vertex, they span the fan. */
void sam_build_fan_corners(const sam_build_context *ctx, uint32_t t, uint32_t k, float p[2][3], float n[2][3]);

/* Both tests are linear in a fan point and its normal, so their extremes
 * over the fan lie at its corners: the vertex, the edge midpoints and the
 * triangles' centroids. The fan's reach around the vertex settles most
 * fans without walking the ring; inline, for the cut's refinement asks it
 * of every member it passes. */
static inline sam_build_fan sam_build_fan_side(const sam_build_context *ctx, uint32_t o, uint32_t i)
{
    const sam_mesh *m = ctx->mesh;
    const float *po = ctx->pos + 3 * (size_t)o, *no = m->topo_normals + 3 * (size_t)o;
    const float *pi = ctx->pos + 3 * (size_t)i, *ni = m->topo_normals + 3 * (size_t)i;
    const float d0 = (pi[0] - po[0]) * no[0] + (pi[1] - po[1]) * no[1] + (pi[2] - po[2]) * no[2];
    const float c0 = ni[0] * no[0] + ni[1] * no[1] + ni[2] * no[2];
    const float reach = ctx->fan_reach[2 * (size_t)i], turn = ctx->fan_reach[2 * (size_t)i + 1];
    if (d0 + reach < 0.0f && c0 + turn < 0.0f)
        return SAM_BUILD_FAN_ALL;
    if (d0 - reach >= 0.0f || c0 - turn >= 0.0f)
        return SAM_BUILD_FAN_NONE;
    /* Whether some corner passes each test, and whether every one does;
     * once some pass both and not all do, the fan is partly behind. */
    int d_some = d0 < 0.0f, d_all = d_some, c_some = c0 < 0.0f, c_all = c_some;
    float dprev = 0.0f, cprev = 0.0f;
    for (uint32_t k = m->ring_offsets[i]; k < m->ring_offsets[i + 1]; ++k) {
        const float *pa = ctx->pos + 3 * (size_t)m->ring[k], *na = m->topo_normals + 3 * (size_t)m->ring[k];
        const float da = (pa[0] - po[0]) * no[0] + (pa[1] - po[1]) * no[1] + (pa[2] - po[2]) * no[2];
        const float ca = na[0] * no[0] + na[1] * no[1] + na[2] * no[2];
        const float dm = 0.5f * (d0 + da), cm = 0.5f * (c0 + ca);
        d_some |= dm < 0.0f, d_all &= dm < 0.0f, c_some |= cm < 0.0f, c_all &= cm < 0.0f;
        if (k > m->ring_offsets[i]) {
            const float dc = (d0 + dprev + da) / 3.0f, cc = (c0 + cprev + ca) / 3.0f;
            d_some |= dc < 0.0f, d_all &= dc < 0.0f, c_some |= cc < 0.0f, c_all &= cc < 0.0f;
        }
        if (d_some && c_some && !(d_all && c_all))
            return SAM_BUILD_FAN_PART;
        dprev = da, cprev = ca;
    }
    if (d_all && c_all)
        return SAM_BUILD_FAN_ALL;
    return d_some && c_some ? SAM_BUILD_FAN_PART : SAM_BUILD_FAN_NONE;
}

/* The smallest radius beyond which every mean R_d (table) is below
 * `threshold`; table_radius when none is. */
float sam_build_bound_radius(const sam_build_context *ctx, float threshold);

/* The point of the reduced fan of topo vertex t at the uniforms u[0..2] in
 * [0, 1): u[0] picks the place by area, u[1] and u[2] the point in it, so
 * uniform u give a point uniform in area. In `normal` (may be NULL) the
 * vertex normals interpolated there, not of unit length (only its
 * direction is asked). */
void sam_build_fan_point(const sam_build_context *ctx, uint32_t t, const float u[3], float out[3], float normal[3]);

/* sam_build_fan_point at three numbers drawn from `rng`. */
void sam_build_sample_fan(const sam_build_context *ctx, uint32_t t, sam_rng *rng, float out[3], float normal[3]);

/* The point pairs of a form factor come from a randomly shifted
 * six-dimensional Kronecker sequence (Roberts' R_6): pair s is
 * frac(shift + s alpha), the receiver's point from its first three
 * coordinates and the sender's from the last three (a steep pair's pairs
 * past the receiver's points take them again, sam_build_pair_count).
 * Each pair is still
 * uniform on the two fans (the shift is), so K stays unbiased, but the
 * pairs cover the six dimensions evenly instead of clumping: where R_d
 * falls steeply across the fans (thin sheets in skin) independent pairs
 * left the per-vertex T noisy (docs/builder.md). Coordinates are 24-bit
 * fixed point, as sam_rng_float's numbers are. */
#define SAM_BUILD_LATTICE_BITS 24
_Static_assert(SAM_BUILD_LATTICE_BITS < 32, "the lattice's steps wrap modulo 2^32, a multiple of 2^bits");
typedef struct sam_build_lattice {
    uint32_t shift[3];
    uint32_t step[3];
} sam_build_lattice;

/* The receiver's (sender = 0) or the sender's (sender = 1) half of the
 * sequence, shifted by three numbers drawn from `rng`. */
void sam_build_lattice_start(sam_build_lattice *lattice, int sender, sam_rng *rng);

/* The uniforms of pair s. s * step may wrap modulo 2^32; as 2^bits
 * divides 2^32, the bits kept are exact. */
static inline void sam_build_lattice_at(const sam_build_lattice *lattice, uint32_t s, float u[3])
{
    const uint32_t mask = (1u << SAM_BUILD_LATTICE_BITS) - 1u;
    for (int d = 0; d < 3; ++d)
        u[d] = (float)((lattice->shift[d] + s * lattice->step[d]) & mask) * (1.0f / (float)(1u << SAM_BUILD_LATTICE_BITS));
}

/* Whether the point x_i is behind the tangent plane of the point x_o with
 * normal n_o (of any length): eq. 13 between two points of two fans.
 * Inline: it runs for every Monte Carlo pair. */
static inline int sam_build_point_behind(const float xo[3], const float no[3], const float xi[3])
{
    return (xi[0] - xo[0]) * no[0] + (xi[1] - xo[1]) * no[1] + (xi[2] - xo[2]) * no[2] < 0.0f;
}

/* Whether the normals n_i and n_o (of any length) of two points face apart:
 * eq. 14 between two points of two fans. */
static inline int sam_build_point_faces_away(const float no[3], const float ni[3])
{
    return ni[0] * no[0] + ni[1] * no[1] + ni[2] * no[2] < 0.0f;
}

/* The `samples` points on vertex o's reduced fan that every form factor of
 * o shares, SAM_BUILD_POINT_FLOATS floats each: the position, then the
 * interpolated normal (sam_build_fan_point). The receiver's half of the
 * pairs' sequence, shifted from the stream (seed, o), so each K_oi is the
 * same whichever caller computes it, and candidates of one vertex are
 * ranked with common random numbers. */
#define SAM_BUILD_POINT_FLOATS 6
void sam_build_receiver_points(const sam_build_context *ctx, uint32_t o, uint32_t samples, uint64_t seed,
                               float *points);

/* Where R_d falls steeply across a pair of fans near each other, a few
 * pairs of points land where its light is and K is noisy: a thin sheet in
 * skin glowed mottled (docs/builder.md). Such a pair, one whose R_d in some
 * channel falls more than SAM_BUILD_STEEP_FALL-fold from the fans' nearest
 * to their farthest possible points (the vertices' distance less and plus
 * both fans' reach) while it is above SAM_BUILD_STEEP_NEAR of that
 * channel's R_d(0) at the nearest, gets SAM_BUILD_STEEP_PAIRS times the
 * pairs: the receiver's points again, each with further sender points.
 * The near floor keeps it to pairs that carry much light: with 1% instead
 * of 10%, the knot in marble took 1.2 times the build for no less noise. */
#define SAM_BUILD_STEEP_FALL 8.0f
#define SAM_BUILD_STEEP_NEAR 0.1f
#define SAM_BUILD_STEEP_PAIRS 4u

/* The number of point pairs K_oi takes: `samples`, or SAM_BUILD_STEEP_PAIRS
 * times it for a steep pair (`samples` where that would pass UINT32_MAX). */
uint32_t sam_build_pair_count(const sam_build_context *ctx, uint32_t o, uint32_t i, uint32_t samples);

/* K_oi from o's shared points and the sender's half of the pairs' sequence,
 * shifted from the stream (seed, o, i), for points on F'_i:
 * eq. 11 over the pairs of points of which the one on F'_i is behind the
 * tangent plane of the one on o's fan (sam_build_point_behind), and with
 * `pointwise`, whose interpolated normals face apart too (eq. 14 per pair:
 * the cut map's, which asks eq. 13-14 of fans; the flat map's search asks
 * it of vertices and keeps it so). sam_build_pair_count(samples) pairs,
 * paired with o's first `samples` points in turn. */
void sam_build_form_factor_from(const sam_build_context *ctx, uint32_t o, const float *points, uint32_t i,
                                uint32_t samples, uint64_t seed, int pointwise, float k[3], float *k_error);

/* ---- the cluster tree (sam_build_tree.c) */

/* A node over the topo vertices perm[first, first + count): the boxes of
 * their reduced fans' points (mm) and of the normals interpolated there,
 * their summed fan area (mm^2) and area-weighted centroid (mm).
 * child[c] < topo_count is a topo vertex, else node child[c] - topo_count. */
typedef struct sam_build_node {
    float lo[3], hi[3], nlo[3], nhi[3];
    float centroid[3];
    float area;
    uint32_t first, count;
    uint32_t child[2];
} sam_build_node;

/* Boxes of positions (mm) and normals. */
typedef struct sam_build_box {
    float lo[3], hi[3], nlo[3], nhi[3];
} sam_build_box;

/* Nodes partly behind a receiver by their boxes, of at most this many
 * members, are classified member by member: a few hundred back-side tests,
 * about the work of one form factor's Monte Carlo. On the head and dragon
 * scans in skin 16 members gained 0.1-1.6 dB, 64 up to 4 dB, 256 up to 8 dB
 * (and halved the build); 1024 and 4096 gave the same scores, slower. */
#define SAM_BUILD_EXACT_MEMBERS 256u

/* A binary tree whose leaves are the topo vertices, nodes numbered level by
 * level from the root (node 0). */
typedef struct sam_build_tree {
    uint32_t node_count;     /* topo_count - 1 */
    sam_build_node *node;
    sam_build_box *vertex_box; /* vertex_box_count: the boxes of the members' vertices alone, of the first */
    uint32_t vertex_box_count; /* nodes, which hold every node of more than SAM_BUILD_EXACT_MEMBERS members */
    uint32_t *perm;          /* topo_count: topo vertices in tree order; a node's members are a range */
    double *area_prefix;     /* topo_count + 1: summed fan areas along perm */
    uint32_t level_count;
    uint32_t *level_offsets; /* level_count + 1 */
} sam_build_tree;

/* Builds the tree by median splits on the axis of widest extent among the
 * positions and the normals scaled by the mesh's diagonal (so normals part
 * first and whole back sides form early), of the members' vertices; the
 * nodes' boxes then widen to their fans.
 * Deterministic. A mesh of one vertex gets no nodes.
 * Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_build_tree_create(const sam_build_context *ctx, sam_build_tree *tree, sam_error *err);

/* Where sample index id (a topo vertex below topo_count, else topo_count +
 * a node) stands, in mm, and the area it stands for: the vertex's
 * position and fan area, or the node's centroid and area. */
static inline const float *sam_build_sample_point(const sam_build_context *ctx, const sam_build_tree *tree,
                                                  uint32_t id)
{
    const uint32_t n = ctx->mesh->topo_count;
    return id < n ? ctx->pos + 3 * (size_t)id : tree->node[id - n].centroid;
}

static inline float sam_build_sample_area(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t id)
{
    const uint32_t n = ctx->mesh->topo_count;
    return id < n ? ctx->fan_area[id] : tree->node[id - n].area;
}
void sam_build_tree_destroy(sam_build_tree *tree);

/* Where a node lies for a receiver, its members' fans asked eq. 13-14
 * (sam_build_fan_side). */
typedef enum sam_build_side {
    SAM_BUILD_SIDE_OUT,   /* no member can contribute: all in front, facing the receiver's way or out of reach */
    SAM_BUILD_SIDE_BACK,  /* every point of every member's fan is behind */
    SAM_BUILD_SIDE_PARTLY /* some may be */
} sam_build_side;

/* Classifies node j for receiver o from its boxes; fills `b` (mm). */
sam_build_side sam_build_node_side(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t j, uint32_t o,
                                   sam_bounds_range *b);

/* ---- the K of a vertex's cut nodes (sam_build_cut_k.c) */

typedef struct sam_build_cut_k_scratch sam_build_cut_k_scratch;

/* Scratch for cuts of at most `entries` parts and `openings` openings.
 * NULL when out of memory. */
sam_build_cut_k_scratch *sam_build_cut_k_scratch_create(uint32_t entries, uint32_t openings);
void sam_build_cut_k_scratch_destroy(sam_build_cut_k_scratch *s);

/* K of each of the `count` parts ids[e] of receiver o's cut (a topo vertex,
 * or topo_count + node): the members' fans' Monte Carlo for a vertex; for a
 * node, eq. 11 summed over its back-side members, opening at most
 * `openings` subnodes or near members across the whole cut, those whose R_d
 * falls most first. `points` are o's shared receiver points. Writes
 * k[3 * count], centre[3 * count] (the K-weighted centre of what each
 * part's light comes from, mm) and spread[count] (the K-weighted root mean
 * square distance of that light from the centre, mm).
 * Deterministic: the same for any thread. */
void sam_build_cut_k(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, const float *points,
                     const uint32_t *ids, uint32_t count, uint32_t openings, sam_build_cut_k_scratch *scratch,
                     float *k, float *centre, float *spread);

/* |b - a| of two points in mm, summed in the order every builder file used. */
static inline float sam_build_distance(const float a[3], const float b[3])
{
    float dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    return sqrtf(dx * dx + dy * dy + dz * dz);
}

/* The flat builder (sam_build_search.c): the N best vertices. */
sam_status sam_build_run_flat(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                              sam_build_result *result, sam_error *err);

/* The cut builder (sam_build_cut.c): tree and cuts. */
sam_status sam_build_run_cut(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                             sam_build_result *result, sam_error *err);

/* ---- what the flat and cut builders share (sam_build_search.c) */

/* Allocates a result of `stride` samples per vertex, all empty: with k and
 * k_error for a flat map, k_total for a cut map (`cut` non-zero). */
sam_status sam_build_result_alloc(const sam_build_context *ctx, uint32_t stride, int cut, sam_build_result *r,
                                  sam_error *err);

/* Progress and cancellation shared by the worker threads. */
typedef struct sam_build_progress {
    sam_build_progress_fn fn;
    void *user;
    uint64_t done, total, next_report;
    int cancelled;
} sam_build_progress;

/* Counts one finished vertex; thread 0 reports. Returns 1 when cancelled. */
int sam_build_progress_step(sam_build_progress *p);

/* Ends a parallel loop: the "cancelled" error (destroying the result), or
 * the final report and the result's wall time since `start`. */
sam_status sam_build_progress_finish(sam_build_progress *p, sam_build_result *r, double start, sam_error *err);

/* OpenMP threads the settings ask for. */
int sam_build_thread_count(const sam_build_context *ctx);

/* The smallest F' R_d (eq. 15's denominator) that holds a K': below it
 * sam_build_kprime gives K' = 1 and that channel's K is lost. */
#define SAM_BUILD_KPRIME_MIN_DENOM SAMFILE_MIN_UNIT_K

/* The K at rest of one unit of K' (eq. 15's F' R_d) for a sample at
 * `distance` mm from the receiver standing for `area` mm^2, against the
 * exact profile. */
void sam_build_unit_k(const sam_build_context *ctx, float area, float distance, float out[3]);

/* K' of eq. 15 for a sample of K `k` at `distance` mm from the receiver,
 * standing for `area` mm^2: k over sam_build_unit_k, which is what the
 * runtime evaluates. */
void sam_build_kprime(const sam_build_context *ctx, const float k[3], float area, float distance, float out[3]);

/* Whether any of topo vertex v's fan can send receiver o light: some of it
 * behind o (sam_build_fan_side), v within the search radius. Its distance
 * (mm) into *d when it can. */
static inline int sam_build_fan_reaches(const sam_build_context *ctx, uint32_t o, uint32_t v, float *d)
{
    if (v == o || sam_build_fan_side(ctx, o, v) == SAM_BUILD_FAN_NONE)
        return 0;
    *d = sam_build_distance(ctx->pos + 3 * (size_t)o, ctx->pos + 3 * (size_t)v);
    return *d < ctx->search_radius;
}

/* ---- the node that holds a cut entry's K (sam_build_cut_hold.c) */

/* The node (topo_count + node index) that holds cut node `id`'s K `k` for
 * receiver o, whose light comes from around `centre` (the K-weighted
 * centre, mm) with K-weighted spread `spread` (mm), as sam_build_cut_k
 * gives them; `back` 1 where every member of `id` lies behind o. Writes
 * the held node's tau (where along its split the light comes from, in
 * [-1, 1]) to *tau. Deterministic. */
uint32_t sam_build_cut_hold(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t id,
                            const float k[3], const float centre[3], float spread, int back, float *tau);

#endif
