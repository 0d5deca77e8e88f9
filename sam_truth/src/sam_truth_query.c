/* The ground truth's queries: the R_d table, a bounding-volume tree over the
 * lit samples, and eq. 7 summed over the back side within the profile's
 * radius. */
#include "sam_truth_internal.h"

#include "sam/sam_bounds.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

/* Samples per leaf of the hierarchy: small enough that a leaf straddling
 * the tangent plane costs little, large enough to keep the tree shallow. */
#define LEAF_SAMPLES 16

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

/* R_d at r model units from the table (linear between entries). */
static void rd_at(const sam_truth *t, float r, float out[3])
{
    float u = r * t->mm_per_unit * t->table_scale;
    int k = (int)u;
    if (k >= SAM_TRUTH_RD_TABLE_SIZE)
        k = SAM_TRUTH_RD_TABLE_SIZE - 1;
    float f = u - (float)k;
    const float *r0 = t->rd_table[k], *r1 = t->rd_table[k + 1];
    for (int j = 0; j < 3; ++j)
        out[j] = r0[j] + f * (r1[j] - r0[j]);
}

/* Reorders samples [begin, end) so that the one of rank `nth` along `axis`
 * is in place, smaller before it and larger after it (quickselect). */
static void select_nth(truth_sample *s, uint32_t begin, uint32_t end, uint32_t nth, int axis)
{
    while (end - begin > 1) {
        float pivot = s[begin + (end - begin) / 2].p[axis];
        uint32_t i = begin, j = end - 1;
        while (i <= j) {
            while (s[i].p[axis] < pivot)
                ++i;
            while (s[j].p[axis] > pivot)
                --j;
            if (i <= j) {
                truth_sample tmp = s[i];
                s[i] = s[j];
                s[j] = tmp;
                ++i;
                if (j == 0)
                    break;
                --j;
            }
        }
        if (nth <= j)
            end = j + 1;
        else if (nth >= i)
            begin = i;
        else
            return;
    }
}

/* Builds node `index` over samples [begin, end) and its subtree; nodes are
 * numbered so that a node's children are 2 index + 1 and 2 index + 2 of a
 * complete tree over leaves of LEAF_SAMPLES, which needs no pointers. */
static void build_node(sam_truth *t, uint32_t index, uint32_t begin, uint32_t end)
{
    truth_node *node = &t->nodes[index];
    node->begin = begin;
    node->end = end;
    for (int k = 0; k < 3; ++k) {
        node->lo[k] = node->nlo[k] = INFINITY;
        node->hi[k] = node->nhi[k] = -INFINITY;
        node->l[k] = 0;
    }
    double centre[3] = {0, 0, 0}, weight = 0;
    for (uint32_t i = begin; i < end; ++i) {
        const truth_sample *s = &t->lit[i];
        double w = (double)s->l[0] + s->l[1] + s->l[2];
        for (int k = 0; k < 3; ++k) {
            node->lo[k] = fminf(node->lo[k], s->p[k]);
            node->hi[k] = fmaxf(node->hi[k], s->p[k]);
            node->nlo[k] = fminf(node->nlo[k], s->n[k]);
            node->nhi[k] = fmaxf(node->nhi[k], s->n[k]);
            node->l[k] += s->l[k];
            centre[k] += w * s->p[k];
        }
        weight += w;
    }
    for (int k = 0; k < 3; ++k)
        node->centre[k] = weight > 0 ? (float)(centre[k] / weight) : 0.5f * (node->lo[k] + node->hi[k]);
    if (2 * index + 2 >= t->node_count || end - begin <= LEAF_SAMPLES)
        return;
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (node->hi[k] - node->lo[k] > node->hi[axis] - node->lo[axis])
            axis = k;
    uint32_t mid = begin + (end - begin) / 2;
    select_nth(t->lit, begin, end, mid, axis);
    build_node(t, 2 * index + 1, begin, mid);
    build_node(t, 2 * index + 2, mid, end);
}

sam_status truth_build_tree(sam_truth *t, const sam_profile *profile, sam_error *err)
{
    t->rd_table = malloc(sizeof *t->rd_table * (SAM_TRUTH_RD_TABLE_SIZE + 1));
    if (!t->rd_table)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "truth: out of memory for the R_d table");
    t->table_scale = (float)SAM_TRUTH_RD_TABLE_SIZE / t->radius_mm;
    for (uint32_t k = 0; k <= SAM_TRUTH_RD_TABLE_SIZE; ++k)
        sam_profile_eval(profile, (float)k / t->table_scale, t->rd_table[k]);
    /* A complete binary tree deep enough that leaves hold at most
     * LEAF_SAMPLES samples. */
    uint32_t leaves = 1;
    while ((uint64_t)leaves * LEAF_SAMPLES < t->lit_count)
        leaves *= 2;
    t->node_count = 2 * leaves - 1;
    t->nodes = malloc(sizeof *t->nodes * t->node_count);
    if (!t->nodes)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "truth: out of memory for the sample tree (%u nodes)",
                        t->node_count);
    build_node(t, 0, 0, (uint32_t)t->lit_count);
    return SAM_OK;
}

/* Adds the exact eq.-7 terms of samples [begin, end). */
static void sum_samples(const sam_truth *t, uint32_t begin, uint32_t end, const float p[3], const float n[3],
                        float radius2, double sum[3])
{
    for (uint32_t i = begin; i < end; ++i) {
        const truth_sample *s = &t->lit[i];
        float d[3] = {s->p[0] - p[0], s->p[1] - p[1], s->p[2] - p[2]};
        float dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
        float nn = s->n[0] * n[0] + s->n[1] * n[1] + s->n[2] * n[2];
        float r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (dn >= 0 || nn >= 0 || r2 >= radius2)
            continue;
        float rd[3];
        rd_at(t, sqrtf(r2), rd);
        for (int j = 0; j < 3; ++j)
            sum[j] += (double)(rd[j] * s->l[j]);
    }
}

/* Eq. 7 at one query point with unit normal n, down the tree: a node out of
 * reach, or wholly in front (eq. 13) or facing the same way (eq. 14), is
 * skipped. With a tolerance, a node wholly on the back side and in reach
 * counts as one sample at its centroid when ln(R_d(nearest) /
 * R_d(farthest)) <= sqrt(8 tolerance): evaluating a falloff at the mean
 * distance instead of averaging it errs by about (ln ratio)^2 / 8 of the
 * node's contribution (second order, as for exp(-k r): k^2 dr^2 / 8). */
static void query(const sam_truth *t, const float p[3], const float n[3], float out[3])
{
    const float radius = t->radius_mm / t->mm_per_unit, radius2 = radius * radius;
    double sum[3] = {0, 0, 0};
    uint32_t stack[64];
    int top = 0;
    if (t->lit_count)
        stack[top++] = 0;
    while (top) {
        const uint32_t index = stack[--top];
        const truth_node *node = &t->nodes[index];
        sam_bounds_range b;
        sam_bounds_classify(node->lo, node->hi, node->nlo, node->nhi, p, n, &b);
        const float near2 = b.near2, far2 = b.far2, dn_hi = b.dn_hi, nn_hi = b.nn_hi;
        if (near2 >= radius2 || b.dn_lo >= 0 || b.nn_lo >= 0)
            continue;
        const int leaf = 2 * index + 2 >= t->node_count || node->end - node->begin <= LEAF_SAMPLES;
        if (!leaf && t->tolerance > 0 && dn_hi < 0 && nn_hi < 0 && far2 < radius2) {
            float r_near[3], r_far[3];
            rd_at(t, sqrtf(near2), r_near);
            rd_at(t, sqrtf(far2), r_far);
            int flat = 1;
            for (int j = 0; j < 3; ++j)
                flat &= r_near[j] <= t->far_ratio * r_far[j];
            if (flat) {
                float d[3] = {node->centre[0] - p[0], node->centre[1] - p[1], node->centre[2] - p[2]}, rd[3];
                rd_at(t, sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), rd);
                for (int j = 0; j < 3; ++j)
                    sum[j] += (double)(rd[j] * node->l[j]);
                continue;
            }
        }
        if (leaf) {
            sum_samples(t, node->begin, node->end, p, n, radius2, sum);
        } else {
            stack[top++] = 2 * index + 1;
            stack[top++] = 2 * index + 2;
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
