/* A map's rows cut to fewer samples (samfile_fold_row, samfile_fit_samples). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "samfile_internal.h"

static float distance2(const float *a, const float *b, int dims)
{
    float sum = 0.0f;
    for (int c = 0; c < dims; ++c)
        sum += (a[c] - b[c]) * (a[c] - b[c]);
    return sum;
}

void samfile_fold_point(const float p[3], const float normal[3], const float receiver[3], float *out)
{
    /* Scaled by its largest component first: a sum of normals by area
     * may be large, and its square past float's range. */
    const float big = fmaxf(fabsf(normal[0]), fmaxf(fabsf(normal[1]), fabsf(normal[2])));
    float unit[3] = {0, 0, 0};
    if (big > 0 && isfinite(big)) {
        for (int c = 0; c < 3; ++c)
            unit[c] = normal[c] / big;
        const float len = sqrtf(distance2(unit, (const float[3]){0, 0, 0}, 3));
        for (int c = 0; c < 3; ++c)
            unit[c] /= len;
    }
    for (int c = 0; c < 3; ++c) {
        out[c] = p[c];
        out[3 + c] = unit[c];
    }
    out[6] = sqrtf(distance2(p, receiver, 3));
}

static int has_normal(const float *point)
{
    return point[3] != 0 || point[4] != 0 || point[5] != 0;
}

/* How far kept point b is from dropped point a (samfile_fold_point): the
 * turn counts only where both have a normal. */
static float fold_distance2(const float *a, const float *b)
{
    const float turn = has_normal(a) && has_normal(b) ? distance2(a + 3, b + 3, 3) : 0.0f;
    return distance2(a, b, 3) + a[6] * a[6] * turn;
}

void samfile_fold_row(const float *points, size_t stride, const float *k_rgb, uint32_t count, uint32_t kept,
                      float *out_rgb)
{
    /* Sums in double: a row's tail can be many small parts of one kept K. */
    double sum[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX], left[3] = {0, 0, 0}, held[3] = {0, 0, 0};
    for (uint32_t j = 0; j < 3 * kept; ++j) {
        sum[j] = k_rgb[j];
        held[j % 3] += k_rgb[j];
    }
    for (uint32_t i = kept; i < count; ++i) {
        const float *p = points + (size_t)i * stride;
        for (int c = 0; c < 3; ++c) {
            const float ki = k_rgb[3 * i + c];
            if (!(ki > 0))
                continue;
            /* Only a sample that outweighs it takes it: one that carries
             * next to none of a channel (skin's blue, far off) would need
             * a K' past float's range, and would swing with the pose. */
            uint32_t to = kept;
            float best = FLT_MAX;
            for (uint32_t j = 0; j < kept; ++j) {
                if (!(k_rgb[3 * j + c] >= ki))
                    continue;
                const float d = fold_distance2(p, points + (size_t)j * stride);
                if (to == kept || d < best) {
                    to = j;
                    best = d;
                }
            }
            if (to < kept)
                sum[3 * to + c] += ki;
            else
                left[c] += ki;
        }
    }
    /* What no kept sample outweighs is shared as the row's K is. */
    for (uint32_t j = 0; j < 3 * kept; ++j) {
        const int c = (int)(j % 3);
        out_rgb[j] = (float)fmin(sum[j] + (held[c] > 0 ? k_rgb[j] * (left[c] / held[c]) : 0.0), FLT_MAX);
    }
}

static float k_sum(const float *k)
{
    return k[0] + k[1] + k[2];
}

/* Whether a node's unit K (per K') holds each channel of K `k`. */
static int holds(const float unit[3], const float k[3])
{
    for (int c = 0; c < 3; ++c)
        if (k[c] > 0 && !(unit[c] > SAMFILE_MIN_UNIT_K))
            return 0;
    return 1;
}

uint32_t samfile_merge_siblings(const uint32_t *parent, const uint32_t *children, uint32_t vertex_count,
                                const float *area, size_t stride, samfile_unit_k_fn unit_k, void *user, uint32_t *id,
                                float *k_rgb, float *tau, uint32_t count, uint32_t keep)
{
    /* Pairs whose parent cannot hold their K are skipped, not retried:
     * their slots stay as they are. */
    uint32_t refused[SAMFILE_MAX_SAMPLES_PER_VERTEX], refused_count = 0;
    while (count > keep) {
        uint32_t bi = count, bj = count;
        float best_lost = 0, best_k = 0;
        for (uint32_t i = 0; i < count; ++i) {
            const uint32_t p = parent[id[i]];
            int skip = p == SAMFILE_NO_SAMPLE;
            for (uint32_t r = 0; r < refused_count && !skip; ++r)
                skip = refused[r] == p;
            if (skip)
                continue;
            for (uint32_t j = i + 1; j < count; ++j) {
                if (parent[id[j]] != p)
                    continue;
                const float lost = k_sum(k_rgb + 3 * i) * fabsf(tau[i]) + k_sum(k_rgb + 3 * j) * fabsf(tau[j]),
                            k = k_sum(k_rgb + 3 * i) + k_sum(k_rgb + 3 * j);
                if (bi == count || lost < best_lost || (lost == best_lost && k < best_k)) {
                    bi = i;
                    bj = j;
                    best_lost = lost;
                    best_k = k;
                }
            }
        }
        if (bi == count)
            break;
        float unit[3], sum[3];
        unit_k(user, parent[id[bi]], unit);
        for (int c = 0; c < 3; ++c)
            sum[c] = k_rgb[3 * bi + c] + k_rgb[3 * bj + c];
        if (!holds(unit, sum)) {
            refused[refused_count++] = parent[id[bi]];
            continue;
        }
        const uint32_t p = parent[id[bi]], first = children[2 * (size_t)(p - vertex_count)] == id[bi] ? bi : bj;
        const float a0 = area[stride * id[first]], a1 = area[stride * id[first == bi ? bj : bi]], w = a0 + a1;
        const float fa = w > 0 ? a0 / w : 0.5f, k0 = k_sum(k_rgb + 3 * first);
        id[bi] = p;
        tau[bi] = best_k > 0 ? fminf(fmaxf(fa - k0 / best_k, -1.0f), 1.0f) : 0.0f;
        for (int c = 0; c < 3; ++c)
            k_rgb[3 * bi + c] += k_rgb[3 * bj + c];
        --count;
        memmove(id + bj, id + bj + 1, (count - bj) * sizeof *id);
        memmove(tau + bj, tau + bj + 1, (count - bj) * sizeof *tau);
        memmove(k_rgb + 3 * bj, k_rgb + 3 * (bj + 1), 3 * (count - bj) * sizeof *k_rgb);
    }
    return count;
}

/* samfile_sample_points' record of each sample index with its mean
 * normal: position, area, normal, the normal's split (4 + 2 * 3 floats). */
#define RECORD 10

/* Vertex v's row of a fit, for unit_k. */
typedef struct fit_receiver {
    const float *points;
    uint32_t v;
    const sam_profile *profile;
    float mm_per_unit;
} fit_receiver;

/* The K at rest of one unit of K' for sample index `id` in the receiver's
 * row (eq. 15, as samfile_sample_k reads it). */
static void unit_k(void *user, uint32_t id, float out[3])
{
    const fit_receiver *r = user;
    const float area = samfile_sample_rd(r->points, RECORD, r->v, id, r->profile, r->mm_per_unit, out);
    for (int c = 0; c < 3; ++c)
        out[c] *= area;
}

/* Row v of `d` (`count` > `samples` entries) fitted to `samples`: siblings
 * merged in place (the row stays best first), then the entries past
 * `samples` folded into the nearest kept in place and facing. */
static void fit_row(const samfile_data *d, const float *points, const uint32_t *parent, uint32_t v, uint32_t count,
                    uint32_t samples, const sam_profile *profile, float mm_per_unit, uint32_t *index, float *kprime,
                    float *tau)
{
    const size_t n = d->samples_per_vertex;
    uint32_t id[SAMFILE_MAX_SAMPLES_PER_VERTEX];
    float k[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX], t[SAMFILE_MAX_SAMPLES_PER_VERTEX];
    for (uint32_t s = 0; s < count; ++s) {
        id[s] = d->sample_index[v * n + s];
        t[s] = d->node_count ? d->sample_tau[v * n + s] : 0.0f;
        samfile_sample_k(d, points, RECORD, v, s, profile, mm_per_unit, k + 3 * s);
    }
    fit_receiver receiver = {points, v, profile, mm_per_unit};
    if (parent)
        count = samfile_merge_siblings(parent, d->node_children, d->vertex_count, points + 3, RECORD, unit_k,
                                       &receiver, id, k, t, count, samples);
    float at[SAMFILE_FOLD_POINT_FLOATS * SAMFILE_MAX_SAMPLES_PER_VERTEX], folded[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX];
    for (uint32_t s = 0; s < count; ++s)
        samfile_fold_point(points + RECORD * (size_t)id[s], points + RECORD * (size_t)id[s] + 4,
                           points + RECORD * (size_t)v, at + SAMFILE_FOLD_POINT_FLOATS * s);
    const uint32_t keep = count < samples ? count : samples;
    samfile_fold_row(at, SAMFILE_FOLD_POINT_FLOATS, k, count, keep, folded);
    for (uint32_t s = 0; s < samples; ++s) {
        const size_t to = (size_t)v * samples + s;
        if (s >= keep) {
            index[to] = SAMFILE_NO_SAMPLE;
            if (tau)
                tau[to] = 0.0f;
            kprime[3 * to] = kprime[3 * to + 1] = kprime[3 * to + 2] = 0.0f;
            continue;
        }
        float unit[3];
        unit_k(&receiver, id[s], unit);
        index[to] = id[s];
        if (tau)
            tau[to] = t[s];
        for (int c = 0; c < 3; ++c)
            kprime[3 * to + c] = unit[c] > SAMFILE_MIN_UNIT_K ? folded[3 * s + c] / unit[c] : 1.0f;
    }
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
    const size_t vc = d->vertex_count, n = d->samples_per_vertex, all = vc + d->node_count;
    float *points = malloc(all * RECORD * sizeof *points);
    uint32_t *parent = d->node_count ? malloc(all * sizeof *parent) : NULL;
    if (!points || (d->node_count && !parent)) {
        free(points);
        free(parent);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "samfile fit: out of memory for %zu sample points", all);
    }
    for (size_t i = 0; parent && i < all; ++i)
        parent[i] = SAMFILE_NO_SAMPLE;
    for (size_t j = 0; j < d->node_count; ++j)
        parent[d->node_children[2 * j]] = parent[d->node_children[2 * j + 1]] = (uint32_t)(vc + j);
    sam_status st = samfile_sample_points(d, d->normals, 3, points, err);
    for (size_t v = 0; st == SAM_OK && v < vc; ++v) {
        uint32_t count = 0;
        while (count < n && d->sample_index[v * n + count] != SAMFILE_NO_SAMPLE)
            ++count;
        if (count > samples) {
            fit_row(d, points, parent, (uint32_t)v, count, samples, profile, mm_per_unit, index, kprime, tau);
            continue;
        }
        for (size_t s = 0; s < samples; ++s) {
            const size_t from = v * n + s, to = v * samples + s;
            index[to] = d->sample_index[from];
            if (tau)
                tau[to] = d->sample_tau[from];
            memcpy(kprime + 3 * to, d->sample_kprime + 3 * from, 3 * sizeof *kprime);
        }
    }
    free(points);
    free(parent);
    return st;
}

