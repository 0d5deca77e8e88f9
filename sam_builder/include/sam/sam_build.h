/*
 * sam_build: precomputation of Spatial Adjacency Maps (Maisch and Ropinski,
 * Sec. 3.2-3.3, 4.1-4.2).
 *
 * For every topological vertex v_o of a mesh (see sam_mesh.h) the builder
 * finds the back-side vertices v_i ((v_i - v_o).n_o < 0 and n_i.n_o < 0,
 * eq. 13-14) whose form factor
 *
 *     K_oi = 1/F'_o  int_{F'_o} int_{F'_i} R_d(|x_i - x_o|) dx_i dx_o   (eq. 11)
 *
 * is largest, estimates K by Monte Carlo over the two reduced fans (each
 * triangle's quadrilateral vertex / edge midpoint / centroid / edge midpoint),
 * keeps the best N, and stores K' = K / (F'_i R_d(|v_i - v_o|)) (eq. 15).
 *
 * The search is not quadratic: candidates come from an Embree point query
 * over the vertices whose radius shrinks while it runs. A back-side vertex
 * at distance d can have a cheap estimate F'_i R_d(d) of at most
 * max_fan_area * R_d(d); once C candidates are held, everything farther than
 * the distance where that bound falls below the C-th best is skipped. Only
 * the C best by the cheap estimate get Monte Carlo (C = `candidates`).
 *
 * Each vertex's work uses its own random stream, seeded from the build seed
 * and the vertex and candidate indices, so the result is bit-identical for
 * any thread count.
 *
 * That is the flat map (SAM_BUILD_MAP_FLAT). By default the builder makes a
 * cut map instead (sam_build_cut.c): a binary tree of surface clusters over
 * the vertices (median splits on position and normal, sam_build_tree.c),
 * and per vertex a cut through it, as lightcuts choose one: the nodes wholly
 * on the back side, refined where R_d changes most across a node, until
 * N nodes are held or the largest node's bound on its R_d variation
 * is below `cut_tolerance` of the vertex's estimated total. Each node's K is
 * eq. 11 summed over its members: stratified Monte Carlo over its area, a
 * point on a member's fan and one on o's fan per sample. A node so stands
 * for a patch of the back side, and a small fixed budget covers a vertex's
 * whole back side within the profile's reach on any tessellation.
 *
 * Lengths inside the builder are millimetres: positions are scaled by
 * mm_per_unit, fan areas are mm^2 and R_d is in mm^-2, so K is unitless.
 */
#ifndef SAM_BUILD_H
#define SAM_BUILD_H

#include "sam/sam_common.h"
#include "sam/sam_mesh.h"
#include "sam/sam_profile.h"
#include "sam/samfile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The builder's version, recorded in every .sam it writes; it changes
 * whenever the same inputs give another map (1.1: cut nodes of up to 256
 * members classified member by member; 1.2: a row is the budget's best
 * vertices where they hold nearly all the light, and a cut node whose
 * centroid cannot hold its K hands it to a descendant node that can; 1.3:
 * the fans' Monte Carlo counts a pair of points only where the one is
 * behind the other's tangent plane, eq. 13 point by point; 1.4: a cut node
 * partly behind its receiver hands its K to a node around its back-side
 * member nearest where its light comes from; 1.5: whether a row is the
 * budget's best vertices is judged on at most 32 of them, so that maps of
 * N > 32 change; 1.6: a cut node wholly behind its receiver hands its K to
 * the smallest node around where its light comes from, no smaller than
 * its spread; 1.7: a cluster whose normals lie within a cone splits by
 * position while it is wider than the profile's reach across; 1.8: a cut
 * node partly behind its receiver with more members than are asked one by
 * one first goes down towards where its light comes from; 1.9: the cut
 * map asks eq. 13-14 of its members' fans, not their vertices, and counts
 * a fan partly behind the receiver by its pairs of points; 1.10: a cut
 * map stores 16 of a 32-entry cut by default, a budget above N fitted by
 * merging siblings and folding the rest into the nearest kept; 1.11: the
 * fold goes to the nearest kept in place and facing; 1.12: a cut node
 * partly behind its receiver hands its K to a node no larger than its
 * light's spread needs, not to the largest wholly behind; 1.13: the
 * fans' point pairs come from a shifted Kronecker sequence, not
 * independent streams; 1.14: a pair of fans across which R_d falls
 * steeply while it carries much light gets four times the pairs), and the
 * tools' map cache keys on it, so that no cached map outlives the builder
 * that made it. */
#define SAM_BUILD_VERSION "1.14"
#define SAM_BUILD_NO_SAMPLE UINT32_MAX

/* Which map the builder makes. */
typedef enum sam_build_map {
    SAM_BUILD_MAP_CUT = 0,        /* a cluster tree and a cut per vertex (default; a version-2 .sam) */
    SAM_BUILD_MAP_FLAT = 1,       /* the paper's N best back-side vertices (a version-1 .sam) */
    SAM_BUILD_MAP_FLAT_SCALED = 2 /* the flat map with each vertex's K scaled so that its samples carry
                                   * the vertex's total back-side transport (the cut's): a baseline */
} sam_build_map;

typedef struct sam_build_settings {
    sam_build_map map;           /* default SAM_BUILD_MAP_CUT */
    uint32_t samples_per_vertex; /* N, 0..64: samples stored per vertex; 0 (default) = the map's default:
                                  * 16 for a cut, 3 for a flat map */
    float cut_tolerance;         /* cut map: refine while a node's R_d bound exceeds this fraction of the
                                  * vertex's total, in (0, 1) (default 0.01) */
    uint32_t cut_budget;         /* cut map: entries of a vertex's cut, N..64, fitted to the N stored as
                                  * samfile_fit_samples fits a map (siblings merged into their parent, the
                                  * rest folded into the kept sample nearest them); 0 (default) = the
                                  * larger of N and SAM_BUILD_CUT_DEFAULT_BUDGET. Ignored by flat maps */
    uint32_t mc_samples;         /* Monte Carlo point pairs per form factor, 4..65536 (default 64) */
    uint32_t candidates;         /* flat maps: cheap-ranked candidates that get Monte Carlo, >= N (0: N + 2) */
    float radius_tolerance;      /* energy fraction of R_d left beyond the search radius (default 1e-4) */
    uint64_t seed;               /* default 1 */
    int threads;                 /* OpenMP threads, 0 = all cores (does not change the result) */
} sam_build_settings;

/* Called from one thread about every 0.5% of the work with the number of
 * vertices done and the total. Returning non-zero cancels the build, which
 * then fails with SAM_ERR_INVALID_ARGUMENT "cancelled". May be NULL. */
typedef int (*sam_build_progress_fn)(void *user, uint64_t done, uint64_t total);

/* Per topological vertex results, N entries each, best first (N is the
 * budget of a cut map). A sample s < topo_count is a topo vertex, s >=
 * topo_count tree node s - topo_count. sample, kprime and tau have room
 * for the mesh's vertex_count rows (>= topo_count), so that
 * sam_build_move_to_samfile turns them into render rows in place; rows
 * past topo_count are scratch. */
typedef struct sam_build_result {
    uint32_t topo_count;
    uint32_t samples_per_vertex;
    uint32_t *sample;    /* topo_count * N: topo vertex, topo_count + node, or SAM_BUILD_NO_SAMPLE */
    float *k;            /* flat maps: topo_count * N * 3: Monte Carlo K (RGB), 0 for no sample; NULL in a
                          * cut map, whose samples' K lives only in kprime (memory: see k_total) */
    float *k_error;      /* flat maps: topo_count * N: standard error of the mean-RGB K estimate as from
                          * as many independent pairs (the pairs' lattice errs less); NULL in a cut map */
    float *k_total;      /* cut maps: topo_count * 3: K (RGB) summed over the vertex's cut, its whole
                          * back-side transport; NULL in a flat map */
    float *kprime;       /* topo_count * N * 3: K' of eq. 15 */
    float *fan_area;     /* topo_count: reduced fan area in mm^2 */
    /* The cluster tree of a cut map (node_count 0 and NULL arrays in a flat
     * one), in samfile.h's layout with topo vertices for render vertices:
     * children < topo_count are topo vertices, else topo_count + node. */
    uint32_t node_count;
    uint32_t *node_children;  /* 2 * node_count */
    uint32_t level_count;
    uint32_t *level_offsets;  /* level_count + 1 */
    float *tau;               /* topo_count * N: samfile.h's STAU per sample (0 for vertices); NULL when
                               * there is no tree */
    float search_radius_mm;   /* the initial query radius */
    uint64_t candidates_seen; /* back-side vertices the queries scored */
    uint64_t form_factors;    /* Monte Carlo estimates computed */
    double seconds;           /* wall time of the build */
} sam_build_result;

/* The form-factor machinery on one mesh and profile: scaled positions, fan
 * areas, fan sampling tables and an R_d lookup table. Opaque. */
typedef struct sam_build_context sam_build_context;

#define SAM_BUILD_CUT_DEFAULT_SAMPLES 16u
/* A cut map is cut at least this fine, whatever N it stores: 16 of a
 * 32-entry cut score within about 0.3 dB of all 32 on most scenes, where a
 * 16-entry cut loses 1.7 to 4.1 dB (docs/comparison.md). */
#define SAM_BUILD_CUT_DEFAULT_BUDGET 32u
#define SAM_BUILD_FLAT_DEFAULT_SAMPLES 3u

/* Fills the defaults documented on sam_build_settings. */
void sam_build_default_settings(sam_build_settings *settings);

/* "cut", "flat" or "flat-scaled" (sam_build's option names); "?" for
 * another value. */
const char *sam_build_map_name(sam_build_map map);

/* N for `settings`: samples_per_vertex, or the map's default when it is 0. */
uint32_t sam_build_samples(const sam_build_settings *settings);
/* A cut map's entries per vertex for `settings`: cut_budget, or when it is
 * 0 the larger of N and SAM_BUILD_CUT_DEFAULT_BUDGET. */
uint32_t sam_build_cut_budget(const sam_build_settings *settings);

/* Checks settings and scale. Errors: SAM_ERR_INVALID_ARGUMENT naming the
 * setting and value. */
sam_status sam_build_check_settings(const sam_build_settings *settings, float mm_per_unit, sam_error *err);

/* Creates a context (caller destroys). `mesh` and `profile` must outlive it.
 * Errors: SAM_ERR_INVALID_ARGUMENT (scale, settings), SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_build_context_create(const sam_mesh *mesh, const sam_profile *profile, float mm_per_unit,
                                    const sam_build_settings *settings, sam_build_context **ctx, sam_error *err);
void sam_build_context_destroy(sam_build_context *ctx);

/* Monte Carlo estimate of K_oi (eq. 11) between topo vertices o and i with
 * `samples` point pairs (four times as many, the same `samples` points on
 * F'_o each with four on F'_i, where R_d falls more than 8-fold across the
 * two fans while above a tenth of R_d(0) at their nearest) from a randomly
 * shifted six-dimensional Kronecker sequence: points on F'_o from its first
 * three coordinates, shifted by a stream seeded by (seed, o) (shared by all
 * of o's candidates), points on F'_i from its last three, shifted by one
 * seeded by (seed, o, i); a pair
 * counts only where its point on F'_i is behind the tangent plane of its
 * point on F'_o (eq. 13, the vertex normals interpolated there), so a fan
 * against itself or beside o gives 0. K in RGB, and the standard error its
 * mean-RGB value would have from as many independent pairs (the lattice's
 * own error is smaller; NaN when out of memory). The builders compute
 * exactly these values. Thread-safe. */
void sam_build_form_factor(const sam_build_context *ctx, uint32_t o, uint32_t i, uint32_t samples,
                           uint64_t seed, float k[3], float *k_error);

/* K_oi as sam_build_form_factor estimates it (the same points), but with
 * eq. 14 asked of each point pair too, between the vertex normals
 * interpolated at its two points, and for any two topo vertices o != i,
 * not only those that pass eq. 13-14 as vertices: the ground truth's test,
 * point by point. The builders do not use it; bench_limit measures with it
 * how far the per-vertex test leaves a vertex map from the truth.
 * Thread-safe. */
void sam_build_form_factor_pointwise(const sam_build_context *ctx, uint32_t o, uint32_t i, uint32_t samples,
                                     uint64_t seed, float k[3], float *k_error);

/* The reduced fan area F'_t of topo vertex t in mm^2 (eq. 16). */
float sam_build_fan_area(const sam_build_context *ctx, uint32_t t);

/* 1 when topo vertex i is on the back side of o (eq. 13-14). */
int sam_build_is_back_side(const sam_build_context *ctx, uint32_t o, uint32_t i);

/* How much of topo vertex i's reduced fan is on the back side of vertex o:
 * eq. 13-14 asked of the fan's points against o's vertex and normal, the
 * vertex normals interpolated at each point. 0: none of it (and when
 * o == i), 1: part of it may be, 2: all of it. The cut map asks this of
 * its nodes' members; the flat map asks sam_build_is_back_side. */
int sam_build_fan_back_side(const sam_build_context *ctx, uint32_t o, uint32_t i);

/* The builder of the map that settings.map names. `result` is filled
 * (caller destroys) on success.
 * Errors: those of context creation, SAM_ERR_INVALID_ARGUMENT ("cancelled"
 * by the progress callback), SAM_ERR_UNSUPPORTED (Embree failure). */
sam_status sam_build_run(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                         sam_build_result *result, sam_error *err);

/* Testing aid. The O(m^2) reference of the flat map: Monte Carlo for every
 * back-side vertex of every vertex, keep the best N, for tests and
 * benchmarks on small meshes. */
sam_status sam_build_reference(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                               sam_build_result *result, sam_error *err);

void sam_build_result_destroy(sam_build_result *result);

/* Where the source mesh came from, for the INFO chunk. */
typedef struct sam_build_source {
    const char *file;    /* as given by the user; may be NULL */
    const char *sha256;  /* 64 hex digits; may be NULL */
} sam_build_source;

/* Expands a result to render vertices and fills a samfile_data ready for
 * samfile_write (caller frees it with samfile_free): positions, normals,
 * UVs and triangles of the mesh, SIDX/SKPR/FANA shared by the render copies
 * of each topo vertex, ADJO/ADJV from the one-rings, and INFO recording
 * counts, scale, material, settings, source and build time.
 * Errors: SAM_ERR_OUT_OF_MEMORY. */
sam_status sam_build_to_samfile(const sam_build_context *ctx, const sam_build_result *result,
                                const sam_build_source *source, samfile_data *out, sam_error *err);

/* sam_build_to_samfile without a second copy of the samples: the result's
 * sample, kprime and tau arrays become the .sam's (grown to render
 * vertices and renumbered in place), so a large map is never held twice.
 * On return, success or not, those three are NULL in `result` (the rest of
 * it stays, for sam_build_result_destroy). Errors: as sam_build_to_samfile. */
sam_status sam_build_move_to_samfile(const sam_build_context *ctx, sam_build_result *result,
                                     const sam_build_source *source, samfile_data *out, sam_error *err);

/* Context, fast build and .sam assembly in one call, for callers that need
 * no intermediate result. `settings` may be NULL (defaults); `source`,
 * `progress` and `seconds` (the build's wall time) may be NULL. `out` is
 * filled on success (caller frees it with samfile_free).
 * Errors: those of the three steps. */
sam_status sam_build_samfile(const sam_mesh *mesh, const sam_profile *profile, float mm_per_unit,
                             const sam_build_settings *settings, const sam_build_source *source,
                             sam_build_progress_fn progress, void *user, samfile_data *out, double *seconds,
                             sam_error *err);

/* Why `map` leaves most of its vertices dark: when at least half of them
 * have no back-side sample, writes into `buf` (`n` bytes, always
 * NUL-terminated) a few sentences for a warning and returns 1: the share,
 * the material's reach `reach_mm` (sam_profile_radius), and the likely
 * causes: an open mesh may be a single sheet (a leaf, a cloth card), which
 * has no back side; a closed one may face inward; a solid may be thicker
 * than the light crosses at its size, `mm_per_unit` times its diagonal,
 * which a wrong scale gives.
 * `name` (may be NULL) names the mesh. Otherwise writes "" and returns 0,
 * as for a NULL map or buffer. */
int sam_build_explain_empty(const samfile_data *map, float mm_per_unit, float reach_mm, const char *name, char *buf,
                            size_t n);

/* Why an object gets next to no translucency for its size: when its
 * diagonal, `mm_per_unit` times the map's, is under `near_mm` (use
 * sam_profile_radius(profile, 0.99): the radius within which the material
 * spreads 1% of the light it takes in), writes into `buf` (`n` bytes,
 * always NUL-terminated) a sentence naming the size, the scale and what to
 * check, and returns 1. A model in metres read as millimetres is a
 * thousandth of its size, and its map is full but lends it no light.
 * `name` (may be NULL) names the mesh. Otherwise writes "" and returns 0,
 * as for a NULL map or buffer. */
int sam_build_explain_small(const samfile_data *map, float mm_per_unit, float near_mm, const char *name, char *buf,
                            size_t n);

#ifdef __cplusplus
}
#endif

#endif
