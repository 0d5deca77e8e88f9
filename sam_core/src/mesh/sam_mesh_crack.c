/* Cracks closed: boundary vertices a hair apart welded (sam_mesh_internal.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_internal.h"

/* A boundary vertex in its grid cell. */
typedef struct cell_entry {
    int64_t cell[3];
    uint32_t id; /* welded id */
} cell_entry;

static int cmp_cell(const int64_t *a, const int64_t *b)
{
    for (int k = 0; k < 3; ++k)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int cmp_entry(const void *pa, const void *pb)
{
    const cell_entry *a = pa, *b = pb;
    const int c = cmp_cell(a->cell, b->cell);
    return c ? c : (a->id > b->id) - (a->id < b->id);
}

static uint32_t find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

/* Each corner's edge to the next corner of its face, counted once per
 * undirected edge: the ones used once lie on a boundary. Marks their
 * welded ends in `on_boundary`; returns how many are marked, or
 * UINT32_MAX when out of memory. */
static uint32_t mark_boundary(const sam_mesh_soup *in, const uint32_t *weld, uint32_t weld_count,
                              unsigned char *on_boundary)
{
    uint32_t *start = calloc((size_t)weld_count + 2, sizeof *start);
    uint32_t *other = malloc((size_t)(in->corner_count ? in->corner_count : 1) * sizeof *other);
    if (!start || !other) {
        free(start), free(other);
        return UINT32_MAX;
    }
    /* Edges filed under their smaller end (counting sort), the larger end kept. */
    for (int pass = 0; pass < 2; ++pass) {
        for (uint32_t f = 0; f < in->face_count; ++f) {
            const uint32_t first = in->face_offsets[f], m = in->face_offsets[f + 1] - first;
            if (m < 3)
                continue;
            for (uint32_t k = 0; k < m; ++k) {
                const uint32_t a = weld[in->corners[first + k]], b = weld[in->corners[first + (k + 1) % m]];
                if (a == b)
                    continue;
                const uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
                if (pass == 0)
                    start[lo + 2]++;
                else
                    other[start[lo + 1]++] = hi;
            }
        }
        if (pass == 0)
            for (uint32_t w = 0; w < weld_count; ++w)
                start[w + 2] += start[w + 1];
    }
    uint32_t marked = 0;
    for (uint32_t w = 0; w < weld_count; ++w) {
        for (uint32_t i = start[w]; i < start[w + 1]; ++i) {
            uint32_t uses = 0;
            for (uint32_t j = start[w]; j < start[w + 1]; ++j)
                uses += other[j] == other[i];
            if (uses != 1)
                continue;
            marked += !on_boundary[w] + !on_boundary[other[i]];
            on_boundary[w] = on_boundary[other[i]] = 1;
        }
    }
    free(start), free(other);
    return marked;
}

sam_status sam_mesh_close_cracks(const sam_mesh_soup *in, uint32_t *weld, uint32_t *weld_count, uint32_t *merged,
                                 const char *name, sam_error *err)
{
    *merged = 0;
    const uint32_t n = *weld_count;
    unsigned char *on_boundary = calloc((size_t)n + 1, 1);
    uint32_t *rep = malloc(((size_t)n + 1) * sizeof *rep); /* a vertex of each welded id */
    if (!on_boundary || !rep) {
        free(on_boundary), free(rep);
        return sam_mesh_oom(err, name);
    }
    const uint32_t marked = mark_boundary(in, weld, n, on_boundary);
    if (marked == UINT32_MAX) {
        free(on_boundary), free(rep);
        return sam_mesh_oom(err, name);
    }
    if (marked < 2) {
        free(on_boundary), free(rep);
        return SAM_OK; /* closed: nothing to close */
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < in->vertex_count; ++v) {
        rep[weld[v]] = v;
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], in->positions[3 * (size_t)v + k]);
            hi[k] = fmax(hi[k], in->positions[3 * (size_t)v + k]);
        }
    }
    const double diagonal = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                 (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double tolerance = SAM_MESH_CRACK_TOLERANCE * diagonal;
    cell_entry *e = malloc((size_t)marked * sizeof *e);
    uint32_t *parent = malloc((size_t)n * sizeof *parent);
    if (!e || !parent) {
        free(on_boundary), free(rep), free(e), free(parent);
        return sam_mesh_oom(err, name);
    }
    uint32_t count = 0;
    for (uint32_t w = 0; w < n; ++w) {
        parent[w] = w;
        if (!on_boundary[w] || !(tolerance > 0))
            continue;
        for (int k = 0; k < 3; ++k)
            e[count].cell[k] = (int64_t)floor(((double)in->positions[3 * (size_t)rep[w] + k] - lo[k]) / tolerance);
        e[count++].id = w;
    }
    qsort(e, count, sizeof *e, cmp_entry);
    /* Each pair within the tolerance lies in the same or neighbouring cells:
     * look up the 27 around each vertex. */
    for (uint32_t i = 0; i < count; ++i) {
        const float *p = in->positions + 3 * (size_t)rep[e[i].id];
        for (int d = 0; d < 27; ++d) {
            const int64_t want[3] = {e[i].cell[0] + d % 3 - 1, e[i].cell[1] + d / 3 % 3 - 1, e[i].cell[2] + d / 9 - 1};
            uint32_t a = 0, b = count;
            while (a < b) {
                const uint32_t mid = a + (b - a) / 2;
                if (cmp_cell(e[mid].cell, want) < 0)
                    a = mid + 1;
                else
                    b = mid;
            }
            for (uint32_t j = a; j < count && !cmp_cell(e[j].cell, want); ++j) {
                const float *q = in->positions + 3 * (size_t)rep[e[j].id];
                double d2 = 0;
                for (int k = 0; k < 3; ++k)
                    d2 += ((double)p[k] - q[k]) * ((double)p[k] - q[k]);
                if (e[j].id == e[i].id || d2 > tolerance * tolerance)
                    continue;
                const uint32_t ra = find(parent, e[i].id), rb = find(parent, e[j].id);
                if (ra != rb)
                    parent[ra > rb ? ra : rb] = ra < rb ? ra : rb;
            }
        }
    }
    /* Dense ids again, in the order of their smallest old id. */
    uint32_t *renumber = rep; /* no longer needed as representatives */
    uint32_t next = 0;
    for (uint32_t w = 0; w < n; ++w)
        renumber[w] = find(parent, w) == w ? next++ : UINT32_MAX;
    for (uint32_t v = 0; v < in->vertex_count; ++v)
        weld[v] = renumber[find(parent, weld[v])];
    *merged = n - next;
    *weld_count = next;
    free(on_boundary), free(rep), free(e), free(parent);
    return SAM_OK;
}
