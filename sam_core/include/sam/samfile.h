/*
 * samfile: the .sam container that sam_build writes and the runtime loads:
 * a mesh extended, per vertex, with n back-side samples and their
 * form-factor constants K', plus the adjacency buffer.
 *
 * Version 1 (a flat map): each sample is one back-side vertex. Version 2 (a
 * cut map) adds a binary tree of surface clusters over the vertices (chunks
 * NODE and NLVL) and lets a sample name a tree node: sample index s < vc is
 * vertex s, s >= vc is node s - vc, which stands for the vertices below it
 * (its area is the sum of their fan areas, its position their area-weighted
 * centroid, its L_d their area-weighted mean, moved along its split by the
 * sample's tau: a first-order correction towards where its light comes
 * from). A reader of this build loads
 * both versions; the writer emits version 1 when there is no tree, so flat
 * maps stay readable by version-1 readers.
 *
 * On disk (little-endian whatever the host): a 16-byte header
 *   "SAMF", u32 version = 1, u32 chunk count, u32 flags = 0,
 * then chunks, each
 *   4-byte tag, u32 reserved = 0, u64 payload length, payload,
 *   zero padding to a multiple of 8, u32 CRC-32 (zlib) of the payload, u32 0.
 * Required tags: INFO (JSON), POS , NRM , TRI , SIDX, SKPR, FANA, ADJO, ADJV,
 * and in version 2 NODE, NLVL and STAU (which version 1 must not have);
 * optional: UV   and SRCV (either version; a reader that predates SRCV
 * skips it as unknown, and loses only the engine's vertex order). Unknown tags are skipped and counted; a duplicated tag is
 * an error. The writer emits the chunks in the order of samfile_data below,
 * so reading a file and writing it again gives the same bytes (less any
 * unknown chunks, which are not kept).
 *
 * Every load error is one line naming the file, the chunk and the values
 * found, e.g. "ear.sam: chunk SIDX: sample index 5123 of vertex 17 is out of
 * range (vertex_count 4096)". Allocations on read are sized from payload
 * lengths already checked against the input size, so a hostile header cannot
 * make the reader allocate much more than the input.
 *
 * Limitation of the format: a chunk's CRC covers its payload only, so a
 * damaged tag of the optional UV chunk reads as an unknown chunk and the file
 * loads without UVs. Damage anywhere else in a file is always detected.
 *
 * No function here keeps global state; all are thread-safe on distinct data
 * (cJSON itself records its last syntax error in a global, which this module
 * never reads).
 */
#ifndef SAMFILE_H
#define SAMFILE_H

#include <stdio.h>

#include "sam/sam_common.h"
#include "sam/sam_profile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The newest version this build reads and writes; it reads version 1 too. */
#define SAMFILE_VERSION 2u
/* Pads a vertex's sample list when it has fewer than n back-side vertices. */
#define SAMFILE_NO_SAMPLE 0xFFFFFFFFu
#define SAMFILE_MAX_SAMPLES_PER_VERTEX 64u
/* A normal is accepted when its length is within this of 1. */
#define SAMFILE_NORMAL_TOLERANCE 1e-3

/*
 * The content of a .sam file, as structs of arrays. vc = vertex_count,
 * tc = triangle_count, n = samples_per_vertex. Every array is required
 * except `uvs` (NULL when the file has no UV chunk) and `adjacency` (NULL
 * allowed only when adjacency_count is 0).
 */
typedef struct samfile_data {
    uint32_t vertex_count;       /* >= 1 */
    uint32_t triangle_count;     /* >= 1 */
    uint32_t samples_per_vertex; /* n, 1..SAMFILE_MAX_SAMPLES_PER_VERTEX */
    /* INFO: NUL-terminated UTF-8 JSON object, exactly from '{' to '}', with
     * numbers vertex_count, triangle_count, samples_per_vertex equal to the
     * counts above and mm_per_unit (> 0, finite); an optional boolean
     * has_uvs must match the presence of the UV chunk; other keys are free. */
    char *info_json;
    float *positions;             /* POS : 3*vc, x,y,z in model units, finite */
    float *normals;               /* NRM : 3*vc, unit length (SAMFILE_NORMAL_TOLERANCE) */
    float *uvs;                   /* UV  : 2*vc, finite, or NULL */
    uint32_t *triangles;          /* TRI : 3*tc vertex indices < vc */
    uint32_t *sample_index;       /* SIDX: n*vc, per vertex best first; each < vc + node_count
                                   * or SAMFILE_NO_SAMPLE, and only pads after a pad */
    float *sample_kprime;         /* SKPR: 3*n*vc, RGB K' per sample, finite, >= 0 */
    float *fan_area;              /* FANA: vc, reduced fan area in mm^2 at rest, finite, >= 0 */
    uint32_t *adjacency_offsets;  /* ADJO: vc+1, [0] = 0, non-decreasing, [vc] = adjacency_count */
    uint32_t adjacency_count;     /* entries in ADJV */
    uint32_t *adjacency;          /* ADJV: one-ring neighbours < vc, in fan order */
    /* The cluster tree (version 2); node_count 0 and both arrays NULL in a
     * flat map. Nodes are grouped by depth, root level first; a node's
     * children are vertices or nodes of the next level, so summing the
     * levels deepest first has every child ready before its parent. Every
     * vertex and node is the child of at most one node, and every node
     * below level 0 of exactly one. */
    uint32_t node_count;          /* NODE: tree nodes; vc + node_count < SAMFILE_NO_SAMPLE */
    uint32_t *node_children;      /* NODE: 2*node_count sample indices: < vc a vertex, else a node of the
                                   * level after its parent's */
    uint32_t level_count;         /* NLVL: depth levels, >= 1 when node_count > 0 */
    uint32_t *level_offsets;      /* NLVL: level_count+1 node indices: [0] = 0, increasing,
                                   * [level_count] = node_count */
    float *sample_tau;            /* STAU: n*vc, per sample: where its light comes from along the node's
                                   * split, in [-1, 1]; the sample reads L_d + tau (L_d(child 1) -
                                   * L_d(child 0)); 0 for a vertex or a pad */
    /* SRCV, optional: the vertices of the mesh the map was built from (a
     * file's or an engine's vertex arrays, in their order) against this
     * file's, both ways (sam_mesh.source_of_render and render_of_source).
     * It lets an engine with its own vertex buffers pose the runtime and
     * read T in its order (sam_runtime_set_engine_pose). On disk: u32
     * source_vertex_count, vertex_source, source_vertex. Both arrays are
     * present or neither. */
    uint32_t source_vertex_count; /* >= 1 with the arrays, 0 without */
    uint32_t *vertex_source;      /* vc: the source vertex each vertex came from, < source_vertex_count */
    uint32_t *source_vertex;      /* source_vertex_count: the vertex each became, < vc or SAMFILE_NO_SAMPLE */
    uint32_t unknown_chunk_count; /* set by read: chunks with unknown tags skipped; ignored by write */
} samfile_data;

/*
 * Checks the semantic rules listed on samfile_data (the same checks a read
 * applies after decoding). Messages start with "samfile data: chunk TAG: ".
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL data, a NULL required array, a rule
 * broken), SAM_ERR_EMPTY (vertex_count or triangle_count is 0).
 */
sam_status samfile_validate(const samfile_data *data, sam_error *err);

/*
 * Validates `data` (messages name `path`), then writes it atomically: a
 * failed write leaves no file behind and an existing file at `path`
 * untouched. `data` stays owned by the caller; unknown_chunk_count is
 * ignored. Errors: those of samfile_validate, SAM_ERR_IO (cannot create,
 * write or rename; the message names the path and strerror).
 */
sam_status samfile_write(const char *path, const samfile_data *data, sam_error *err);

/*
 * Reads and validates the .sam file at `path` into `out`, whose arrays are
 * newly allocated and released with samfile_free. On failure `out` is left
 * zeroed with nothing to free. Errors: SAM_ERR_INVALID_ARGUMENT (NULL
 * argument), SAM_ERR_IO, and those of samfile_read_memory.
 */
sam_status samfile_read(const char *path, samfile_data *out, sam_error *err);

/*
 * As samfile_read, from `size` bytes at `bytes` (not kept, not modified).
 * `name` labels messages; NULL gives "<memory>".
 * Errors: SAM_ERR_FORMAT (bad magic, truncation, framing, payload sizes),
 * SAM_ERR_UNSUPPORTED (version other than 1 and 2, nonzero header flags),
 * SAM_ERR_CORRUPT (CRC mismatch, counts that disagree between chunks,
 * values out of range), SAM_ERR_EMPTY (no vertices or no triangles),
 * SAM_ERR_OUT_OF_MEMORY.
 */
sam_status samfile_read_memory(const uint8_t *bytes, size_t size, const char *name, samfile_data *out,
                               sam_error *err);

/*
 * What each sample index of `data` stands for at rest: for every vertex and
 * then every tree node (vertex_count + node_count records of 4 + 2 channels
 * floats), its position (model units), area (mm^2), the area-weighted mean
 * of `channels` per-vertex values `values` (vertex_count * channels; may be
 * NULL when channels is 0), and for a node its second child's mean minus
 * its first's (0 for a vertex): a sample's value is mean + tau * that. A vertex's record is its own; a node's
 * sums its children as the runtime's node pass does (samfile.h's layout),
 * so CPU tools read a cut map's samples as the GPU does. `out` is caller
 * owned. Errors: SAM_ERR_INVALID_ARGUMENT (NULL data or out, values NULL
 * with channels > 0, channels > 16).
 */
sam_status samfile_sample_points(const samfile_data *data, const float *values, uint32_t channels, float *out,
                                 sam_error *err);

/*
 * The K at rest of slot k of vertex v's row of `data` (eq. 15: K = K' F'_b
 * R_d(mm_per_unit |v_b - v|), RGB into k_rgb), as the runtime's rest pass
 * evaluates it, from the records of samfile_sample_points (`points`,
 * `stride` floats each: 4 + 2 channels) and `profile`. The slot must name
 * a sample (not SAMFILE_NO_SAMPLE).
 */
void samfile_sample_k(const samfile_data *data, const float *points, size_t stride, uint32_t v, uint32_t k,
                      const sam_profile *profile, float mm_per_unit, float k_rgb[3]);

/* Floats per point of samfile_fold_row (samfile_fold_point). */
#define SAMFILE_FOLD_POINT_FLOATS 7

/*
 * The point samfile_fold_row compares a row's entries by, from the entry's
 * position `p`, its normal `normal` (any length; a zero one gives none)
 * and the receiving vertex's position `receiver` (the same units as p):
 * the position, the unit normal (or 0) and the distance from the receiver.
 * An entry is as far from another as their positions are apart plus the
 * turn between their normals times its distance from the receiver (in
 * squares): the arc the turn spans seen from there, a length like theirs;
 * where either has no normal, their positions alone.
 * What light reaches the back side depends on which way it faces as much
 * as on where it is. Writes SAMFILE_FOLD_POINT_FLOATS floats to `out`.
 */
void samfile_fold_point(const float p[3], const float normal[3], const float receiver[3], float *out);

/*
 * One row's K (RGB, `k_rgb`: 3 * count floats; entries best first) fitted
 * to its first `kept` entries: each entry past them hands its K, channel by
 * channel, to the nearest kept entry that carries at least as much of that
 * channel (`points`: entry i's samfile_fold_point at points + i * stride,
 * SAMFILE_FOLD_POINT_FLOATS floats; ties go to the better entry), so the
 * dropped light is read near where it comes from and from a part of the
 * back side that faces its way; what no kept entry outweighs is shared among the kept in
 * proportion to their K, and a channel no kept entry carries is left out.
 * So no entry's K grows past its own times (1 + count - kept) plus that
 * share. Writes 3 * kept floats to `out_rgb` (caller owned, may not alias
 * k_rgb). kept <= count <= SAMFILE_MAX_SAMPLES_PER_VERTEX; kept == count
 * copies the row.
 */
void samfile_fold_row(const float *points, size_t stride, const float *k_rgb, uint32_t count, uint32_t kept,
                      float *out_rgb);

/* The smallest K at rest per unit of K' (F'_b R_d, eq. 15) that holds a
 * K': below it a channel's K' is 1, its far-field limit, and that channel's
 * sliver of K is lost (the builder's rule too). */
#define SAMFILE_MIN_UNIT_K 1e-30f

/* The K at rest per unit of K' (F'_b R_d(|v_b - v|), RGB) of sample index
 * `id` in the row being fitted. */
typedef void (*samfile_unit_k_fn)(void *user, uint32_t id, float out[3]);

/*
 * One row's entries (`count` of them: sample indices `id`, RGB K `k_rgb`
 * 3 * count, `tau`) with pairs of siblings merged into their parent until
 * `keep` are left or no two entries share a parent: the parent's sample
 * reads L_d + tau (L_d(child 1) - L_d(child 0)), and with tau = a_0 / (a_0
 * + a_1) - K_0 / (K_0 + K_1) (areas a, K summed over channels) that is the
 * two children's K-weighted L_d exactly, where neither had a tau of its
 * own. So the pairs merged first are those whose own taus weigh least (K
 * times |tau|), then the dimmest. A pair is left as it is where its
 * parent's `unit_k` (called with `user`) is at most SAMFILE_MIN_UNIT_K in
 * a channel the pair carries: its K' would leave float's range. `parent`:
 * per sample index (vertex_count + nodes), the sample index of the node
 * it is a child of, or SAMFILE_NO_SAMPLE; `children`: 2 per node, as
 * samfile_data's node_children; `area`: sample index i's area at area[i *
 * stride], as samfile_sample_points' records hold it. Rewrites the arrays
 * in place, a merged pair at its first entry's place and the rest in
 * their order (a best-first row stays best first, near enough), and
 * returns the entries left (>= keep unless no mergeable siblings were left).
 */
uint32_t samfile_merge_siblings(const uint32_t *parent, const uint32_t *children, uint32_t vertex_count,
                                const float *area, size_t stride, samfile_unit_k_fn unit_k, void *user, uint32_t *id,
                                float *k_rgb, float *tau, uint32_t count, uint32_t keep);

/*
 * Every row of `data` (as samfile_validate accepts it, which a read's
 * always is; rows are best first) fitted to `samples` entries, for a
 * GL whose storage blocks cannot hold the whole map (sam_runtime_create):
 * a row longer than `samples` first has pairs of sibling samples merged
 * into their parent node (samfile_merge_siblings; in a cut map), then
 * each sample past the first `samples` folded into the kept sample
 * nearest it in place and facing (samfile_fold_row, samfile_fold_point,
 * a node's normal the area-weighted mean of its members'), both on the K
 * at rest (K = K' F'_b R_d(mm_per_unit |v_b - v|), eq. 15, with
 * `profile`, at the sample points of samfile_sample_points), so the row
 * carries the K at rest it carried whole; the kept samples' K' are set to
 * carry it. A channel the kept samples carry none of is left out. Shorter
 * rows are copied. Writes vertex_count *
 * samples entries of `index` and `tau` (NULL allowed for a flat map) and
 * 3 * vertex_count * samples of `kprime`, row by row as the .sam's arrays;
 * all caller owned. Errors: SAM_ERR_INVALID_ARGUMENT (a NULL argument,
 * samples 0 or above data's samples_per_vertex, mm_per_unit not > 0),
 * SAM_ERR_OUT_OF_MEMORY.
 */
sam_status samfile_fit_samples(const samfile_data *data, uint32_t samples, const sam_profile *profile,
                               float mm_per_unit, uint32_t *index, float *kprime, float *tau, sam_error *err);

/* Frees the arrays of a samfile_data filled by a read and zeroes it. Safe on
 * a zeroed struct and on NULL. Do not call it on caller-built data. */
void samfile_free(samfile_data *data);

/*
 * What INFO records about a map's making, for tools that light or inspect it
 * with the material and scale it was built with. INFO's keys: the counts and
 * has_uvs (checked by every read), mm_per_unit, material (a profile as
 * sam_profile_to_json writes it), source {file, sha256}, builder {name,
 * version and settings} and build_seconds.
 */
typedef struct samfile_info {
    int has_material;          /* 0: INFO records no material (profile untouched) */
    sam_profile profile;       /* valid when has_material */
    float mm_per_unit;         /* 0 when INFO records no scale */
    char source_file[256];     /* "" when not recorded; cut to fit */
    char source_sha256[65];    /* 64 hex digits, or "" when not recorded */
    double build_seconds;      /* the build's wall time; 0 when not recorded */
    char map[24];              /* the builder's kind of map ("cut", "flat", "flat-scaled"); "" when not recorded */
} samfile_info;

/*
 * Reads the INFO of `data` (as validated by samfile_read) into `out`.
 * `name` (the file's name, may be NULL) prefixes messages. Fields INFO lacks
 * are left empty as described above; deciding whether that is an error is
 * the caller's. Errors: SAM_ERR_FORMAT when the recorded material is not a
 * valid one (the message names the field), SAM_ERR_OUT_OF_MEMORY.
 */
sam_status samfile_info_read(const samfile_data *data, const char *name, samfile_info *out, sam_error *err);

/*
 * Prints every INFO key but the counts to `out`, one line each ("  key
 * value": strings bare, objects and arrays as compact JSON), so a map's
 * material, scale, build settings and source show up, new keys included.
 * Prints nothing when INFO cannot be parsed (out of memory: a read has
 * already validated it).
 */
void samfile_info_print(const samfile_data *data, FILE *out);

#ifdef __cplusplus
}
#endif

#endif
