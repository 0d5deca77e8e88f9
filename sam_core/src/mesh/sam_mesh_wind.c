/* Triangles turned to agree with their neighbours (sam_mesh_internal.h). */
#include <stdlib.h>
#include <string.h>

#include "sam_mesh_internal.h"

/* +1 when triangle t runs a -> b, -1 when it runs b -> a, 0 when it does
 * not hold both. */
static int runs(const uint32_t *tri, uint32_t t, uint32_t a, uint32_t b)
{
    for (int k = 0; k < 3; ++k) {
        const uint32_t from = tri[3 * (size_t)t + k], to = tri[3 * (size_t)t + (k + 1) % 3];
        if (from == a && to == b)
            return 1;
        if (from == b && to == a)
            return -1;
    }
    return 0;
}

sam_status sam_mesh_agree_windings(uint32_t triangle_count, uint32_t vertex_count, uint32_t *tri, uint32_t *corner,
                                   uint32_t *turned, const char *name, sam_error *err)
{
    *turned = 0;
    uint32_t *start = calloc((size_t)vertex_count + 2, sizeof *start);
    uint32_t *around = malloc(3 * (size_t)(triangle_count ? triangle_count : 1) * sizeof *around);
    uint32_t *queue = malloc((size_t)(triangle_count ? triangle_count : 1) * sizeof *queue);
    signed char *sign = calloc((size_t)triangle_count + 1, sizeof *sign); /* 0: not reached; +1 kept; -1 turned */
    if (!start || !around || !queue || !sign) {
        free(start), free(around), free(queue), free(sign);
        return sam_mesh_oom(err, name);
    }
    /* The triangles around each vertex (counting sort). */
    for (size_t c = 0; c < 3 * (size_t)triangle_count; ++c)
        start[tri[c] + 2]++;
    for (uint32_t v = 0; v < vertex_count; ++v)
        start[v + 2] += start[v + 1];
    for (size_t c = 0; c < 3 * (size_t)triangle_count; ++c)
        around[start[tri[c] + 1]++] = (uint32_t)(c / 3);
    /* Across every edge two triangles share, they must run it in opposite
     * directions. Each connected part, walked breadth first from its first
     * triangle, keeps the winding most of its triangles have: a file with a
     * few faces written backwards is mended, not turned inside out. An
     * edge of three or more triangles carries no rule; a part that cannot
     * agree (a Moebius strip) keeps the first answer its walk gives. */
    for (uint32_t seed = 0; seed < triangle_count; ++seed) {
        if (sign[seed])
            continue;
        uint32_t head = 0, tail = 0, against = 0;
        sign[seed] = 1;
        queue[tail++] = seed;
        while (head < tail) {
            const uint32_t t = queue[head++];
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = tri[3 * (size_t)t + k], b = tri[3 * (size_t)t + (k + 1) % 3];
                uint32_t other = UINT32_MAX, sharing = 0;
                for (uint32_t i = start[a]; i < start[a + 1]; ++i) {
                    const uint32_t u = around[i];
                    if (u != t && runs(tri, u, a, b)) {
                        other = u;
                        sharing++;
                    }
                }
                if (sharing != 1 || sign[other])
                    continue;
                /* t runs a -> b (times its sign); other must run b -> a. */
                sign[other] = (signed char)(-runs(tri, other, a, b) * sign[t]);
                against += sign[other] < 0;
                queue[tail++] = other;
            }
        }
        const int flip_part = 2 * against > tail;
        for (uint32_t i = 0; i < tail; ++i) {
            const uint32_t t = queue[i];
            if ((sign[t] < 0) == flip_part)
                continue;
            uint32_t *w = tri + 3 * (size_t)t, *c = corner + 3 * (size_t)t, x;
            x = w[1], w[1] = w[2], w[2] = x;
            x = c[1], c[1] = c[2], c[2] = x;
            ++*turned;
        }
    }
    free(start), free(around), free(queue), free(sign);
    return SAM_OK;
}
