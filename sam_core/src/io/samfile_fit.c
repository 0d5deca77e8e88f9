/* A map's rows cut to fewer samples (samfile_fold_row, samfile_fit_samples). */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "sam/samfile.h"

static float distance2(const float *a, const float *b)
{
    const float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

void samfile_fold_row(const float *points, size_t stride, const float *k_rgb, uint32_t count, uint32_t kept,
                      float *out_rgb)
{
    /* Sums in double: a row's tail can be many small parts of one kept K. */
    double sum[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX];
    for (uint32_t j = 0; j < 3 * kept; ++j)
        sum[j] = k_rgb[j];
    for (uint32_t i = kept; i < count; ++i) {
        const float *p = points + (size_t)i * stride;
        for (int c = 0; c < 3; ++c) {
            if (!(k_rgb[3 * i + c] > 0))
                continue;
            uint32_t to = kept;
            float best = FLT_MAX;
            for (uint32_t j = 0; j < kept; ++j) {
                if (!(k_rgb[3 * j + c] > 0))
                    continue;
                const float d = distance2(p, points + (size_t)j * stride);
                if (to == kept || d < best) {
                    to = j;
                    best = d;
                }
            }
            if (to < kept)
                sum[3 * to + c] += k_rgb[3 * i + c];
        }
    }
    for (uint32_t j = 0; j < 3 * kept; ++j)
        out_rgb[j] = (float)fmin(sum[j], FLT_MAX);
}

sam_status samfile_fit_samples(const samfile_data *d, uint32_t samples, const sam_profile *profile,
                               float mm_per_unit, uint32_t *index, float *kprime, float *tau, sam_error *err)
{
    if (!d || !profile || !index || !kprime || (d->node_count && !tau))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "samfile fit: no data, profile or output");
    if (samples == 0 || samples > d->samples_per_vertex || !(mm_per_unit > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "samfile fit: %u samples of the map's %u per vertex, at %g mm per unit", samples,
                        d->samples_per_vertex, (double)mm_per_unit);
    const size_t vc = d->vertex_count, n = d->samples_per_vertex;
    float *points = malloc((vc + d->node_count) * 4 * sizeof *points);
    if (!points)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "samfile fit: out of memory for %zu sample points",
                        vc + (size_t)d->node_count);
    sam_status st = samfile_sample_points(d, NULL, 0, points, err);
    for (size_t v = 0; st == SAM_OK && v < vc; ++v) {
        /* The row's K at rest as the runtime's eq. 15 gives it, and where
         * each sample stands. */
        float k[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX], at[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX],
            folded[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX];
        uint32_t count = 0;
        while (count < n && d->sample_index[v * n + count] != SAMFILE_NO_SAMPLE) {
            samfile_sample_k(d, points, 4, (uint32_t)v, count, profile, mm_per_unit, k + 3 * count);
            for (int c = 0; c < 3; ++c)
                at[3 * count + c] = points[4 * (size_t)d->sample_index[v * n + count] + c];
            ++count;
        }
        const uint32_t keep = count < samples ? count : samples;
        samfile_fold_row(at, 3, k, count, keep, folded);
        for (size_t s = 0; s < samples; ++s) {
            const size_t from = v * n + s, to = v * samples + s;
            index[to] = d->sample_index[from];
            if (tau)
                tau[to] = d->sample_tau[from];
            /* A channel the sample carries nothing of stays as it is: no
             * scale puts light there. */
            for (int c = 0; c < 3; ++c) {
                const double scale = s < keep && k[3 * s + c] > 0 ? (double)folded[3 * s + c] / k[3 * s + c] : 1.0;
                kprime[3 * to + c] = (float)fmin(d->sample_kprime[3 * from + c] * scale, FLT_MAX);
            }
        }
    }
    free(points);
    return st;
}
