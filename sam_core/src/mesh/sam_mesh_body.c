/* A mesh's body, its loose specks left out (sam_mesh_body in sam_mesh.h).
 *
 * A scan's stray triangle or a modeller's forgotten fin far from the object
 * made the bounding box, and so --size-mm, the camera and the staged
 * lights, the speck's and not the object's. Pieces are found on positions
 * welded where equal (as topology welds them) so that a UV or normal seam
 * splits none,
 * and from the triangles alone, so that a map's positions and triangles
 * give the body its mesh had. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_mesh.h"

typedef struct keyed {
    float p[3];
    uint32_t v;
} keyed;

static int by_position(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    for (int c = 0; c < 3; ++c)
        if (x->p[c] != y->p[c])
            return x->p[c] < y->p[c] ? -1 : 1;
    return x->v < y->v ? -1 : x->v > y->v;
}

static uint32_t find(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v)
        v = parent[v] = parent[parent[v]];
    return v;
}

static void join(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = find(parent, a), b = find(parent, b);
    if (a != b)
        parent[a < b ? b : a] = a < b ? a : b;
}

sam_status sam_mesh_body(const sam_mesh *mesh, uint8_t *in_body, sam_mesh_body_info *info, sam_error *err)
{
    if (!mesh || !info || (mesh->vertex_count && !mesh->positions) || (mesh->triangle_count && !mesh->triangles))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_mesh_body: NULL argument");
    memset(info, 0, sizeof *info);
    const uint32_t n = mesh->vertex_count;
    uint32_t *parent = malloc(((size_t)n + 1) * sizeof *parent);
    double *area = calloc((size_t)n + 1, sizeof *area);
    keyed *key = malloc(((size_t)n + 1) * sizeof *key);
    if (!parent || !area || !key) {
        free(parent), free(area), free(key);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "sam_mesh_body: out of memory for %u vertices", n);
    }
    for (uint32_t v = 0; v < n; ++v) {
        parent[v] = v;
        memcpy(key[v].p, mesh->positions + 3 * (size_t)v, sizeof key[v].p);
        key[v].v = v;
    }
    qsort(key, n, sizeof *key, by_position);
    /* Equal as numbers, so -0 and +0 meet, as topology welds them. */
    for (uint32_t i = 1; i < n; ++i)
        if (key[i].p[0] == key[i - 1].p[0] && key[i].p[1] == key[i - 1].p[1] && key[i].p[2] == key[i - 1].p[2])
            join(parent, key[i - 1].v, key[i].v);
    free(key);
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        const uint32_t *c = mesh->triangles + 3 * (size_t)t;
        if (c[0] >= n || c[1] >= n || c[2] >= n) {
            free(parent), free(area);
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sam_mesh_body: triangle %u names vertex %u of %u", t,
                            c[0] >= n ? c[0] : c[1] >= n ? c[1] : c[2], n);
        }
        join(parent, c[0], c[1]);
        join(parent, c[0], c[2]);
    }
    double total = 0, largest = 0;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        const uint32_t *c = mesh->triangles + 3 * (size_t)t;
        const float *a = mesh->positions + 3 * (size_t)c[0], *b = mesh->positions + 3 * (size_t)c[1],
                    *d = mesh->positions + 3 * (size_t)c[2];
        const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        const double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
                     z = e1[0] * e2[1] - e1[1] * e2[0];
        const double at = 0.5 * sqrt(x * x + y * y + z * z);
        area[find(parent, c[0])] += at;
        total += at;
    }
    for (uint32_t v = 0; v < n; ++v)
        if (parent[v] == v && area[v] > largest)
            largest = area[v];
    /* A mesh with no area (or no triangles) keeps every vertex. */
    const double cut = SAM_MESH_LOOSE_FRACTION * largest;
    float lo[3], hi[3]; /* every vertex's bounds */
    for (int c = 0; c < 3; ++c)
        info->min[c] = lo[c] = INFINITY, info->max[c] = hi[c] = -INFINITY;
    for (uint32_t v = 0; v < n; ++v) {
        for (int c = 0; c < 3; ++c) {
            lo[c] = fminf(lo[c], mesh->positions[3 * (size_t)v + c]);
            hi[c] = fmaxf(hi[c], mesh->positions[3 * (size_t)v + c]);
        }
        const uint32_t root = find(parent, v);
        const int kept = !(area[root] < cut);
        if (in_body)
            in_body[v] = (uint8_t)kept;
        if (!kept) {
            info->loose_vertices++;
            if (root == v) {
                info->loose_pieces++;
                info->loose_area += area[v];
            }
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            info->min[c] = fminf(info->min[c], mesh->positions[3 * (size_t)v + c]);
            info->max[c] = fmaxf(info->max[c], mesh->positions[3 * (size_t)v + c]);
        }
    }
    info->total_area = total;
    for (int c = 0; c < 3; ++c)
        info->box_changed |= lo[c] != info->min[c] || hi[c] != info->max[c];
    free(parent), free(area);
    return SAM_OK;
}
