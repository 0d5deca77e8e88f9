/* The ground truth's queries: the R_d table, the uniform grid over the lit
 * samples, and eq. 7 summed over the back side within the profile's radius. */
#include "sam_truth_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

/* Cells of the grid at most: enough for cells of half the radius around
 * any object a few radii across, and bounded against a tiny radius. */
#define MAX_CELLS (1u << 22)

void truth_progress_step(truth_progress *p)
{
    uint64_t done;
#pragma omp atomic capture
    done = ++p->done;
    if (p->truth->progress && omp_get_thread_num() == 0 && done >= p->next && done < p->total) {
        p->next = done + p->total / 200 + 1;
        p->truth->progress(p->truth->progress_user, p->stage, (double)done / (double)p->total);
    }
}

void truth_progress_finish(const truth_progress *p)
{
    if (p->truth->progress)
        p->truth->progress(p->truth->progress_user, p->stage, 1.0);
}

static sam_status build_table(sam_truth *t, const sam_profile *profile, sam_error *err)
{
    t->rd_table = malloc(sizeof *t->rd_table * (SAM_TRUTH_RD_TABLE_SIZE + 1));
    if (!t->rd_table)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "truth: out of memory for the R_d table");
    t->table_scale = (float)SAM_TRUTH_RD_TABLE_SIZE / t->radius_mm;
    for (uint32_t k = 0; k <= SAM_TRUTH_RD_TABLE_SIZE; ++k)
        sam_profile_eval(profile, (float)k / t->table_scale, t->rd_table[k]);
    return SAM_OK;
}

static uint32_t cell_of(const sam_truth *t, const float p[3])
{
    uint32_t c[3];
    for (int k = 0; k < 3; ++k) {
        float x = floorf((p[k] - t->grid_origin[k]) / t->cell);
        c[k] = x <= 0 ? 0 : x >= (float)(t->dims[k] - 1) ? t->dims[k] - 1 : (uint32_t)x;
    }
    return (c[2] * t->dims[1] + c[1]) * t->dims[0] + c[0];
}

sam_status truth_build_grid(sam_truth *t, const sam_profile *profile, sam_error *err)
{
    sam_status st = build_table(t, profile, err);
    if (st != SAM_OK)
        return st;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint64_t i = 0; i < t->lit_count; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fminf(lo[k], t->lit[i].p[k]);
            hi[k] = fmaxf(hi[k], t->lit[i].p[k]);
        }
    if (t->lit_count == 0)
        lo[0] = lo[1] = lo[2] = hi[0] = hi[1] = hi[2] = 0;
    /* Half-radius cells: a query's sphere touches at most 5^3 of them, about
     * 3.7 times its volume, against 6.4 times for cells of one radius. */
    double cell = 0.5 * (double)t->radius_mm / t->mm_per_unit, cells;
    for (;;) {
        cells = 1;
        for (int k = 0; k < 3; ++k)
            cells *= floor((hi[k] - lo[k]) / cell) + 1;
        if (cells <= MAX_CELLS && cells <= 8.0 * (double)t->lit_count + 1)
            break;
        cell *= 1.25;
    }
    t->cell = (float)cell;
    for (int k = 0; k < 3; ++k) {
        t->grid_origin[k] = lo[k];
        t->dims[k] = (uint32_t)floor((hi[k] - lo[k]) / cell) + 1;
    }
    uint32_t cell_count = t->dims[0] * t->dims[1] * t->dims[2];
    t->cell_start = calloc((size_t)cell_count + 1, sizeof *t->cell_start);
    uint32_t *dest = malloc(sizeof *dest * (t->lit_count ? t->lit_count : 1));
    if (!t->cell_start || !dest) {
        free(dest);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "truth: out of memory for the sample grid (%u cells)",
                        cell_count);
    }
    for (uint64_t i = 0; i < t->lit_count; ++i) {
        dest[i] = cell_of(t, t->lit[i].p);
        t->cell_start[dest[i] + 1]++;
    }
    for (uint32_t c = 0; c < cell_count; ++c)
        t->cell_start[c + 1] += t->cell_start[c];
    /* Stable counting sort into final slots, then an in-place permutation:
     * every swap puts one sample where it belongs, so no second copy of the
     * samples is needed. */
    uint32_t *fill = malloc(sizeof *fill * cell_count);
    if (!fill) {
        free(dest);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "truth: out of memory for the sample grid (%u cells)",
                        cell_count);
    }
    memcpy(fill, t->cell_start, sizeof *fill * cell_count);
    for (uint64_t i = 0; i < t->lit_count; ++i)
        dest[i] = fill[dest[i]]++;
    free(fill);
    for (uint32_t i = 0; i < t->lit_count; ++i)
        while (dest[i] != i) {
            uint32_t j = dest[i];
            truth_sample s = t->lit[j];
            t->lit[j] = t->lit[i];
            t->lit[i] = s;
            dest[i] = dest[j];
            dest[j] = j;
        }
    free(dest);
    return SAM_OK;
}

/* Eq. 7 at one query point with unit normal n. */
static void query(const sam_truth *t, const float p[3], const float n[3], float out[3])
{
    const float radius = t->radius_mm / t->mm_per_unit, radius2 = radius * radius;
    const float scale = t->mm_per_unit * t->table_scale;
    double sum[3] = {0, 0, 0};
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        float a = floorf((p[k] - radius - t->grid_origin[k]) / t->cell);
        float b = floorf((p[k] + radius - t->grid_origin[k]) / t->cell);
        if (b < 0 || a > (float)(t->dims[k] - 1)) {
            out[0] = out[1] = out[2] = 0;
            return;
        }
        lo[k] = a < 0 ? 0 : (int)a;
        hi[k] = b > (float)(t->dims[k] - 1) ? (int)t->dims[k] - 1 : (int)b;
    }
    /* How far a cell's corners reach along n from its centre. */
    const float half_extent = 0.5f * t->cell * (fabsf(n[0]) + fabsf(n[1]) + fabsf(n[2]));
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int x = lo[0]; x <= hi[0]; ++x) {
                const int c[3] = {x, y, z};
                float dist2 = 0, centre_dn = 0;
                for (int k = 0; k < 3; ++k) {
                    float b0 = t->grid_origin[k] + (float)c[k] * t->cell, b1 = b0 + t->cell;
                    float d = p[k] < b0 ? b0 - p[k] : p[k] > b1 ? p[k] - b1 : 0.0f;
                    dist2 += d * d;
                    centre_dn += (0.5f * (b0 + b1) - p[k]) * n[k];
                }
                /* Cells out of reach, or wholly in front of the tangent plane (eq. 13). */
                if (dist2 >= radius2 || centre_dn - half_extent >= 0)
                    continue;
                uint32_t cell = ((uint32_t)z * t->dims[1] + (uint32_t)y) * t->dims[0] + (uint32_t)x;
                for (uint32_t i = t->cell_start[cell]; i < t->cell_start[cell + 1]; ++i) {
                    const truth_sample *s = &t->lit[i];
                    float d[3] = {s->p[0] - p[0], s->p[1] - p[1], s->p[2] - p[2]};
                    float dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
                    float nn = s->n[0] * n[0] + s->n[1] * n[1] + s->n[2] * n[2];
                    float r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    if (dn >= 0 || nn >= 0 || r2 >= radius2)
                        continue;
                    float u = sqrtf(r2) * scale;
                    int k = (int)u;
                    if (k >= SAM_TRUTH_RD_TABLE_SIZE)
                        k = SAM_TRUTH_RD_TABLE_SIZE - 1;
                    float f = u - (float)k;
                    const float *r0 = t->rd_table[k], *r1 = t->rd_table[k + 1];
                    for (int j = 0; j < 3; ++j)
                        sum[j] += (double)((r0[j] + f * (r1[j] - r0[j])) * s->l[j]);
                }
            }
    for (int j = 0; j < 3; ++j)
        out[j] = (float)sum[j];
}

static int finite3(const float *v)
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

sam_status sam_truth_translucency(sam_truth *truth, size_t count, const float *positions, const float *normals,
                                  float *out_rgb, sam_error *err)
{
    if (!truth || !positions || !normals || !out_rgb)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth query: %s is NULL",
                        !truth ? "truth" : !positions ? "positions" : !normals ? "normals" : "out_rgb");
    if (count == 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth query: count is 0");
    for (size_t q = 0; q < count; ++q) {
        if (!finite3(positions + 3 * q))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth query: position %zu is not finite (%g, %g, %g)",
                            q, positions[3 * q], positions[3 * q + 1], positions[3 * q + 2]);
        if (!finite3(normals + 3 * q))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "truth query: normal %zu is not finite (%g, %g, %g)", q,
                            normals[3 * q], normals[3 * q + 1], normals[3 * q + 2]);
    }
    double start = sam_seconds();
    truth_progress prog = {truth, "translucency", 0, count, 0};
#pragma omp parallel for num_threads(truth->threads) schedule(dynamic, 16)
    for (size_t q = 0; q < count; ++q) {
        const float *m = normals + 3 * q;
        float len = sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        if (len > 0) {
            float n[3] = {m[0] / len, m[1] / len, m[2] / len};
            query(truth, positions + 3 * q, n, out_rgb + 3 * q);
        } else {
            out_rgb[3 * q] = out_rgb[3 * q + 1] = out_rgb[3 * q + 2] = 0;
        }
        truth_progress_step(&prog);
    }
    truth_progress_finish(&prog);
    truth->seconds += sam_seconds() - start;
    return SAM_OK;
}
