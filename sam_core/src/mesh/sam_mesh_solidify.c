/* Thickness for single sheets (sam_mesh.h sam_mesh_solidify): a leaf or a
 * cloth card modelled as one layer of triangles has no back side, so no
 * light can come through it; offset into two faces closed by a rim, it is
 * the thin solid that SAM and the ground truth both need. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_internal.h"

/* ------------------------------------------------------------ components */

static uint32_t find_root(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

static void join(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = find_root(parent, a);
    b = find_root(parent, b);
    if (a != b)
        parent[a > b ? a : b] = a < b ? a : b;
}

/* ------------------------------------------------------------ boundary edges */

typedef struct edge_key {
    uint32_t lo, hi;  /* topo vertices, lo < hi */
    uint32_t corner;  /* 3 * triangle + k: the edge runs from corner k to k + 1 */
} edge_key;

static int edge_key_cmp(const void *pa, const void *pb)
{
    const edge_key *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->corner < b->corner ? -1 : (a->corner > b->corner);
}

/* The corners whose edge (to the next corner) no other triangle shares,
 * in triangle order; *count receives how many. NULL on running out of
 * memory. */
static uint32_t *boundary_corners(const sam_mesh *m, uint32_t *count)
{
    const size_t corners = 3 * (size_t)m->triangle_count;
    edge_key *keys = malloc(corners * sizeof *keys + 1);
    unsigned char *alone = calloc(corners + 1, 1);
    uint32_t *out = malloc(corners * sizeof *out + 1);
    if (!keys || !alone || !out) {
        free(keys), free(alone), free(out);
        return NULL;
    }
    for (size_t c = 0; c < corners; ++c) {
        const uint32_t a = m->topo_of[m->triangles[c]];
        const uint32_t b = m->topo_of[m->triangles[c - c % 3 + (c % 3 + 1) % 3]];
        keys[c] = (edge_key){a < b ? a : b, a < b ? b : a, (uint32_t)c};
    }
    qsort(keys, corners, sizeof *keys, edge_key_cmp);
    for (size_t i = 0; i < corners;) {
        size_t j = i + 1;
        while (j < corners && keys[j].lo == keys[i].lo && keys[j].hi == keys[i].hi)
            ++j;
        alone[keys[i].corner] = j == i + 1;
        i = j;
    }
    uint32_t n = 0;
    for (size_t c = 0; c < corners; ++c)
        if (alone[c])
            out[n++] = (uint32_t)c;
    free(keys), free(alone);
    *count = n;
    return out;
}

/* ------------------------------------------------------------ solidify */

/* The working arrays, freed together. */
typedef struct scratch {
    uint32_t *parent;     /* topo vertices' union-find */
    uint32_t *back_of;    /* render vertex -> its back copy, or SAM_MESH_DROPPED (closed part) */
    float *curvature;     /* topo vertices' mean curvature */
    unsigned char *open;  /* per union-find root: the part has a boundary */
    uint32_t *rim;        /* boundary corners (boundary_corners) */
    uint32_t rim_count;
} scratch;

static void scratch_free(scratch *w)
{
    free(w->parent), free(w->back_of), free(w->curvature), free(w->open), free(w->rim);
}

/* Fills `out` (allocated to size) from the mesh and the parts found in
 * `w`. Returns 0 when a face left float range. */
static int fill(const sam_mesh *mesh, double half, const scratch *w, sam_shape_mesh *out)
{
    /* The sheet is taken as the solid's mid-surface: its faces lie half
     * the thickness to either side along the normal, so it looks the same
     * from both. Seam copies share their topo vertex's normal, so they
     * move by the same bits and stay welded. */
    int finite = 1;
    for (uint32_t v = 0; v < mesh->vertex_count; ++v) {
        const float *p = mesh->positions + 3 * (size_t)v;
        const float *nrm = mesh->topo_normals + 3 * (size_t)mesh->topo_of[v];
        const uint32_t b = w->back_of[v];
        float *front = out->positions + 3 * (size_t)v;
        if (b == SAM_MESH_DROPPED) {
            memcpy(front, p, 3 * sizeof *front);
        } else {
            float *behind = out->positions + 3 * (size_t)b;
            for (int k = 0; k < 3; ++k) {
                front[k] = (float)(p[k] + half * nrm[k]);
                behind[k] = (float)(p[k] - half * nrm[k]);
                finite = finite && isfinite(front[k]) && isfinite(behind[k]);
            }
        }
        if (out->uvs) {
            memcpy(out->uvs + 2 * (size_t)v, mesh->uvs + 2 * (size_t)v, 2 * sizeof(float));
            if (b != SAM_MESH_DROPPED)
                memcpy(out->uvs + 2 * (size_t)b, mesh->uvs + 2 * (size_t)v, 2 * sizeof(float));
        }
    }
    uint32_t *tri = out->triangles;
    memcpy(tri, mesh->triangles, 3 * (size_t)mesh->triangle_count * sizeof *tri);
    tri += 3 * (size_t)mesh->triangle_count;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        const uint32_t *f = mesh->triangles + 3 * (size_t)t;
        if (w->back_of[f[0]] == SAM_MESH_DROPPED)
            continue;
        /* Wound the other way: it faces out on the other side. */
        *tri++ = w->back_of[f[0]], *tri++ = w->back_of[f[2]], *tri++ = w->back_of[f[1]];
    }
    /* A boundary edge a -> b of a front triangle (its inside to the left,
     * seen from the front) gets a quad a, b, b', a' facing away from it. */
    for (uint32_t e = 0; e < w->rim_count; ++e) {
        const uint32_t c = w->rim[e], a = mesh->triangles[c], b = mesh->triangles[c - c % 3 + (c % 3 + 1) % 3];
        *tri++ = b, *tri++ = a, *tri++ = w->back_of[a];
        *tri++ = b, *tri++ = w->back_of[a], *tri++ = w->back_of[b];
    }
    return finite;
}

static void fill_report(const sam_mesh *mesh, double half, scratch *w, sam_mesh_solidify_report *report)
{
    sam_mesh_mean_curvature(mesh, w->curvature);
    for (uint32_t v = 0; v < mesh->topo_count; ++v) {
        if (w->parent[v] == v) {
            if (w->open[v])
                ++report->open_parts;
            else
                ++report->closed_parts;
        }
        /* 2|H| is a cylinder's curvature, the shape a curled sheet takes:
         * its inner face crosses itself past a radius of half the
         * thickness. */
        if (w->open[find_root(w->parent, v)] && 2.0 * fabs((double)w->curvature[v]) * half > 1.0)
            ++report->folded_vertices;
    }
    report->rim_edges = w->rim_count;
}

sam_status sam_mesh_solidify(const sam_mesh *mesh, float thickness, sam_shape_mesh *out,
                             sam_mesh_solidify_report *report, sam_error *err)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (report)
        memset(report, 0, sizeof *report);
    if (!mesh || !out || !mesh->triangle_count || !mesh->topo_of || !mesh->topo_normals)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "solidify: a loaded mesh and an output are required");
    const double diagonal = sam_mesh_diagonal(mesh);
    const double least = SAM_SHAPE_MIN_RELATIVE_THICKNESS * diagonal;
    if (!(thickness >= least) || !isfinite(thickness) || !(thickness <= diagonal))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "solidify: a thickness of %g units is outside %.3g..%.3g (%g to 1 times the mesh's "
                        "diagonal of %.4g units: thinner, float cannot hold its two faces apart)",
                        (double)thickness, least, diagonal, SAM_SHAPE_MIN_RELATIVE_THICKNESS, diagonal);

    const uint32_t n = mesh->vertex_count, topo = mesh->topo_count;
    scratch w = {0};
    w.parent = malloc((size_t)topo * sizeof *w.parent + 1);
    w.back_of = malloc((size_t)n * sizeof *w.back_of + 1);
    w.curvature = malloc((size_t)topo * sizeof *w.curvature + 1);
    w.open = calloc((size_t)topo + 1, 1);
    w.rim = boundary_corners(mesh, &w.rim_count);
    sam_status st = SAM_OK;
    if (!w.parent || !w.back_of || !w.curvature || !w.open || !w.rim) {
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "solidify: out of memory for %u vertices", n);
        goto done;
    }
    for (uint32_t v = 0; v < topo; ++v)
        w.parent[v] = v;
    for (size_t c = 0; c < 3 * (size_t)mesh->triangle_count; c += 3)
        for (int k = 1; k < 3; ++k)
            join(w.parent, mesh->topo_of[mesh->triangles[c]], mesh->topo_of[mesh->triangles[c + k]]);
    for (uint32_t e = 0; e < w.rim_count; ++e)
        w.open[find_root(w.parent, mesh->topo_of[mesh->triangles[w.rim[e]]])] = 1;

    /* Vertices and triangles of the open parts get a back copy. */
    uint32_t back = 0, back_triangles = 0;
    for (uint32_t v = 0; v < n; ++v)
        w.back_of[v] = w.open[find_root(w.parent, mesh->topo_of[v])] ? n + back++ : SAM_MESH_DROPPED;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t)
        back_triangles += w.back_of[mesh->triangles[3 * (size_t)t]] != SAM_MESH_DROPPED;
    const uint64_t vertices = (uint64_t)n + back;
    const uint64_t triangles = (uint64_t)mesh->triangle_count + back_triangles + 2 * (uint64_t)w.rim_count;
    if (vertices > SAM_SHAPE_MAX_VERTICES || triangles > SAM_SHAPE_MAX_VERTICES) {
        st = sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "solidify: %llu vertices and %llu triangles are too many",
                      (unsigned long long)vertices, (unsigned long long)triangles);
        goto done;
    }
    out->vertex_count = (uint32_t)vertices;
    out->triangle_count = (uint32_t)triangles;
    out->positions = malloc(3 * vertices * sizeof(float));
    out->uvs = mesh->uvs ? malloc(2 * vertices * sizeof(float)) : NULL;
    out->triangles = malloc(3 * triangles * sizeof(uint32_t));
    const double half = 0.5 * (double)thickness;
    if (!out->positions || (mesh->uvs && !out->uvs) || !out->triangles)
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "solidify: out of memory for %llu vertices",
                      (unsigned long long)vertices);
    else if (!fill(mesh, half, &w, out))
        st = sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                      "solidify: faces %g units to either side of the mesh leave the range of 32-bit floats", half);
    else if (report)
        fill_report(mesh, half, &w, report);
done:
    if (st != SAM_OK)
        sam_shape_mesh_destroy(out);
    scratch_free(&w);
    return st;
}
