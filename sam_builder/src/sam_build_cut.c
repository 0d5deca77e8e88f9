/* The cut map: per vertex, a cut through the cluster tree (lightcuts'
 * refinement) and each cut node's K by stratified Monte Carlo. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "sam/sam_bounds.h"
#include "sam_build_internal.h"

/* A node or vertex of a vertex's cut. `id` < topo_count is a topo vertex,
 * else topo_count + node. */
typedef struct cut_entry {
    uint32_t id;
    int back;       /* 1: every member is on the back side; 0: some are not (K counts those that are) */
    float priority; /* back: area x the fall of mean R_d across it; mixed: area x R_d at its nearest point */
    float estimate; /* back: area x mean R_d at its centroid; mixed: 0 */
    float k[3], k_error;
    float tau;      /* node_tau; 0 for a vertex */
} cut_entry;



enum { SIDE_OUT, SIDE_BACK, SIDE_PARTLY };

/* Where `node` lies for receiver o, from its boxes (filled into `b`):
 * SIDE_OUT when no member can contribute (all in front, all facing o's way
 * or all beyond the search radius), SIDE_BACK when every member is behind
 * (eq. 13-14), else SIDE_PARTLY. */
static int node_side(const sam_build_context *ctx, const sam_build_node *node, uint32_t o, sam_bounds_range *b)
{
    const float *p = ctx->pos + 3 * (size_t)o, *nrm = ctx->mesh->topo_normals + 3 * (size_t)o;
    sam_bounds_classify(node->lo, node->hi, node->nlo, node->nhi, p, nrm, b);
    if (b->near2 >= ctx->search_radius * ctx->search_radius || b->dn_lo >= 0 || b->nn_lo >= 0)
        return SIDE_OUT;
    /* The members' own test is float arithmetic on coordinates of this
     * size: "wholly behind" keeps a margin above its rounding. */
    const float scale = fmaxf(fmaxf(fabsf(p[0]), fabsf(p[1])), fabsf(p[2])) + sqrtf(b->far2);
    return b->dn_hi < -1e-5f * scale && b->nn_hi < -1e-5f ? SIDE_BACK : SIDE_PARTLY;
}

/* Classifies `id` for receiver o. Returns 0 when no member can contribute
 * (all in front, all facing o's way, or all beyond the search radius). */
static int classify(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t id, cut_entry *e)
{
    const uint32_t n = ctx->mesh->topo_count;
    const float *p = ctx->pos + 3 * (size_t)o;
    const float radius = ctx->search_radius;
    memset(e, 0, sizeof *e);
    e->id = id;
    if (id < n) {
        if (id == o || !sam_build_is_back_side(ctx, o, id))
            return 0;
        const float *q = ctx->pos + 3 * (size_t)id;
        const float d = sam_build_distance(p, q);
        if (d >= radius)
            return 0;
        e->back = 1;
        e->estimate = ctx->fan_area[id] * sam_build_rd_mean(ctx, d);
        return 1;
    }
    const sam_build_node *node = &tree->node[id - n];
    sam_bounds_range b;
    const int side = node_side(ctx, node, o, &b);
    if (side == SIDE_OUT)
        return 0;
    const float near = sam_build_rd_mean(ctx, sqrtf(b.near2));
    e->back = side == SIDE_BACK;
    if (e->back) {
        const float *c = node->centroid;
        e->priority = node->area * fmaxf(near - sam_build_rd_mean(ctx, sqrtf(b.far2)), 0.0f);
        e->estimate = node->area * sam_build_rd_mean(ctx, sam_build_distance(p, c));
    } else {
        e->priority = node->area * near;
    }
    return 1;
}

/* Adds a part of mean-RGB K at `at` to a K-weighted sum of positions. */
static void add_centre(double centre[3], const float at[3], const float k[3])
{
    const double w = (double)k[0] + k[1] + k[2];
    for (int c = 0; c < 3; ++c)
        centre[c] += w * at[c];
}

#define STRADDLE_SAMPLES 8u

/* The back-side members' K of `node`, where R_d is flat across it, from
 * STRADDLE_SAMPLES members drawn one per equal-area stratum along the tree
 * order (point form each, 0 for a member not behind o); adds to `centre`. */
static void straddle_estimate(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o,
                              const sam_build_node *node, sam_rng *rng, float k[3], double centre[3])
{
    const double *prefix = tree->area_prefix;
    const double base = prefix[node->first], span = prefix[node->first + node->count] - base;
    const float *p = ctx->pos + 3 * (size_t)o;
    double sum[3] = {0, 0, 0};
    uint32_t lo = node->first;
    for (uint32_t s = 0; s < STRADDLE_SAMPLES; ++s) {
        const double target = base + span * ((s + (double)sam_rng_float(rng)) / STRADDLE_SAMPLES);
        uint32_t hi = node->first + node->count - 1;
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (prefix[mid + 1] > target)
                hi = mid;
            else
                lo = mid + 1;
        }
        const uint32_t i = tree->perm[lo];
        if (i == o || !sam_build_is_back_side(ctx, o, i))
            continue;
        const float *q = ctx->pos + 3 * (size_t)i;
        float rd[4];
        sam_build_rd(ctx, sam_build_distance(p, q), rd);
        const float kv[3] = {(float)span / STRADDLE_SAMPLES * rd[0], (float)span / STRADDLE_SAMPLES * rd[1],
                             (float)span / STRADDLE_SAMPLES * rd[2]};
        for (int c = 0; c < 3; ++c)
            sum[c] += kv[c];
        add_centre(centre, q, kv);
    }
    for (int c = 0; c < 3; ++c)
        k[c] = (float)sum[c];
}

/* K of node j for receiver o: eq. 11 summed over its members, down its
 * subtree as the ground truth sums eq. 7. A subnode across which mean R_d
 * changes by a ratio of at most `flat_ratio` = exp(sqrt(8 tol)) counts as
 * one point at its centroid, F R_d(|c - x_o|), where every channel's does (the error of evaluating a
 * falloff at the mean distance is second order: about tol of that part);
 * so does a member whose R_d is flat across its fan; a nearer member gets
 * the fans' Monte Carlo form factor, as in a flat map, and the standard
 * errors add in quadrature. Deterministic but
 * for those members, so neighbouring vertices get smoothly varying K. */
static void node_form_factor(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o,
                             const float *points, uint32_t j, float flat_ratio, float k[3], float *k_error,
                             float k_centre[3])
{
    double centre[3] = {0, 0, 0};
    const uint32_t n = ctx->mesh->topo_count;
    const float *p = ctx->pos + 3 * (size_t)o;
    double sum[3] = {0, 0, 0}, var = 0;
    sam_rng rng;
    sam_rng_seed(&rng, ctx->settings.seed, o, (uint64_t)n + j);
    uint32_t stack[64];
    int top = 0;
    stack[top++] = n + j;
    while (top) {
        const uint32_t id = stack[--top];
        if (id < n) {
            if (id == o || !sam_build_is_back_side(ctx, o, id))
                continue;
            /* A member whose fan R_d hardly changes across (its fan's
             * radius taken as sqrt(F')) takes the point form too; only the
             * near ones need the fans' Monte Carlo. */
            const float *q = ctx->pos + 3 * (size_t)id, area = ctx->fan_area[id], r = sqrtf(area);
            const float d = sam_build_distance(p, q);
            float r_near[4], r_far[4];
            sam_build_rd(ctx, fmaxf(d - r, 0.0f), r_near);
            sam_build_rd(ctx, d + r, r_far);
            int flat = 1;
            for (int ch = 0; ch < 3; ++ch)
                flat &= r_near[ch] <= flat_ratio * r_far[ch];
            float kv[3], ev = 0;
            if (flat) {
                float rd[4];
                sam_build_rd(ctx, d, rd);
                for (int ch = 0; ch < 3; ++ch)
                    kv[ch] = area * rd[ch];
            } else {
                sam_build_form_factor_from(ctx, o, points, id, ctx->settings.mc_samples, ctx->settings.seed, kv, &ev);
            }
            for (int c = 0; c < 3; ++c)
                sum[c] += kv[c];
            var += (double)ev * ev;
            add_centre(centre, q, kv);
            continue;
        }
        const sam_build_node *node = &tree->node[id - n];
        sam_bounds_range b;
        /* Only back-side members count: a part wholly in front, facing v_o's
         * way or out of reach adds nothing, one partly behind is opened. */
        const int side = node_side(ctx, node, o, &b);
        if (side == SIDE_OUT)
            continue;
        const int back = side == SIDE_BACK;
        float r_near[4], r_far[4];
        sam_build_rd(ctx, sqrtf(b.near2), r_near);
        sam_build_rd(ctx, sqrtf(b.far2), r_far);
        int flat = 1;
        for (int ch = 0; ch < 3; ++ch)
            flat &= r_near[ch] <= flat_ratio * r_far[ch];
        if (flat && !back) {
            /* Partly behind where R_d is flat: rather than open it down to
             * every member (the back side's edge on a scan with noisy
             * normals runs through thousands), STRADDLE_SAMPLES members
             * stratified by area, each counted when it is behind. Unbiased;
             * its noise averages over the many such parts of a node. */
            float kv[3];
            straddle_estimate(ctx, tree, o, node, &rng, kv, centre);
            for (int ch = 0; ch < 3; ++ch)
                sum[ch] += kv[ch];
            continue;
        }
        if (flat) {
            const float *c = node->centroid;
            float rd[4];
            sam_build_rd(ctx, sam_build_distance(p, c), rd);
            float kv[3] = {node->area * rd[0], node->area * rd[1], node->area * rd[2]};
            for (int ch = 0; ch < 3; ++ch)
                sum[ch] += kv[ch];
            add_centre(centre, c, kv);
            continue;
        }
        stack[top++] = node->child[0];
        stack[top++] = node->child[1];
    }
    const double total = sum[0] + sum[1] + sum[2];
    for (int c = 0; c < 3; ++c) {
        k[c] = (float)sum[c];
        k_centre[c] = total > 0 ? (float)(centre[c] / total) : tree->node[j].centroid[c];
    }
    *k_error = (float)sqrt(var);
}

/* Where along node j's split its light comes from: the K-weighted centre's
 * offset from the centroid, projected on the line between its children's
 * centroids, in units of that line (clamped to [-1, 1]). The runtime reads
 * the node's L_d moved by tau times the children's difference: exact for
 * L_d that changes linearly along the split. */
static float node_tau(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t j, const float k_centre[3])
{
    const uint32_t n = ctx->mesh->topo_count;
    const sam_build_node *node = &tree->node[j];
    const float *c0 = node->child[0] < n ? ctx->pos + 3 * (size_t)node->child[0] : tree->node[node->child[0] - n].centroid;
    const float *c1 = node->child[1] < n ? ctx->pos + 3 * (size_t)node->child[1] : tree->node[node->child[1] - n].centroid;
    double axis2 = 0, along = 0;
    for (int c = 0; c < 3; ++c) {
        double a = (double)c1[c] - c0[c];
        axis2 += a * a;
        along += a * ((double)k_centre[c] - node->centroid[c]);
    }
    if (!(axis2 > 0))
        return 0.0f;
    double tau = along / axis2;
    return (float)(tau < -1 ? -1 : tau > 1 ? 1 : tau);
}

static int entry_better(const cut_entry *a, const cut_entry *b)
{
    float ka = a->k[0] + a->k[1] + a->k[2], kb = b->k[0] + b->k[1] + b->k[2];
    return ka > kb || (ka == kb && a->id < b->id);
}

static int cmp_entry(const void *pa, const void *pb)
{
    const cut_entry *a = pa, *b = pb;
    return entry_better(a, b) ? -1 : entry_better(b, a) ? 1 : 0;
}

typedef struct cut_scratch {
    cut_entry *entry; /* N + 1 */
    float *points;    /* 3 * mc_samples */
} cut_scratch;

/* Vertex o's cut into its result row. Returns the entries classified. */
static uint64_t cut_vertex(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, cut_scratch *sc,
                           sam_build_result *r, uint64_t *form_factors)
{
    const uint32_t n = ctx->mesh->topo_count, budget = ctx->settings.samples_per_vertex, m = ctx->settings.mc_samples;
    const float flat_ratio = expf(sqrtf(8.0f * ctx->settings.cut_tolerance));
    cut_entry *e = sc->entry;
    uint32_t count = 0;
    uint64_t classified = 1;
    if (classify(ctx, tree, o, tree->node_count ? n : 0, &e[0]))
        count = 1;
    /* Lightcuts' loop: split the entry with the largest bound until the
     * bounds are small against the total or a split would hold more than
     * N entries. An entry only partly on the back side stays a candidate
     * too: its K will count just its back-side members. */
    for (;;) {
        uint32_t best = UINT32_MAX;
        double total = 0;
        for (uint32_t c = 0; c < count; ++c) {
            total += e[c].estimate;
            if (e[c].id >= n && (best == UINT32_MAX || e[c].priority > e[best].priority))
                best = c;
        }
        if (best == UINT32_MAX || !(e[best].priority > ctx->settings.cut_tolerance * total))
            break;
        const sam_build_node *node = &tree->node[e[best].id - n];
        cut_entry kids[2];
        int live[2];
        for (int c = 0; c < 2; ++c)
            live[c] = classify(ctx, tree, o, node->child[c], &kids[c]);
        classified += 2;
        if (count - 1 + (uint32_t)live[0] + (uint32_t)live[1] > budget)
            break;
        if (live[0]) {
            e[best] = kids[0];
            if (live[1])
                e[count++] = kids[1];
        } else if (live[1]) {
            e[best] = kids[1];
        } else {
            e[best] = e[--count];
        }
    }
    const uint32_t kept = count;
    if (kept)
        sam_build_receiver_points(ctx, o, m, ctx->settings.seed, sc->points);
    for (uint32_t c = 0; c < kept; ++c) {
        if (e[c].id < n)
            sam_build_form_factor_from(ctx, o, sc->points, e[c].id, m, ctx->settings.seed, e[c].k, &e[c].k_error);
        else
        {
            float k_centre[3];
            node_form_factor(ctx, tree, o, sc->points, e[c].id - n, flat_ratio, e[c].k, &e[c].k_error, k_centre);
            e[c].tau = node_tau(ctx, tree, e[c].id - n, k_centre);
        }
    }
    *form_factors += kept;
    qsort(e, kept, sizeof *e, cmp_entry);
    const float *po = ctx->pos + 3 * (size_t)o;
    for (uint32_t c = 0, slot = 0; c < kept; ++c) {
        if (!(e[c].k[0] + e[c].k[1] + e[c].k[2] > 0))
            break; /* no light through it: leave the slot empty */
        const uint32_t id = e[c].id;
        const float *q = id < n ? ctx->pos + 3 * (size_t)id : tree->node[id - n].centroid;
        const float area = id < n ? ctx->fan_area[id] : tree->node[id - n].area;
        size_t at = (size_t)o * budget + slot++;
        r->sample[at] = id;
        r->k_error[at] = e[c].k_error;
        r->tau[at] = e[c].tau;
        memcpy(r->k + 3 * at, e[c].k, sizeof e[c].k);
        sam_build_kprime(ctx, e[c].k, area, sam_build_distance(po, q), r->kprime + 3 * at);
    }
    return classified;
}

/* Copies the tree's shape into the result. */
static sam_status keep_tree(const sam_build_tree *tree, sam_build_result *r, sam_error *err)
{
    r->node_count = tree->node_count;
    r->level_count = tree->level_count;
    r->node_children = malloc(((size_t)tree->node_count * 2 + 1) * sizeof *r->node_children);
    r->level_offsets = malloc(((size_t)tree->level_count + 1) * sizeof *r->level_offsets);
    r->tau = calloc((size_t)r->topo_count * r->samples_per_vertex, sizeof *r->tau);
    if (!r->node_children || !r->level_offsets || !r->tau)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory for the tree's %u nodes", tree->node_count);
    for (uint32_t j = 0; j < tree->node_count; ++j) {
        r->node_children[2 * (size_t)j] = tree->node[j].child[0];
        r->node_children[2 * (size_t)j + 1] = tree->node[j].child[1];
    }
    memcpy(r->level_offsets, tree->level_offsets, ((size_t)tree->level_count + 1) * sizeof *r->level_offsets);
    return SAM_OK;
}

sam_status sam_build_run_cut(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                             sam_build_result *result, sam_error *err)
{
    double start = sam_seconds();
    sam_build_tree tree;
    sam_status st = sam_build_result_alloc(ctx, ctx->settings.samples_per_vertex, result, err);
    if (st != SAM_OK)
        return st;
    if ((st = sam_build_tree_create(ctx, &tree, err)) != SAM_OK || (st = keep_tree(&tree, result, err)) != SAM_OK) {
        sam_build_tree_destroy(&tree);
        sam_build_result_destroy(result);
        return st;
    }
    const uint32_t n = ctx->mesh->topo_count;
    sam_build_progress prog = {progress, user, 0, n, 0, 0};
    uint64_t seen = 0, form_factors = 0;
    int oom = 0;
#pragma omp parallel num_threads(sam_build_thread_count(ctx)) reduction(+ : seen, form_factors)
    {
        cut_scratch sc = {malloc(((size_t)ctx->settings.samples_per_vertex + 1) * sizeof(cut_entry)),
                          malloc((size_t)ctx->settings.mc_samples * 3 * sizeof(float))};
        if (!sc.entry || !sc.points) {
#pragma omp atomic write
            oom = 1;
#pragma omp atomic write
            prog.cancelled = 1;
        }
#pragma omp for schedule(dynamic, 64)
        for (uint32_t o = 0; o < n; ++o)
            if (!sam_build_progress_step(&prog))
                seen += cut_vertex(ctx, &tree, o, &sc, result, &form_factors);
        free(sc.entry);
        free(sc.points);
    }
    sam_build_tree_destroy(&tree);
    if (oom) {
        sam_build_result_destroy(result);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory for per-thread buffers");
    }
    result->candidates_seen = seen;
    result->form_factors = form_factors;
    return sam_build_progress_finish(&prog, result, start, err);
}
