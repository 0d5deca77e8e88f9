/* The K of every node of one vertex's cut: eq. 11 summed over the node's
 * back-side members, refined under one budget of openings per vertex. */
#include <math.h>
#include <stdlib.h>

#include "sam_build_internal.h"

/* A part of a cut node's sum that is not flat: a subnode or a member,
 * waiting to be opened or estimated. */
typedef struct part {
    uint32_t id;    /* topo vertex, or topo_count + node */
    uint32_t entry; /* the cut node it belongs to */
    float err;      /* area x the fall of mean R_d across it: which to open first */
} part;

/* A cut node's K accumulating. */
typedef struct k_sum {
    double k[3], centre[3], square;
} k_sum;

struct sam_build_cut_k_scratch {
    part *heap; /* capacity: openings + entries */
    k_sum *sum; /* entries */
};

sam_build_cut_k_scratch *sam_build_cut_k_scratch_create(uint32_t entries, uint32_t openings)
{
    sam_build_cut_k_scratch *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->heap = malloc(((size_t)openings + entries + 1) * sizeof *s->heap);
    s->sum = malloc(((size_t)entries + 1) * sizeof *s->sum);
    if (!s->heap || !s->sum) {
        sam_build_cut_k_scratch_destroy(s);
        return NULL;
    }
    return s;
}

void sam_build_cut_k_scratch_destroy(sam_build_cut_k_scratch *s)
{
    if (!s)
        return;
    free(s->heap);
    free(s->sum);
    free(s);
}

/* Adds a part of K `kv` at `at`. */
static void k_add(k_sum *s, const float at[3], const float kv[3])
{
    const double w = (double)kv[0] + kv[1] + kv[2];
    for (int c = 0; c < 3; ++c) {
        s->k[c] += kv[c];
        s->centre[c] += w * at[c];
        s->square += w * at[c] * at[c];
    }
}

#define STRADDLE_SAMPLES 8u

/* The back-side members' K of `node`, from STRADDLE_SAMPLES members drawn
 * one per equal-area stratum along the tree order (point form each, 0 for a
 * member not behind o). Unbiased; used where R_d is flat across a node
 * partly behind o (rather than opening it down to every member: the back
 * side's edge on a scan with noisy normals runs through thousands) and for
 * a subnode the budget leaves unopened. */
static void straddle_estimate(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o,
                              const float *points, const sam_build_node *node, sam_rng *rng, k_sum *s)
{
    const double *prefix = tree->area_prefix;
    const double base = prefix[node->first], span = prefix[node->first + node->count] - base;
    const float weight = (float)(span / STRADDLE_SAMPLES);
    uint32_t lo = node->first;
    for (uint32_t j = 0; j < STRADDLE_SAMPLES; ++j) {
        const double target = base + span * ((j + (double)sam_rng_float(rng)) / STRADDLE_SAMPLES);
        uint32_t hi = node->first + node->count - 1;
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (prefix[mid + 1] > target)
                hi = mid;
            else
                lo = mid + 1;
        }
        const uint32_t i = tree->perm[lo];
        if (i == o || sam_build_fan_side(ctx, o, i) == SAM_BUILD_FAN_NONE)
            continue;
        /* A uniform point of the member's fan: the samples are uniform in
         * area over the node, and so the estimate is unbiased where R_d
         * is not flat across a fan either. */
        float q[3], nq[3], rd[4];
        sam_build_sample_fan(ctx, i, rng, q, nq);
        const float *xo = points + SAM_BUILD_POINT_FLOATS * (size_t)(j % ctx->settings.mc_samples);
        if (!sam_build_point_behind(xo, xo + 3, q) || !sam_build_point_faces_away(xo + 3, nq))
            continue; /* as in sam_build_form_factor_from, pointwise */
        sam_build_rd(ctx, sam_build_distance(xo, q), rd);
        const float kv[3] = {weight * rd[0], weight * rd[1], weight * rd[2]};
        k_add(s, q, kv);
    }
}

/* What counts as flat. */
typedef struct flat_test {
    float ratio;    /* exp(sqrt(8 tol)): how much a part's own R_d may change across it */
    float floor[3]; /* per channel: a change in R_d always small enough */
} flat_test;

/* Whether a part whose R_d runs from `near` to `far` across it may count as
 * one point at its centroid. Either R_d changes across it by at most
 * `ratio` (the point form's error is then second order: about tol of the
 * part), or by at most `floor`: tol of the channel's mean R_d over the
 * back side in reach, so that all such parts together err by at most tol
 * of the vertex's transport. The floor lets far parts count as points: a
 * Gaussian tail is steep everywhere (skin's red falls 50-fold across a
 * 1.3 mm fan 20 mm away) while it carries next to nothing there. */
static int part_flat(const flat_test *t, const float near[4], const float far[4])
{
    for (int ch = 0; ch < 3; ++ch) {
        const float change = near[ch] - far[ch];
        if (change > (t->ratio - 1.0f) * far[ch] && change > t->floor[ch])
            return 0;
    }
    return 1;
}

/* Max-heap on err; ties by id and entry so that the order, and so the
 * random numbers each estimate draws, is the same on every thread. */
static int part_above(const part *a, const part *b)
{
    if (a->err != b->err)
        return a->err > b->err;
    return a->id != b->id ? a->id < b->id : a->entry < b->entry;
}

static void heap_push(part *h, uint32_t *count, part x)
{
    uint32_t i = (*count)++;
    while (i && part_above(&x, &h[(i - 1) / 2])) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = x;
}

static part heap_pop(part *h, uint32_t *count)
{
    part top = h[0], x = h[--*count];
    uint32_t i = 0;
    for (;;) {
        uint32_t c = 2 * i + 1;
        if (c >= *count)
            break;
        if (c + 1 < *count && part_above(&h[c + 1], &h[c]))
            c++;
        if (!part_above(&h[c], &x))
            break;
        h[i] = h[c];
        i = c;
    }
    if (*count)
        h[i] = x;
    return top;
}

/* One vertex's cut being summed. */
typedef struct cut_k {
    const sam_build_context *ctx;
    const sam_build_tree *tree;
    uint32_t o;
    const float *points;
    flat_test flat;
    sam_rng rng;
    sam_build_cut_k_scratch *s;
    uint32_t pending;
    uint32_t few; /* pairs of a member's cheaper Monte Carlo: STRADDLE_SAMPLES, at most the receiver's points
                   * (a steep pair takes four times as many, sam_build_pair_count) */
} cut_k;

/* Takes `id` into entry `entry`'s sum: adds it at once where it is flat,
 * queues it where it is not, drops it where no member can contribute. */
static void part_take(cut_k *c, uint32_t entry, uint32_t id)
{
    const sam_build_context *ctx = c->ctx;
    const uint32_t n = ctx->mesh->topo_count;
    const float *p = ctx->pos + 3 * (size_t)c->o;
    k_sum *s = &c->s->sum[entry];
    float r_near[4], r_far[4], rd[4], kv[3];
    if (id < n) {
        const sam_build_fan fan = id == c->o ? SAM_BUILD_FAN_NONE : sam_build_fan_side(ctx, c->o, id);
        if (fan == SAM_BUILD_FAN_NONE)
            return;
        /* A member's fan, its radius taken as sqrt(F'). */
        const float *q = ctx->pos + 3 * (size_t)id, area = ctx->fan_area[id], r = sqrtf(area);
        const float d = sam_build_distance(p, q);
        sam_build_rd_span(ctx, d, r, r_near, r_far);
        if (!part_flat(&c->flat, r_near, r_far)) {
            heap_push(c->s->heap, &c->pending, (part){id, entry, area * (r_near[3] - r_far[3])});
            return;
        }
        if (fan == SAM_BUILD_FAN_PART) {
            /* Flat, but only part of it behind: which part, the pairs tell. */
            float ev;
            sam_build_form_factor_from(ctx, c->o, c->points, id, c->few, ctx->settings.seed, 1, kv, &ev);
            k_add(s, q, kv);
            return;
        }
        sam_build_rd(ctx, d, rd);
        for (int ch = 0; ch < 3; ++ch)
            kv[ch] = area * rd[ch];
        k_add(s, q, kv);
        return;
    }
    const sam_build_node *node = &c->tree->node[id - n];
    sam_bounds_range b;
    const int side = sam_build_node_side(ctx, c->tree, id - n, c->o, &b);
    if (side == SAM_BUILD_SIDE_OUT)
        return;
    sam_build_rd(ctx, sqrtf(b.near2), r_near);
    sam_build_rd(ctx, sqrtf(b.far2), r_far);
    if (!part_flat(&c->flat, r_near, r_far)) {
        heap_push(c->s->heap, &c->pending, (part){id, entry, node->area * (r_near[3] - r_far[3])});
        return;
    }
    if (side != SAM_BUILD_SIDE_BACK) {
        straddle_estimate(ctx, c->tree, c->o, c->points, node, &c->rng, s);
        return;
    }
    sam_build_rd(ctx, sam_build_distance(p, node->centroid), rd);
    for (int ch = 0; ch < 3; ++ch)
        kv[ch] = node->area * rd[ch];
    k_add(s, node->centroid, kv);
}

void sam_build_cut_k(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, const float *points,
                     const uint32_t *ids, uint32_t count, uint32_t openings, sam_build_cut_k_scratch *scratch,
                     float *k, float *centre, float *spread)
{
    const uint32_t n = ctx->mesh->topo_count, m = ctx->settings.mc_samples;
    const float tol = ctx->settings.cut_tolerance, *p = ctx->pos + 3 * (size_t)o;
    cut_k c = {ctx, tree, o, points, {expf(sqrtf(8.0f * tol)), {0, 0, 0}}, {0}, scratch, 0,
               m < STRADDLE_SAMPLES ? m : STRADDLE_SAMPLES};
    sam_rng_seed(&c.rng, ctx->settings.seed, o, (uint64_t)n + tree->node_count);
    /* The floor: tol of each channel's mean R_d over the cut's parts, every
     * part taken as a point. */
    double rough[3] = {0, 0, 0}, rough_area = 0;
    for (uint32_t e = 0; e < count; ++e) {
        const uint32_t id = ids[e];
        const float *q = sam_build_sample_point(ctx, tree, id);
        const float area = sam_build_sample_area(ctx, tree, id);
        float rd[4];
        sam_build_rd(ctx, sam_build_distance(p, q), rd);
        for (int ch = 0; ch < 3; ++ch)
            rough[ch] += (double)area * rd[ch];
        rough_area += area;
    }
    for (int ch = 0; ch < 3; ++ch)
        c.flat.floor[ch] = rough_area > 0 ? (float)(tol * rough[ch] / rough_area) : 0.0f;
    for (uint32_t e = 0; e < count; ++e) {
        scratch->sum[e] = (k_sum){{0, 0, 0}, {0, 0, 0}, 0};
        if (ids[e] < n) {
            /* A vertex of the cut: the fans' Monte Carlo, as in a flat map. */
            float kv[3], ev;
            sam_build_form_factor_from(ctx, o, points, ids[e], m, ctx->settings.seed, 1, kv, &ev);
            k_add(&scratch->sum[e], ctx->pos + 3 * (size_t)ids[e], kv);
        } else {
            part_take(&c, e, ids[e]);
        }
    }
    /* The part whose R_d falls most across it first: while the budget
     * lasts, a subnode is opened and a member gets the fans' Monte Carlo
     * (one opening each); after, a subnode gets stratified members and a
     * member the point form. Summing until everything was flat made the
     * build grow as the square of the density: where the profile falls fast
     * against the fans (skin a few mm away), every member in reach took
     * Monte Carlo. */
    uint32_t opened = 0;
    while (c.pending) {
        const part at = heap_pop(scratch->heap, &c.pending);
        k_sum *s = &scratch->sum[at.entry];
        const int open = opened < openings;
        opened += (uint32_t)open;
        if (at.id >= n && open) {
            const sam_build_node *node = &tree->node[at.id - n];
            part_take(&c, at.entry, node->child[0]);
            part_take(&c, at.entry, node->child[1]);
        } else if (at.id >= n) {
            straddle_estimate(ctx, tree, o, points, &tree->node[at.id - n], &c.rng, s);
        } else {
            /* A member: the fans' Monte Carlo, with fewer samples once the
             * budget is spent. */
            float kv[3], ev;
            sam_build_form_factor_from(ctx, o, points, at.id, open ? m : c.few, ctx->settings.seed, 1, kv,
                                       &ev);
            k_add(s, ctx->pos + 3 * (size_t)at.id, kv);
        }
    }
    for (uint32_t e = 0; e < count; ++e) {
        const k_sum *s = &scratch->sum[e];
        const double total = s->k[0] + s->k[1] + s->k[2];
        const float *fallback = sam_build_sample_point(ctx, tree, ids[e]);
        double mean2 = 0;
        for (int ch = 0; ch < 3; ++ch) {
            k[3 * (size_t)e + ch] = (float)s->k[ch];
            centre[3 * (size_t)e + ch] = total > 0 ? (float)(s->centre[ch] / total) : fallback[ch];
            mean2 += total > 0 ? (s->centre[ch] / total) * (s->centre[ch] / total) : 0;
        }
        const double var = total > 0 ? s->square / total - mean2 : 0;
        spread[e] = var > 0 ? (float)sqrt(var) : 0.0f;
    }
}
