/* A map's rows cut to fewer samples (samfile_fit_samples). */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "sam/samfile.h"

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
        /* The row's K at rest as the runtime's eq. 15 gives it, whole and
         * in the kept slots. */
        double whole[3] = {0, 0, 0}, kept[3] = {0, 0, 0};
        for (size_t k = 0; k < n && d->sample_index[v * n + k] != SAMFILE_NO_SAMPLE; ++k) {
            float kc[3];
            samfile_sample_k(d, points, 4, (uint32_t)v, (uint32_t)k, profile, mm_per_unit, kc);
            for (int c = 0; c < 3; ++c) {
                whole[c] += kc[c];
                if (k < samples)
                    kept[c] += kc[c];
            }
        }
        for (size_t k = 0; k < samples; ++k) {
            const size_t from = v * n + k, to = v * samples + k;
            index[to] = d->sample_index[from];
            if (tau)
                tau[to] = d->sample_tau[from];
            /* A channel the kept slots carry nothing of stays as it is: no
             * scale puts its light anywhere. */
            for (int c = 0; c < 3; ++c) {
                const double scale = kept[c] > 0 ? whole[c] / kept[c] : 1.0;
                kprime[3 * to + c] = (float)fmin(d->sample_kprime[3 * from + c] * scale, FLT_MAX);
            }
        }
    }
    free(points);
    return st;
}
