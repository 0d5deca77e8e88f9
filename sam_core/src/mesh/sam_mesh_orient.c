/* Which side of a mesh is out: a closed mesh turned inside out, turned
 * back, and the winding number of a point (sam_mesh.h). */
#include <math.h>

#include "sam/sam_mesh.h"

double sam_mesh_signed_volume(const sam_mesh *mesh)
{
    double sum = 0;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        const float *a = mesh->positions + 3 * (size_t)mesh->triangles[3 * (size_t)t],
                    *b = mesh->positions + 3 * (size_t)mesh->triangles[3 * (size_t)t + 1],
                    *c = mesh->positions + 3 * (size_t)mesh->triangles[3 * (size_t)t + 2];
        sum += (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) +
               (double)a[1] * ((double)b[2] * c[0] - (double)b[0] * c[2]) +
               (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
    }
    return sum / 6.0;
}

int sam_mesh_is_closed(const sam_mesh *mesh)
{
    if (!mesh->topo_count)
        return 0;
    for (uint32_t t = 0; t < mesh->topo_count; ++t) {
        const uint32_t first = mesh->ring_offsets[t], last = mesh->ring_offsets[t + 1] - 1;
        if (last <= first || mesh->ring[first] != mesh->ring[last])
            return 0;
    }
    return 1;
}

int sam_mesh_orient_outward(sam_mesh *mesh)
{
    if (!sam_mesh_is_closed(mesh) || !(sam_mesh_signed_volume(mesh) < 0))
        return 0;
    for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
        uint32_t *tri = mesh->triangles + 3 * (size_t)t, keep = tri[1];
        tri[1] = tri[2];
        tri[2] = keep;
    }
    for (size_t i = 0; i < 3 * (size_t)mesh->vertex_count; ++i)
        mesh->normals[i] = -mesh->normals[i];
    for (size_t i = 0; i < 3 * (size_t)mesh->topo_count; ++i)
        mesh->topo_normals[i] = -mesh->topo_normals[i];
    /* Fan order is counter-clockwise about the outward normal: reversed. */
    for (uint32_t t = 0; t < mesh->topo_count; ++t)
        for (uint32_t i = mesh->ring_offsets[t], j = mesh->ring_offsets[t + 1] - 1; i < j; ++i, --j) {
            uint32_t keep = mesh->ring[i];
            mesh->ring[i] = mesh->ring[j];
            mesh->ring[j] = keep;
        }
    return 1;
}

double sam_mesh_winding_number(const float *positions, const uint32_t *triangles, uint32_t triangle_count,
                               const float point[3])
{
    double sum = 0;
    for (uint32_t t = 0; t < triangle_count; ++t) {
        double r[3][3], len[3];
        for (int k = 0; k < 3; ++k) {
            const float *v = positions + 3 * (size_t)triangles[3 * (size_t)t + k];
            for (int c = 0; c < 3; ++c)
                r[k][c] = (double)v[c] - point[c];
            len[k] = sqrt(r[k][0] * r[k][0] + r[k][1] * r[k][1] + r[k][2] * r[k][2]);
        }
        /* Van Oosterom and Strackee's solid angle of the triangle. */
        const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                           r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                           r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
        const double d01 = r[0][0] * r[1][0] + r[0][1] * r[1][1] + r[0][2] * r[1][2],
                     d12 = r[1][0] * r[2][0] + r[1][1] * r[2][1] + r[1][2] * r[2][2],
                     d20 = r[2][0] * r[0][0] + r[2][1] * r[0][1] + r[2][2] * r[0][2];
        const double denom = len[0] * len[1] * len[2] + d01 * len[2] + d12 * len[0] + d20 * len[1];
        sum += 2.0 * atan2(det, denom);
    }
    return sum / (4.0 * 3.14159265358979323846);
}
