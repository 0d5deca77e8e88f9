/* The ring median of per-vertex thickness (sam_thickness.h). */
#include <stdlib.h>

#include "sam/sam_thickness.h"

static int cmp_float(const void *pa, const void *pb)
{
    const float a = *(const float *)pa, b = *(const float *)pb;
    return (a > b) - (a < b);
}

sam_status sam_thickness_ring_median(uint32_t vertex_count, const uint32_t *ring_offsets, const uint32_t *ring,
                                     const float *thickness_mm, float *out, sam_error *err)
{
    if (!ring_offsets || !ring || !thickness_mm || !out || thickness_mm == out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "thickness median: needs the rings and two distinct arrays of %u floats", vertex_count);
    uint32_t widest = 0;
    for (uint32_t v = 0; v < vertex_count; ++v) {
        if (ring_offsets[v + 1] < ring_offsets[v])
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness median: ring offsets fall at vertex %u (%u, %u)",
                            v, ring_offsets[v], ring_offsets[v + 1]);
        const uint32_t size = ring_offsets[v + 1] - ring_offsets[v];
        widest = size > widest ? size : widest;
        for (uint32_t a = ring_offsets[v]; a < ring_offsets[v + 1]; ++a)
            if (ring[a] >= vertex_count)
                return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                                "thickness median: vertex %u's ring names vertex %u; there are %u", v, ring[a],
                                vertex_count);
    }
    float *values = malloc(((size_t)widest + 1) * sizeof *values);
    if (!values)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "thickness median: out of memory for a ring of %u", widest);
    for (uint32_t v = 0; v < vertex_count; ++v) {
        uint32_t count = 0;
        values[count++] = thickness_mm[v];
        for (uint32_t a = ring_offsets[v]; a < ring_offsets[v + 1]; ++a)
            values[count++] = thickness_mm[ring[a]];
        qsort(values, count, sizeof *values, cmp_float);
        out[v] = count % 2 ? values[count / 2] : 0.5f * (values[count / 2 - 1] + values[count / 2]);
    }
    free(values);
    return SAM_OK;
}
