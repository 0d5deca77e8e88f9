/* An OBJ's per-corner normals (vn), gathered while the pre-check reads its
 * faces and matched to OpenMesh's faces afterwards (sam_mesh_soup.h):
 * OpenMesh's importer gives a vertex one normal, the last a corner named,
 * and a hard edge would be lost. */
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_soup.h"

/* Makes room for `need` elements of `size` bytes in *buf. 0 when out of memory. */
static int reserve(void **buf, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 1;
    size_t grown = *cap ? 2 * *cap : 256;
    while (grown < need)
        grown *= 2;
    void *p = realloc(*buf, grown * size);
    if (!p)
        return 0;
    *buf = p;
    *cap = grown;
    return 1;
}

/* Lets the gathered normals go: the file does not name one at every corner. */
static void drop(sam_mesh_expect *e, sam_mesh_obj_gather *g)
{
    free(e->obj_normals);
    free(e->obj_face_offsets);
    free(e->obj_corner_vertex);
    free(e->obj_corner_normal);
    e->obj_normals = NULL;
    e->obj_face_offsets = e->obj_corner_vertex = e->obj_corner_normal = NULL;
    e->obj_normal_count = 0;
    g->ok = 0;
}

void sam_mesh_expect_free(sam_mesh_expect *expect)
{
    sam_mesh_obj_gather unused;
    if (!expect)
        return;
    drop(expect, &unused);
    free(expect->rewritten);
    free(expect->corner_uvs);
    free(expect->vertex_colors);
    expect->vertex_colors = NULL;
    for (uint32_t m = 0; m < expect->material_count; ++m)
        free(expect->material_names[m]);
    free(expect->material_names);
    free(expect->face_materials);
    expect->material_names = NULL;
    expect->material_count = 0;
    expect->face_materials = NULL;
    expect->rewritten = NULL;
    expect->rewritten_size = 0;
    expect->corner_uvs = NULL;
    expect->corner_uv_count = 0;
}

int sam_mesh_obj_gather_normal(sam_mesh_expect *e, sam_mesh_obj_gather *g, uint64_t index, const float v[3])
{
    if (!g->ok)
        return 1;
    if (index >= UINT32_MAX || !reserve((void **)&e->obj_normals, &g->normal_cap, 3 * ((size_t)index + 1),
                                        sizeof *e->obj_normals))
        return 0;
    memcpy(e->obj_normals + 3 * (size_t)index, v, 3 * sizeof *v);
    e->obj_normal_count = (uint32_t)(index + 1);
    return 1;
}

int sam_mesh_obj_gather_corner(sam_mesh_expect *e, sam_mesh_obj_gather *g, uint32_t corner, uint64_t vertex,
                               int has_normal, uint64_t normal)
{
    if (!g->ok)
        return 1;
    if (!has_normal) {
        drop(e, g);
        return 1;
    }
    /* Staged past the kept faces' corners until the face is known to be kept. */
    const size_t at = (size_t)g->corner_count + corner;
    if (at >= UINT32_MAX || !reserve((void **)&e->obj_corner_vertex, &g->vertex_cap, at + 1, sizeof(uint32_t)) ||
        !reserve((void **)&e->obj_corner_normal, &g->corner_cap, at + 1, sizeof(uint32_t)))
        return 0;
    e->obj_corner_vertex[at] = (uint32_t)vertex;
    e->obj_corner_normal[at] = (uint32_t)normal;
    return 1;
}

int sam_mesh_obj_gather_face(sam_mesh_expect *e, sam_mesh_obj_gather *g, uint32_t corners)
{
    if (!g->ok)
        return 1;
    if (!reserve((void **)&e->obj_face_offsets, &g->face_cap, (size_t)g->face_count + 2, sizeof *e->obj_face_offsets))
        return 0;
    e->obj_face_offsets[0] = 0;
    g->corner_count += corners;
    e->obj_face_offsets[++g->face_count] = g->corner_count;
    return 1;
}

void sam_mesh_obj_gather_finish(sam_mesh_expect *e, sam_mesh_obj_gather *g)
{
    if (g->ok && (g->face_count == 0 || !e->obj_normals))
        drop(e, g);
}

sam_status sam_mesh_expect_corner_normals(const sam_mesh_expect *expect, const sam_mesh_soup *soup, float **out,
                                          sam_error *err)
{
    *out = NULL;
    if (!expect->obj_face_offsets || soup->face_count != expect->faces)
        return SAM_OK;
    float *n = malloc(3 * (size_t)(soup->corner_count ? soup->corner_count : 1) * sizeof *n);
    if (!n)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "out of memory for %u corner normals", soup->corner_count);
    for (uint32_t f = 0; f < soup->face_count; ++f) {
        const uint32_t first = expect->obj_face_offsets[f], end = expect->obj_face_offsets[f + 1];
        for (uint32_t c = soup->face_offsets[f]; c < soup->face_offsets[f + 1]; ++c) {
            uint32_t k = first;
            while (k < end && expect->obj_corner_vertex[k] != soup->corners[c])
                k++;
            if (k == end) {
                free(n);
                return SAM_OK; /* not the file's face: OpenMesh changed it */
            }
            memcpy(n + 3 * (size_t)c, expect->obj_normals + 3 * (size_t)expect->obj_corner_normal[k],
                   3 * sizeof *n);
        }
    }
    *out = n;
    return SAM_OK;
}
