#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_internal.h"

/* ---- A small open-addressing map from fixed-size uint32 keys to dense ids.
 * Ids are handed out in insertion order, so results are deterministic. */

typedef struct keymap {
    uint32_t words;     /* words per key */
    uint32_t count;     /* keys stored */
    uint32_t capacity;  /* slots, power of two */
    uint32_t *slots;    /* capacity entries: id + 1, 0 = empty */
    uint32_t *keys;     /* words * (number of keys inserted) */
} keymap;

static int keymap_init(keymap *m, uint32_t words, uint32_t expected)
{
    memset(m, 0, sizeof *m);
    m->words = words;
    m->capacity = 16;
    while (m->capacity < expected * 2u && m->capacity < (1u << 31))
        m->capacity <<= 1;
    m->slots = calloc(m->capacity, sizeof *m->slots);
    m->keys = malloc((size_t)(expected ? expected : 1) * words * sizeof *m->keys);
    return m->slots && m->keys;
}

static void keymap_free(keymap *m)
{
    free(m->slots);
    free(m->keys);
    memset(m, 0, sizeof *m);
}

static uint32_t hash_words(const uint32_t *k, uint32_t words)
{
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint32_t i = 0; i < words; ++i) {
        h ^= k[i];
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 31;
    }
    return (uint32_t)(h ^ (h >> 32));
}

/* Returns the id of `key`, inserting it if new (*inserted = 1). The caller
 * sized the map for every key it will insert, so the key array never grows;
 * the slot table stays at most half full. Returns UINT32_MAX on a full map. */
static uint32_t keymap_get(keymap *m, const uint32_t *key, int *inserted)
{
    uint32_t mask = m->capacity - 1;
    for (uint32_t i = hash_words(key, m->words) & mask, probes = 0; probes < m->capacity;
         i = (i + 1) & mask, ++probes) {
        uint32_t s = m->slots[i];
        if (s == 0) {
            if (m->count * 2 >= m->capacity)
                return UINT32_MAX;
            memcpy(m->keys + (size_t)m->count * m->words, key, m->words * sizeof *key);
            m->slots[i] = ++m->count;
            *inserted = 1;
            return m->count - 1;
        }
        if (memcmp(m->keys + (size_t)(s - 1) * m->words, key, m->words * sizeof *key) == 0) {
            *inserted = 0;
            return s - 1;
        }
    }
    return UINT32_MAX;
}

static uint32_t float_bits(float f)
{
    uint32_t u;
    if (f == 0.0f)
        f = 0.0f; /* -0 and +0 are one position */
    memcpy(&u, &f, sizeof u);
    return u;
}

/* ---- building: the stages, in the order sam_mesh_build runs them */

#define NONE UINT32_MAX

/* The build's inputs, its running counts and everything it allocates on the
 * way (freed in one place); each stage reads what the earlier ones left. */
typedef struct build_state {
    const sam_mesh_soup *in;
    const char *name;        /* for messages */
    sam_mesh *mesh;
    sam_mesh_report *rep;
    sam_error *err;
    uint32_t weld_count;     /* distinct positions */
    uint64_t candidates;     /* triangles the polygon fans make */
    uint32_t kept;           /* triangles left after the drops */
    uint32_t topo_count;     /* fans: welded positions, non-manifold ones split */
    uint32_t render_count;   /* distinct (topo vertex, UV, file normal) */
    uint32_t *weld;          /* per input vertex: welded position id */
    uint32_t *tri_weld;      /* 3 per kept triangle: welded ids */
    uint32_t *kept_corner;   /* 3 per kept triangle: input corner index */
    uint32_t *corner_topo;   /* 3 per kept triangle */
    uint32_t *fan_start;     /* weld_count + 1 */
    uint32_t *fan_corner;    /* 3 * kept: corners grouped by welded vertex */
    uint32_t *succ, *pred;   /* per corner: linked corner in fan order or NONE */
    uint32_t *render_of;     /* per corner: render vertex */
    uint32_t *by_vertex;     /* corners ordered by input vertex */
    keymap map;
} build_state;

static void build_state_free(build_state *b)
{
    free(b->weld);
    free(b->tri_weld);
    free(b->kept_corner);
    free(b->corner_topo);
    free(b->fan_start);
    free(b->fan_corner);
    free(b->succ);
    free(b->pred);
    free(b->render_of);
    free(b->by_vertex);
    keymap_free(&b->map);
}

/* Corners of a kept triangle: c = 3t + k; its fan edge runs a -> b. */
static uint32_t corner_a(uint32_t c) { return c - c % 3 + (c % 3 + 1) % 3; }
static uint32_t corner_b(uint32_t c) { return c - c % 3 + (c % 3 + 2) % 3; }

/* Where the fan of corner c starts: the head of its chain, or on a cycle,
 * which has no head, the corner after c. */
static uint32_t fan_head(const build_state *b, uint32_t c)
{
    uint32_t start = c;
    while (b->pred[start] != NONE && b->pred[start] != c)
        start = b->pred[start];
    return start;
}

/* Non-finite values would poison welding and normals, bad indices read out of bounds: errors, not repairs. */
static sam_status check_input(build_state *b)
{
    const sam_mesh_soup *in = b->in;
    const uint32_t nv = in->vertex_count;
    for (uint32_t v = 0; v < nv; ++v) {
        const float *p = in->positions + 3 * (size_t)v;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return sam_fail(b->err, SAM_ERR_FORMAT, "%s: vertex %u has a non-finite coordinate (%g, %g, %g)",
                            b->name, v, p[0], p[1], p[2]);
    }
    for (uint32_t c = 0; c < in->corner_count; ++c) {
        if (in->corners[c] >= nv)
            return sam_fail(b->err, SAM_ERR_FORMAT,
                            "%s: face corner %u refers to vertex %u (vertex count %u)", b->name, c,
                            in->corners[c], nv);
    }
    const float *uv_src = in->corner_uvs ? in->corner_uvs : in->uvs;
    if (uv_src) {
        uint32_t n = in->corner_uvs ? in->corner_count : nv;
        for (uint32_t i = 0; i < 2 * n; ++i) {
            if (!isfinite(uv_src[i]))
                return sam_fail(b->err, SAM_ERR_FORMAT, "%s: texture coordinate %u is not finite (%g)",
                                b->name, i / 2, uv_src[i]);
        }
    }
    return SAM_OK;
}

/* Files repeat a point per face or seam copy; welding equal bits gives the topology one vertex per point. */
static sam_status weld_positions(build_state *b)
{
    const sam_mesh_soup *in = b->in;
    const uint32_t nv = in->vertex_count;
    b->weld = malloc((size_t)(nv ? nv : 1) * sizeof *b->weld);
    if (!b->weld || !keymap_init(&b->map, 3, nv))
        return sam_mesh_oom(b->err, b->name);
    for (uint32_t v = 0; v < nv; ++v) {
        const float *p = in->positions + 3 * (size_t)v;
        uint32_t key[3] = {float_bits(p[0]), float_bits(p[1]), float_bits(p[2])};
        int inserted;
        b->weld[v] = keymap_get(&b->map, key, &inserted);
    }
    b->weld_count = b->map.count;
    keymap_free(&b->map);
    return SAM_OK;
}

/* A soup whose corners were rounded apart would fall apart into single
 * triangles, each its own boundary. */
static sam_status close_cracks(build_state *b)
{
    return sam_mesh_close_cracks(b->in, b->weld, &b->weld_count, &b->rep->crack_vertices_welded, b->name, b->err);
}

/* Polygons become fans around their first corner; counting first sizes the arrays and bounds the indices. */
static sam_status count_triangles(build_state *b)
{
    const sam_mesh_soup *in = b->in;
    uint64_t candidates = 0;
    for (uint32_t f = 0; f < in->face_count; ++f) {
        uint32_t m = in->face_offsets[f + 1] - in->face_offsets[f];
        if (m < 3)
            b->rep->faces_too_small++;
        else
            candidates += m - 2;
        if (m > 3)
            b->rep->polygons_triangulated++;
    }
    if (candidates > UINT32_MAX / 4)
        return sam_fail(b->err, SAM_ERR_UNSUPPORTED, "%s: %llu triangles exceed the 32-bit index range",
                        b->name, (unsigned long long)candidates);
    b->candidates = candidates;
    return SAM_OK;
}

/* |e0 x e1| = |e0||e1| sin(angle); below 1e-7 of the longest edge squared
 * the triangle is a sliver with no usable normal. */
static int is_sliver(const float *p0, const float *p1, const float *p2)
{
    double e0[3], e1[3], e2[3], n[3];
    sub3(p1, p0, e0);
    sub3(p2, p0, e1);
    sub3(p2, p1, e2);
    cross3(e0, e1, n);
    double longest = fmax(dot3(e0, e0), fmax(dot3(e1, e1), dot3(e2, e2)));
    return len3(n) <= 1e-7 * longest;
}

/* Triangles on a repeated vertex, slivers and repeats of an earlier triangle would break the fans. */
static sam_status keep_triangles(build_state *b)
{
    const sam_mesh_soup *in = b->in;
    sam_mesh_report *rep = b->rep;
    b->tri_weld = malloc((size_t)(b->candidates ? b->candidates : 1) * 3 * sizeof *b->tri_weld);
    b->kept_corner = malloc((size_t)(b->candidates ? b->candidates : 1) * 3 * sizeof *b->kept_corner);
    if (!b->tri_weld || !b->kept_corner || !keymap_init(&b->map, 3, (uint32_t)b->candidates))
        return sam_mesh_oom(b->err, b->name);
    for (uint32_t f = 0; f < in->face_count; ++f) {
        uint32_t first = in->face_offsets[f], m = in->face_offsets[f + 1] - first;
        for (uint32_t k = 1; k + 1 < m; ++k) {
            uint32_t c[3] = {first, first + k, first + k + 1};
            uint32_t w[3];
            for (int i = 0; i < 3; ++i)
                w[i] = b->weld[in->corners[c[i]]];
            if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
                rep->degenerate_triangles++;
                continue;
            }
            if (is_sliver(in->positions + 3 * (size_t)in->corners[c[0]],
                          in->positions + 3 * (size_t)in->corners[c[1]],
                          in->positions + 3 * (size_t)in->corners[c[2]])) {
                rep->zero_area_triangles++;
                continue;
            }
            uint32_t sorted[3] = {w[0], w[1], w[2]};
            for (int i = 0; i < 2; ++i)
                for (int j = i + 1; j < 3; ++j)
                    if (sorted[j] < sorted[i]) {
                        uint32_t t = sorted[i];
                        sorted[i] = sorted[j];
                        sorted[j] = t;
                    }
            int inserted;
            keymap_get(&b->map, sorted, &inserted);
            if (!inserted) {
                rep->duplicate_triangles++;
                continue;
            }
            memcpy(b->kept_corner + 3 * (size_t)b->kept, c, sizeof c);
            memcpy(b->tri_weld + 3 * (size_t)b->kept, w, sizeof w);
            b->kept++;
        }
    }
    keymap_free(&b->map);
    if (b->kept == 0)
        return sam_fail(b->err, SAM_ERR_EMPTY,
                        "%s: no usable triangle (%u faces in the file: %u with fewer than 3 corners, "
                        "%u degenerate, %u zero-area, %u duplicate)",
                        b->name, in->face_count, rep->faces_too_small, rep->degenerate_triangles,
                        rep->zero_area_triangles, rep->duplicate_triangles);
    return SAM_OK;
}

/* Faces written backwards split the fans along every edge they share
 * with the rest and render lit from the wrong side. */
static sam_status agree_windings(build_state *b)
{
    return sam_mesh_agree_windings(b->kept, b->weld_count, b->tri_weld, b->kept_corner, &b->rep->triangles_turned,
                                   b->name, b->err);
}

/* Fans are searched among one welded vertex's corners only, so those are grouped (stable counting sort).
 * The per-corner arrays of the fan stages are allocated here, before either of them counts a repair. */
static sam_status group_corners(build_state *b)
{
    const uint32_t nc = 3 * b->kept;
    b->fan_start = calloc((size_t)b->weld_count + 2, sizeof *b->fan_start);
    b->fan_corner = malloc((size_t)nc * sizeof *b->fan_corner);
    b->succ = malloc((size_t)nc * sizeof *b->succ);
    b->pred = malloc((size_t)nc * sizeof *b->pred);
    b->corner_topo = malloc((size_t)nc * sizeof *b->corner_topo);
    if (!b->fan_start || !b->fan_corner || !b->succ || !b->pred || !b->corner_topo)
        return sam_mesh_oom(b->err, b->name);
    for (uint32_t c = 0; c < nc; ++c)
        b->fan_start[b->tri_weld[c] + 2]++;
    for (uint32_t w = 0; w < b->weld_count; ++w)
        b->fan_start[w + 2] += b->fan_start[w + 1];
    for (uint32_t c = 0; c < nc; ++c)
        b->fan_corner[b->fan_start[b->tri_weld[c] + 1]++] = c;
    /* now fan_start[w] .. fan_start[w + 1] holds welded vertex w's corners */
    return SAM_OK;
}

/* Linking corners across shared edges orders each vertex's triangles around it, as rings need.
 *
 * Corner c of welded vertex w spans the fan edge a(c) -> b(c). For each
 * neighbour x of w, the edge {w, x} links the corner ending at x to the
 * corner starting at x only when exactly one of each exists (two triangles,
 * opposite windings); otherwise the edge is a boundary (one triangle) or
 * non-manifold and the fans stay apart, so every corner has at most one
 * successor and one predecessor. */
static sam_status link_fans(build_state *b)
{
    const uint32_t nc = 3 * b->kept;
    for (uint32_t c = 0; c < nc; ++c)
        b->succ[c] = b->pred[c] = NONE;
    for (uint32_t w = 0; w < b->weld_count; ++w) {
        uint32_t begin = b->fan_start[w], end = b->fan_start[w + 1];
        for (uint32_t i = begin; i < end; ++i) {
            for (int side = 0; side < 2; ++side) {
                uint32_t c = b->fan_corner[i];
                uint32_t x = b->tri_weld[side ? corner_b(c) : corner_a(c)];
                int seen = side && b->tri_weld[corner_a(c)] == x;
                for (uint32_t j = begin; j < i && !seen; ++j) {
                    uint32_t d = b->fan_corner[j];
                    seen = b->tri_weld[corner_a(d)] == x || b->tri_weld[corner_b(d)] == x;
                }
                if (seen)
                    continue;
                uint32_t starts = 0, ends = 0, s_corner = NONE, e_corner = NONE;
                for (uint32_t j = i; j < end; ++j) {
                    uint32_t d = b->fan_corner[j];
                    if (b->tri_weld[corner_a(d)] == x)
                        starts++, s_corner = d;
                    if (b->tri_weld[corner_b(d)] == x)
                        ends++, e_corner = d;
                }
                if (starts == 1 && ends == 1) {
                    b->succ[e_corner] = s_corner;
                    b->pred[s_corner] = e_corner;
                } else if (starts + ends > 1 && w < x) {
                    b->rep->non_manifold_edges++;
                }
            }
        }
    }
    return SAM_OK;
}

/* A topo vertex per fan (chain or cycle of linked corners): a welded vertex with several is split. */
static sam_status assign_topo_vertices(build_state *b)
{
    const uint32_t nc = 3 * b->kept;
    for (uint32_t c = 0; c < nc; ++c)
        b->corner_topo[c] = NONE;
    for (uint32_t w = 0; w < b->weld_count; ++w) {
        uint32_t begin = b->fan_start[w], end = b->fan_start[w + 1], fans = 0;
        for (uint32_t i = begin; i < end; ++i) {
            uint32_t c = b->fan_corner[i];
            if (b->corner_topo[c] != NONE)
                continue;
            for (uint32_t d = fan_head(b, c); d != NONE && b->corner_topo[d] == NONE; d = b->succ[d])
                b->corner_topo[d] = b->topo_count;
            b->topo_count++;
            fans++;
        }
        if (fans > 1)
            b->rep->non_manifold_vertices++;
    }
    return SAM_OK;
}

/* Fan areas and curvature walk each topo vertex's neighbours in order, so rings list them in fan order:
 * [a(c1), b(c1), ..., b(ck)], each entry the topo vertex of that corner of the triangle. */
static sam_status build_rings(build_state *b)
{
    sam_mesh *mesh = b->mesh;
    const uint32_t nc = 3 * b->kept, topo_count = b->topo_count;
    mesh->topo_count = topo_count;
    mesh->ring_offsets = calloc((size_t)topo_count + 1, sizeof *mesh->ring_offsets);
    mesh->ring = malloc(((size_t)nc + topo_count) * sizeof *mesh->ring);
    if (!mesh->ring_offsets || !mesh->ring)
        return sam_mesh_oom(b->err, b->name);
    uint32_t *fan_size = calloc((size_t)topo_count, sizeof *fan_size);
    if (!fan_size)
        return sam_mesh_oom(b->err, b->name);
    for (uint32_t c = 0; c < nc; ++c)
        fan_size[b->corner_topo[c]]++;
    for (uint32_t t = 0; t < topo_count; ++t)
        mesh->ring_offsets[t + 1] = mesh->ring_offsets[t] + fan_size[t] + 1;
    for (uint32_t c = 0; c < nc; ++c) {
        uint32_t t = b->corner_topo[c];
        if (fan_size[t] == 0)
            continue;
        /* Each fan is written once, from its chain head (or, for a cycle,
         * from the first corner met); a zeroed fan_size marks it written. */
        uint32_t start = fan_head(b, c);
        uint32_t *out = mesh->ring + mesh->ring_offsets[t];
        *out++ = b->corner_topo[corner_a(start)];
        uint32_t d = start;
        do {
            *out++ = b->corner_topo[corner_b(d)];
            d = b->succ[d];
        } while (d != NONE && d != start);
        if (b->pred[start] == NONE)
            b->rep->boundary_vertices++;
        fan_size[t] = 0;
    }
    free(fan_size);
    return SAM_OK;
}

/* The GPU needs one vertex per distinct (topo vertex, UV, file normal); input order keeps a clean file's. */
static sam_status number_render_vertices(build_state *b)
{
    const sam_mesh_soup *in = b->in;
    const uint32_t nv = in->vertex_count, nc = 3 * b->kept;
    b->render_of = malloc((size_t)nc * sizeof *b->render_of);
    b->by_vertex = calloc((size_t)nv + 1, sizeof *b->by_vertex);
    uint32_t *order = malloc((size_t)nc * sizeof *order);
    if (!b->render_of || !b->by_vertex || !order || !keymap_init(&b->map, 6, nc)) {
        free(order);
        return sam_mesh_oom(b->err, b->name);
    }
    for (uint32_t c = 0; c < nc; ++c)
        b->by_vertex[in->corners[b->kept_corner[c]] + 1]++;
    for (uint32_t v = 0; v < nv; ++v)
        b->by_vertex[v + 1] += b->by_vertex[v];
    for (uint32_t c = 0; c < nc; ++c)
        order[b->by_vertex[in->corners[b->kept_corner[c]]]++] = c;
    for (uint32_t v = 0; v < nv; ++v) {
        uint32_t used = b->by_vertex[v] - (v ? b->by_vertex[v - 1] : 0);
        if (used == 0)
            b->rep->unreferenced_vertices++;
    }
    for (uint32_t i = 0; i < nc; ++i) {
        uint32_t c = order[i], ic = b->kept_corner[c], v = in->corners[ic];
        uint32_t key[6] = {b->corner_topo[c], 0, 0, 0, 0, 0};
        if (in->corner_uvs) {
            key[1] = float_bits(in->corner_uvs[2 * (size_t)ic]);
            key[2] = float_bits(in->corner_uvs[2 * (size_t)ic + 1]);
        } else if (in->uvs) {
            key[1] = float_bits(in->uvs[2 * (size_t)v]);
            key[2] = float_bits(in->uvs[2 * (size_t)v + 1]);
        }
        if (in->corner_normals)
            for (int k = 0; k < 3; ++k)
                key[3 + k] = float_bits(in->corner_normals[3 * (size_t)ic + k]);
        else if (in->normals)
            for (int k = 0; k < 3; ++k)
                key[3 + k] = float_bits(in->normals[3 * (size_t)v + k]);
        int inserted;
        b->render_of[c] = keymap_get(&b->map, key, &inserted);
    }
    free(order);
    b->render_count = b->map.count;
    keymap_free(&b->map);
    return SAM_OK;
}

/* The mesh owns its attributes per render vertex, each linked to its topo vertex and its fan's first copy. */
/* The input face corner `c` belongs to (face_offsets increase). */
static uint32_t face_of_corner(const sam_mesh_soup *in, uint32_t c)
{
    uint32_t lo = 0, hi = in->face_count; /* face_offsets[lo] <= c < face_offsets[hi] */
    while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (in->face_offsets[mid] <= c)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static sam_status fill_render_vertices(build_state *b)
{
    const sam_mesh_soup *in = b->in;
    sam_mesh *mesh = b->mesh;
    const uint32_t nr = b->render_count, nc = 3 * b->kept, topo_count = b->topo_count;
    const int has_uvs = in->corner_uvs || in->uvs;
    mesh->vertex_count = nr;
    mesh->triangle_count = b->kept;
    mesh->positions = malloc((size_t)nr * 3 * sizeof *mesh->positions);
    mesh->normals = malloc((size_t)nr * 3 * sizeof *mesh->normals);
    mesh->uvs = has_uvs ? malloc((size_t)nr * 2 * sizeof *mesh->uvs) : NULL;
    mesh->triangles = malloc((size_t)nc * sizeof *mesh->triangles);
    mesh->topo_of = malloc((size_t)nr * sizeof *mesh->topo_of);
    mesh->topo_rep = malloc((size_t)topo_count * sizeof *mesh->topo_rep);
    mesh->topo_normals = calloc((size_t)topo_count * 3, sizeof *mesh->topo_normals);
    mesh->source_count = in->vertex_count;
    mesh->source_of_render = malloc((size_t)nr * sizeof *mesh->source_of_render);
    mesh->render_of_source = malloc(((size_t)in->vertex_count + 1) * sizeof *mesh->render_of_source);
    mesh->face_count = in->face_count;
    mesh->face_of_triangle = malloc((size_t)b->kept * sizeof *mesh->face_of_triangle);
    if (!mesh->positions || !mesh->normals || (has_uvs && !mesh->uvs) || !mesh->triangles || !mesh->topo_of ||
        !mesh->topo_rep || !mesh->topo_normals || !mesh->source_of_render || !mesh->render_of_source ||
        !mesh->face_of_triangle)
        return sam_mesh_oom(b->err, b->name);
    for (uint32_t t = 0; t < b->kept; ++t)
        mesh->face_of_triangle[t] = face_of_corner(in, b->kept_corner[3 * (size_t)t]);
    for (uint32_t t = 0; t < topo_count; ++t)
        mesh->topo_rep[t] = NONE;
    for (uint32_t r = 0; r < nr; ++r)
        mesh->source_of_render[r] = NONE;
    for (uint32_t v = 0; v < in->vertex_count; ++v)
        mesh->render_of_source[v] = SAM_MESH_DROPPED;
    for (uint32_t c = 0; c < nc; ++c) {
        uint32_t r = b->render_of[c], ic = b->kept_corner[c], v = in->corners[ic];
        mesh->triangles[c] = r;
        mesh->topo_of[r] = b->corner_topo[c];
        if (mesh->source_of_render[r] == NONE)
            mesh->source_of_render[r] = v;
        if (mesh->render_of_source[v] == SAM_MESH_DROPPED)
            mesh->render_of_source[v] = r;
        if (b->corner_topo[c] < topo_count && r < mesh->topo_rep[b->corner_topo[c]])
            mesh->topo_rep[b->corner_topo[c]] = r;
        memcpy(mesh->positions + 3 * (size_t)r, in->positions + 3 * (size_t)v, 3 * sizeof(float));
        if (in->corner_uvs)
            memcpy(mesh->uvs + 2 * (size_t)r, in->corner_uvs + 2 * (size_t)ic, 2 * sizeof(float));
        else if (in->uvs)
            memcpy(mesh->uvs + 2 * (size_t)r, in->uvs + 2 * (size_t)v, 2 * sizeof(float));
        if (in->corner_normals)
            memcpy(mesh->normals + 3 * (size_t)r, in->corner_normals + 3 * (size_t)ic, 3 * sizeof(float));
        else if (in->normals)
            memcpy(mesh->normals + 3 * (size_t)r, in->normals + 3 * (size_t)v, 3 * sizeof(float));
    }
    return SAM_OK;
}

/* Seam copies of a point must shade alike: one area-weighted normal per fan (face normal = 2 x area). */
static sam_status compute_topo_normals(build_state *b)
{
    sam_mesh *mesh = b->mesh;
    const uint32_t topo_count = b->topo_count;
    double *acc = calloc((size_t)topo_count * 3, sizeof *acc);
    if (!acc)
        return sam_mesh_oom(b->err, b->name);
    for (uint32_t t = 0; t < b->kept; ++t) {
        const float *p0 = mesh->positions + 3 * (size_t)mesh->triangles[3 * t];
        const float *p1 = mesh->positions + 3 * (size_t)mesh->triangles[3 * t + 1];
        const float *p2 = mesh->positions + 3 * (size_t)mesh->triangles[3 * t + 2];
        double e0[3], e1[3], n[3];
        sub3(p1, p0, e0);
        sub3(p2, p0, e1);
        cross3(e0, e1, n);
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i)
                acc[3 * (size_t)b->corner_topo[3 * t + k] + i] += n[i];
    }
    for (uint32_t t = 0; t < topo_count; ++t) {
        double *n = acc + 3 * (size_t)t;
        double l = len3(n);
        /* A fan folded flat onto itself cancels; any unit vector is as good. */
        if (!(l > 0))
            n[0] = 0, n[1] = 0, n[2] = 1, l = 1;
        for (int i = 0; i < 3; ++i)
            mesh->topo_normals[3 * (size_t)t + i] = (float)(n[i] / l);
    }
    free(acc);
    return SAM_OK;
}

/* A file's normals carry its creases, so they are kept (normalised); a zero-length one takes the fan's. */
static sam_status choose_render_normals(build_state *b)
{
    const sam_mesh_soup *in = b->in;
    sam_mesh *mesh = b->mesh;
    const int from_file = in->normals || in->corner_normals;
    b->rep->normals_from_file = from_file;
    for (uint32_t r = 0; r < b->render_count; ++r) {
        float *n = mesh->normals + 3 * (size_t)r;
        const float *tn = mesh->topo_normals + 3 * (size_t)mesh->topo_of[r];
        if (from_file) {
            double d[3] = {n[0], n[1], n[2]};
            double l = len3(d);
            if (l > 1e-20 && isfinite(l)) {
                for (int i = 0; i < 3; ++i)
                    n[i] = (float)(d[i] / l);
                continue;
            }
            b->rep->invalid_file_normals++;
        }
        memcpy(n, tn, 3 * sizeof(float));
    }
    return SAM_OK;
}

/* The report names seams: topo vertices with more than one render copy (split by UVs or file normals). */
static sam_status count_seams(build_state *b)
{
    uint32_t *copies = calloc((size_t)b->topo_count, sizeof *copies);
    if (!copies)
        return sam_mesh_oom(b->err, b->name);
    for (uint32_t r = 0; r < b->render_count; ++r)
        if (++copies[b->mesh->topo_of[r]] == 2)
            b->rep->seam_vertices++;
    free(copies);
    return SAM_OK;
}

sam_status sam_mesh_build(const sam_mesh_soup *in, const char *name, sam_mesh *mesh, sam_mesh_report *rep,
                          sam_error *err)
{
    static sam_status (*const stages[])(build_state *) = {
        check_input,
        weld_positions,
        close_cracks,
        count_triangles,
        keep_triangles,
        agree_windings,
        group_corners,
        link_fans,
        assign_topo_vertices,
        build_rings,
        number_render_vertices,
        fill_render_vertices,
        compute_topo_normals,
        choose_render_normals,
        count_seams,
    };
    build_state b;
    memset(&b, 0, sizeof b);
    b.in = in;
    b.name = name;
    b.mesh = mesh;
    b.rep = rep;
    b.err = err;
    rep->file_vertices = in->vertex_count;
    rep->file_faces = in->face_count;
    sam_status st = SAM_OK;
    for (size_t i = 0; i < sizeof stages / sizeof stages[0] && st == SAM_OK; ++i)
        st = stages[i](&b);
    build_state_free(&b);
    return st;
}
