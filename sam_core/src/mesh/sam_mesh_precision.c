/* Whether 32-bit floats can place a mesh's vertices: a mesh far from its
 * origin against its own size (a scan in georeferenced coordinates) is
 * rounded to a grid as coarse as its triangles. */
#include <math.h>
#include <stdio.h>

#include "sam/sam_mesh.h"

/* Beyond this share of the mean edge the rounding of positions showed as
 * blotches in the shading of a sphere 3e5 of its radii from the origin
 * (24% of an edge); at 3e4 radii (1.5%) the picture was clean. */
#define SAM_MESH_ROUNDING_LIMIT 0.05

int sam_mesh_precision_warning(const sam_mesh *mesh, const char *name, char *buf, size_t n)
{
    if (!buf || !n)
        return 0;
    buf[0] = '\0';
    if (!mesh || !mesh->positions || !mesh->triangles || !mesh->triangle_count)
        return 0;
    float lo[3], hi[3], far = 0;
    sam_mesh_bounds(mesh, lo, hi);
    for (int c = 0; c < 3; ++c)
        far = fmaxf(far, fmaxf(fabsf(lo[c]), fabsf(hi[c])));
    double edges = 0;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            const float *a = mesh->positions + 3 * (size_t)mesh->triangles[3 * (size_t)t + k];
            const float *b = mesh->positions + 3 * (size_t)mesh->triangles[3 * (size_t)t + (k + 1) % 3];
            const double dx = (double)a[0] - b[0], dy = (double)a[1] - b[1], dz = (double)a[2] - b[2];
            edges += sqrt(dx * dx + dy * dy + dz * dz);
        }
    const double edge = edges / (3.0 * mesh->triangle_count);
    /* The spacing of floats at the farthest coordinate, taken below it so
     * that it stays finite at FLT_MAX. */
    const double step = (double)far - nextafterf(far, 0.0f);
    if (!(edge > 0) || step <= SAM_MESH_ROUNDING_LIMIT * edge)
        return 0;
    snprintf(buf, n,
             "%s lies %.3g units from its origin, %.3g mean edges: 32-bit floats place its vertices to %.2g "
             "units there (%.0f%% of an edge), which blotches its shading; move it near the origin",
             name ? name : "the mesh", (double)far, far / edge, step, 100.0 * step / edge);
    return 1;
}
