/*
 * Internal: what sam_mesh.c and sam_mesh_build.c share. sam_mesh.c holds the
 * public entry points and the computations on a built mesh; sam_mesh_build.c
 * turns a polygon soup into a mesh (welding, repairs, topology, normals).
 */
#ifndef SAM_MESH_INTERNAL_H
#define SAM_MESH_INTERNAL_H

#include <math.h>

#include "sam/sam_mesh.h"
#include "sam_mesh_soup.h"

/* Differences are taken in double so that thin triangles far from the
 * origin keep their shape. */
static inline void sub3(const float *a, const float *b, double *out)
{
    out[0] = (double)a[0] - b[0];
    out[1] = (double)a[1] - b[1];
    out[2] = (double)a[2] - b[2];
}

static inline void cross3(const double *a, const double *b, double *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline double len3(const double *a)
{
    return sqrt(dot3(a, a));
}

/* One message for every allocation failure of loading, naming the mesh.
 * Inline: the build's stages in their own files use it too. */
static inline sam_status sam_mesh_oom(sam_error *err, const char *name)
{
    return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory while building the mesh", name);
}

/* Boundary vertices closer than this times the mesh's diagonal are one:
 * exporters that write each face's corners on their own round them apart
 * by about 1e-7 to 1e-6 of the size, and a real gap that narrow does not
 * show. */
#define SAM_MESH_CRACK_TOLERANCE 1e-5

/* Welds vertices on the boundary of the soup (its faces' edges used once,
 * after the exact weld `weld`: per input vertex a welded id < *weld_count)
 * that lie within SAM_MESH_CRACK_TOLERANCE of the diagonal of another:
 * `weld` and *weld_count are renumbered (dense, in the order of each
 * group's smallest old id) and the ids merged away go to *merged. A closed
 * soup is left as it is. Errors: SAM_ERR_OUT_OF_MEMORY naming `name`.
 * (sam_mesh_crack.c) */
sam_status sam_mesh_close_cracks(const sam_mesh_soup *in, uint32_t *weld, uint32_t *weld_count, uint32_t *merged,
                                 const char *name, sam_error *err);

/* Turns triangles so that every edge two of them share is run in opposite
 * directions, as an orientable surface's are: each connected part keeps the
 * winding most of its triangles have. `tri` holds 3 welded vertex ids
 * (< vertex_count) per triangle and `corner` 3 parallel values that move
 * with them; a turned triangle swaps its second and third of both. The
 * count turned goes to *turned. Errors: SAM_ERR_OUT_OF_MEMORY naming
 * `name`. (sam_mesh_wind.c) */
sam_status sam_mesh_agree_windings(uint32_t triangle_count, uint32_t vertex_count, uint32_t *tri, uint32_t *corner,
                                   uint32_t *turned, const char *name, sam_error *err);

/* Welds, triangulates, repairs and builds the topology of `in` into `mesh`,
 * counting every repair in `rep` (also on failure). `name` is for messages.
 * On failure `mesh` may hold partial arrays: the caller destroys it. */
sam_status sam_mesh_build(const sam_mesh_soup *in, const char *name, sam_mesh *mesh, sam_mesh_report *rep,
                          sam_error *err);

#endif
