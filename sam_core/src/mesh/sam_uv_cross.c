/* Where the surface goes on past each triangle edge, across UV seams too,
 * and which chart each triangle lies in: what texture-space diffusion
 * follows to blur across seams (sam_uv.h). */
#include "sam/sam_uv.h"

#include <stdlib.h>

#include "sam/sam_shape.h"

typedef struct edge_key {
    uint32_t lo, hi; /* welded ends, lo < hi */
    uint32_t at;     /* 4 * triangle + edge */
} edge_key;

static int cmp_edge(const void *pa, const void *pb)
{
    const edge_key *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return (a->at > b->at) - (a->at < b->at);
}

static uint32_t find_root(uint32_t *parent, uint32_t t)
{
    while (parent[t] != t) {
        parent[t] = parent[parent[t]];
        t = parent[t];
    }
    return t;
}

static int same_uv(const float *uvs, uint32_t a, uint32_t b)
{
    return uvs[2 * (size_t)a] == uvs[2 * (size_t)b] && uvs[2 * (size_t)a + 1] == uvs[2 * (size_t)b + 1];
}

/* Joins the two triangles of an edge into one chart when both give each
 * end the same UV. e and f: 4 * triangle + edge, the same two corners. */
static void join_if_continuous(const uint32_t *triangles, const uint32_t *weld, const float *uvs, uint32_t e,
                               uint32_t f, uint32_t *parent)
{
    const uint32_t *te = triangles + 3 * (size_t)(e >> 2), *tf = triangles + 3 * (size_t)(f >> 2);
    uint32_t ea = te[e & 3], eb = te[((e & 3) + 1) % 3], fa = tf[f & 3], fb = tf[((f & 3) + 1) % 3];
    if (weld[ea] != weld[fa]) { /* the usual case: the neighbour runs the edge the other way */
        uint32_t swap = fa;
        fa = fb;
        fb = swap;
    }
    if (same_uv(uvs, ea, fa) && same_uv(uvs, eb, fb)) {
        uint32_t ra = find_root(parent, e >> 2), rb = find_root(parent, f >> 2);
        if (ra != rb)
            parent[ra > rb ? ra : rb] = ra < rb ? ra : rb;
    }
}

sam_status sam_uv_crossings(const float *positions, const float *uvs, uint32_t vertex_count,
                            const uint32_t *triangles, uint32_t triangle_count, uint32_t *across, uint32_t *chart,
                            sam_error *err)
{
    if ((!positions || !uvs) && vertex_count > 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_uv_crossings: NULL positions or uvs for %u vertices",
                        vertex_count);
    if ((!triangles || !across || !chart) && triangle_count > 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_uv_crossings: NULL array for %u triangles",
                        triangle_count);
    if (triangle_count > SAM_UV_MAX_CROSSING_TRIANGLES)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_uv_crossings: %u triangles (at most %u)", triangle_count,
                        SAM_UV_MAX_CROSSING_TRIANGLES);
    for (size_t k = 0; k < 3 * (size_t)triangle_count; ++k)
        if (triangles[k] >= vertex_count)
            return sam_fail(err, SAM_ERR_FORMAT, "sam_uv_crossings: triangle %zu corner %zu has index %u (vertex count %u)",
                            k / 3, k % 3, triangles[k], vertex_count);
    uint32_t *weld = malloc((vertex_count ? vertex_count : 1) * sizeof *weld);
    edge_key *edges = malloc((triangle_count ? 3 * (size_t)triangle_count : 1) * sizeof *edges);
    uint32_t *parent = malloc((triangle_count ? triangle_count : 1) * sizeof *parent);
    /* Seam copies of a vertex keep its position bit for bit (sam_mesh
     * splits them so): equal positions are one place on the surface. The
     * weld only reads the positions. */
    const sam_shape_mesh places = {.vertex_count = vertex_count, .positions = (float *)positions};
    uint32_t place_count;
    sam_status st = weld && edges && parent
                        ? sam_shape_weld(&places, weld, &place_count, err)
                        : sam_fail(err, SAM_ERR_OUT_OF_MEMORY,
                                   "sam_uv_crossings: out of memory for %u vertices, %u triangles", vertex_count,
                                   triangle_count);
    if (st != SAM_OK) {
        free(weld);
        free(edges);
        free(parent);
        return st;
    }
    for (uint32_t t = 0; t < triangle_count; ++t) {
        parent[t] = t;
        for (uint32_t e = 0; e < 3; ++e) {
            uint32_t a = weld[triangles[3 * (size_t)t + e]], b = weld[triangles[3 * (size_t)t + (e + 1) % 3]];
            edges[3 * (size_t)t + e] = (edge_key){a < b ? a : b, a < b ? b : a, 4 * t + e};
            across[3 * (size_t)t + e] = SAM_UV_NO_CROSSING;
        }
    }
    const size_t edge_count = 3 * (size_t)triangle_count;
    qsort(edges, edge_count, sizeof *edges, cmp_edge);
    for (size_t k = 0; k < edge_count;) {
        size_t end = k + 1;
        while (end < edge_count && edges[end].lo == edges[k].lo && edges[end].hi == edges[k].hi)
            ++end;
        /* Two triangles, and a real edge: a boundary has one, a
         * non-manifold edge three or more (which of them would the light
         * go on into?), and a triangle folded onto one point none. */
        if (end - k == 2 && edges[k].lo != edges[k].hi) {
            const uint32_t e = edges[k].at, f = edges[k + 1].at;
            across[3 * (size_t)(e >> 2) + (e & 3)] = f;
            across[3 * (size_t)(f >> 2) + (f & 3)] = e;
            join_if_continuous(triangles, weld, uvs, e, f, parent);
        }
        k = end;
    }
    /* Roots are each chart's smallest triangle: number them in order. */
    uint32_t charts = 0;
    for (uint32_t t = 0; t < triangle_count; ++t) {
        const uint32_t r = find_root(parent, t);
        chart[t] = r == t ? charts++ : chart[r];
    }
    free(weld);
    free(edges);
    free(parent);
    return SAM_OK;
}
