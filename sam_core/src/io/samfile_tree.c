/* The CPU's node pass over a cut map's tree (samfile_sample_points), and
 * a sample's K read from it (samfile_sample_k). */
#include <math.h>

#include "samfile_internal.h"

float samfile_sample_rd(const float *points, size_t stride, uint32_t v, uint32_t id, const sam_profile *profile,
                        float mm_per_unit, float rd[3])
{
    const float *p = points + stride * v, *q = points + stride * id;
    const float dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
    sam_profile_eval(profile, mm_per_unit * sqrtf(dx * dx + dy * dy + dz * dz), rd);
    return q[3];
}

void samfile_sample_k(const samfile_data *d, const float *points, size_t stride, uint32_t v, uint32_t k,
                      const sam_profile *profile, float mm_per_unit, float k_rgb[3])
{
    const size_t slot = (size_t)v * d->samples_per_vertex + k;
    float rd[3];
    const float area = samfile_sample_rd(points, stride, v, d->sample_index[slot], profile, mm_per_unit, rd);
    for (int c = 0; c < 3; ++c)
        k_rgb[c] = d->sample_kprime[3 * slot + c] * area * rd[c];
}

sam_status samfile_sample_points(const samfile_data *d, const float *values, uint32_t channels, float *out,
                                 sam_error *err)
{
    if (!d || !out || (channels && !values) || channels > 16)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "samfile sample points: %s",
                        !d || !out ? "no data or no output" : channels > 16 ? "more than 16 channels" : "no values");
    const size_t vc = d->vertex_count, stride = 4 + 2 * (size_t)channels;
    for (size_t v = 0; v < vc; ++v) {
        float *o = out + stride * v;
        for (int c = 0; c < 3; ++c)
            o[c] = d->positions[3 * v + c];
        o[3] = d->fan_area[v];
        for (uint32_t c = 0; c < channels; ++c)
            o[4 + c] = values[channels * v + c], o[4 + channels + c] = 0.0f;
    }
    /* Deepest level first, children before parents; the same weights and
     * zero-area rule as shaders/nodes.comp. */
    for (uint32_t l = d->level_count; l-- > 0;)
        for (uint32_t j = d->level_offsets[l]; j < d->level_offsets[l + 1]; ++j) {
            const float *a = out + stride * d->node_children[2 * (size_t)j],
                        *b = out + stride * d->node_children[2 * (size_t)j + 1];
            float *o = out + stride * (vc + j), w = a[3] + b[3], fa = w > 0 ? a[3] / w : 0.5f, fb = 1.0f - fa;
            for (int c = 0; c < 3; ++c)
                o[c] = fa * a[c] + fb * b[c];
            o[3] = w;
            for (uint32_t c = 0; c < channels; ++c) {
                o[4 + c] = w > 0 ? fa * a[4 + c] + fb * b[4 + c] : 0.0f;
                o[4 + channels + c] = b[4 + c] - a[4 + c];
            }
        }
    return SAM_OK;
}
