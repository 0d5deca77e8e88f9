/* The cut map: per vertex, a cut through the cluster tree (lightcuts'
 * refinement); each cut node's K comes from sam_build_cut_k.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "sam_build_internal.h"

/* A node or vertex of a vertex's cut. `id` < topo_count is a topo vertex,
 * else topo_count + node. */
typedef struct cut_entry {
    uint32_t id;
    int back;       /* 1: every member is on the back side; 0: some are not (K counts those that are) */
    float priority; /* back: area x the fall of mean R_d across it; mixed: area x R_d at its nearest point */
    float estimate; /* back: area x mean R_d at its centroid; mixed: 0 */
    float k[3];
    float tau;      /* sam_build_cut_hold's; 0 for a vertex */
} cut_entry;

/* Whether topo vertex v may stand in receiver o's row as a vertex sample:
 * itself behind o (eq. 13-14) and within the search radius. Its distance
 * (mm) into *d when it may. The runtime drops a vertex sample whose own
 * test fails at a pose, so a vertex only part of whose fan is behind (a
 * rim's) counts only inside the nodes around it. */
static int reaches(const sam_build_context *ctx, uint32_t o, uint32_t v, float *d)
{
    if (v == o || !sam_build_behind(ctx, o, v))
        return 0;
    *d = sam_build_distance(ctx->pos + 3 * (size_t)o, ctx->pos + 3 * (size_t)v);
    return *d < ctx->search_radius;
}

/* What classify found. */
typedef enum cut_kind {
    CUT_OUT,   /* no member can contribute: all in front, facing o's way, or beyond the search radius */
    CUT_ENTRY, /* a candidate for the cut, in *e */
    CUT_RIMS   /* light through its members' rims alone (keep_rims) */
} cut_kind;

/* Classifies `id` for receiver o. For CUT_RIMS, the rims (topo vertices)
 * go to rim[0, *rim_count), at most SAM_BUILD_EXACT_MEMBERS of them; both
 * may be NULL where `id` cannot be one (a vertex that reaches o). */
static cut_kind classify(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t id,
                         cut_entry *e, uint32_t *rim, uint32_t *rim_count)
{
    const uint32_t n = ctx->mesh->topo_count;
    memset(e, 0, sizeof *e);
    e->id = id;
    float d;
    if (id < n) {
        if (!reaches(ctx, o, id, &d)) {
            if (!sam_build_fan_reaches(ctx, o, id, &d))
                return CUT_OUT;
            rim[0] = id;
            *rim_count = 1;
            return CUT_RIMS;
        }
        e->back = 1;
        e->estimate = ctx->fan_area[id] * sam_build_rd_mean(ctx, d);
        return CUT_ENTRY;
    }
    const sam_build_node *node = &tree->node[id - n];
    sam_bounds_range b;
    sam_build_side side = sam_build_node_side(ctx, tree, id - n, o, &b);
    if (side == SAM_BUILD_SIDE_PARTLY && node->count <= SAM_BUILD_EXACT_MEMBERS) {
        /* Boxes cannot tell the receiver's own front from its back side:
         * around it every node is "partly" behind. Such a node that holds
         * no back-side member carried no K but took a slot, and one of a
         * few back-side members lent them the L_d of all its members,
         * front ones too: on a skin scan most of the cut was such nodes,
         * and vertices with no back side in reach got light. A small
         * node's members are asked one by one. One whose light comes
         * through rims alone is no entry either: as one, it took the
         * cut's slots near folds and creases and lent its slivers the L_d
         * of members facing the other way (the statue in marble lost 2.1
         * dB, docs/comparison.md); its rims go where rims go. */
        uint32_t behind = 0, fans = 0;
        for (uint32_t m = 0; m < node->count; ++m) {
            const uint32_t v = tree->perm[node->first + m];
            if (reaches(ctx, o, v, &d)) {
                behind++;
                fans++;
            } else if (sam_build_fan_reaches(ctx, o, v, &d)) {
                if (behind == 0 && rim)
                    rim[fans] = v; /* with no vertex behind so far, fans counts the rims */
                fans++;
            }
        }
        if (behind == 0) {
            if (rim_count)
                *rim_count = fans;
            return fans ? CUT_RIMS : CUT_OUT;
        }
        side = fans == node->count ? SAM_BUILD_SIDE_BACK : side;
    }
    if (side == SAM_BUILD_SIDE_OUT)
        return CUT_OUT;
    const float near = sam_build_rd_mean(ctx, sqrtf(b.near2));
    e->back = side == SAM_BUILD_SIDE_BACK;
    if (e->back) {
        const float *c = node->centroid;
        e->priority = node->area * fmaxf(near - sam_build_rd_mean(ctx, sqrtf(b.far2)), 0.0f);
        e->estimate = node->area * sam_build_rd_mean(ctx, sam_build_distance(ctx->pos + 3 * (size_t)o, c));
    } else {
        e->priority = node->area * near;
    }
    return CUT_ENTRY;
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

/* Subnodes opened or members given full Monte Carlo to sum a cut's K, per
 * sample: at 16, the K of the tests' shapes is within 0.7% of their
 * members' and the slabs' within 0.1% of the closed form; 8 fails the
 * marble slab, 1000 (no limit, in effect) costs 4x the time. */
#define SAM_BUILD_CUT_OPENINGS 16u

/* list_back_side: the vertices it tests before it gives up, and the part
 * of the transport the budget's best vertices may leave out. With 0.01 (the
 * cut tolerance) the Chinese dragon in skin scored 51.6 dB, with 0.05, 0.1,
 * 0.2 and 1 (every row the search finishes) 53.2, 53.4, 53.7 and 53.8 dB
 * (the flat map of N = 64: 53.9); the area-lit marble slab 36.4 (the
 * lightcut alone), 36.6, 37.7 and 35.8 dB at 0.01, 0.05, 0.1 and 0.2. */
#define LIST_TESTS 1024u
#define LIST_TOLERANCE 0.1

/* Whether a row is listed is judged on its best LIST_JUDGED vertices
 * (fewer with a smaller budget), however many slots it has: a row whose
 * light 32 vertices cannot hold is one nodes hold better, and a larger
 * budget should refine a row, not change how it is held. Judged on all
 * its slots, a budget of 64 listed more of the environment-lit marble
 * slab's rows, folding a tenth of their light into vertices that do not
 * stand for it, and scored under 32 (docs/comparison.md). */
#define LIST_JUDGED SAM_BUILD_CUT_DEFAULT_BUDGET

typedef struct listed {
    float estimate; /* F' x mean R_d */
    uint32_t id;
} listed;

/* A rim of the receiver (keep_rims) and its K, which weigh_rims fills. */
typedef struct rim {
    uint32_t v;
    float k[3];
} rim;

typedef struct rim_set {
    rim *rim;       /* LIST_TESTS */
    uint32_t count;
    double rest[3]; /* the K of rims beyond LIST_TESTS */
} rim_set;

typedef struct cut_scratch {
    cut_entry *entry;                 /* N + 1 */
    float *points;                    /* SAM_BUILD_POINT_FLOATS * mc_samples */
    uint32_t *ids;                    /* N */
    float *k, *centre, *spread;       /* 3N, 3N, N */
    uint32_t *stack;                  /* the tree's levels + 2 */
    listed *found;                    /* LIST_TESTS */
    rim_set rims;
    uint32_t *rim_ids;                /* 2 * SAM_BUILD_EXACT_MEMBERS */
    sam_build_cut_k_scratch *k_scratch;
} cut_scratch;

static void cut_scratch_free(cut_scratch *sc)
{
    free(sc->entry);
    free(sc->points);
    free(sc->ids);
    free(sc->k);
    free(sc->centre);
    free(sc->spread);
    free(sc->stack);
    free(sc->found);
    free(sc->rims.rim);
    free(sc->rim_ids);
    sam_build_cut_k_scratch_destroy(sc->k_scratch);
}

/* A vertex's cut entries: the budget, never fewer than the samples stored. */
static uint32_t cut_budget(const sam_build_context *ctx)
{
    const uint32_t n = ctx->settings.samples_per_vertex, b = ctx->settings.cut_budget;
    return b > n ? b : n;
}

/* Returns 0 when out of memory (what was allocated is freed). */
static int cut_scratch_alloc(const sam_build_context *ctx, const sam_build_tree *tree, cut_scratch *sc)
{
    const size_t n = cut_budget(ctx);
    sc->entry = malloc((n + 1) * sizeof *sc->entry);
    sc->points = malloc((size_t)ctx->settings.mc_samples * SAM_BUILD_POINT_FLOATS * sizeof *sc->points);
    sc->ids = malloc(n * sizeof *sc->ids);
    sc->k = malloc(3 * n * sizeof *sc->k);
    sc->centre = malloc(3 * n * sizeof *sc->centre);
    sc->spread = malloc(n * sizeof *sc->spread);
    sc->stack = malloc(((size_t)tree->level_count + 2) * sizeof *sc->stack);
    sc->found = malloc(LIST_TESTS * sizeof *sc->found);
    sc->rims.rim = malloc(LIST_TESTS * sizeof *sc->rims.rim);
    sc->rim_ids = malloc(2 * SAM_BUILD_EXACT_MEMBERS * sizeof *sc->rim_ids);
    sc->k_scratch = sam_build_cut_k_scratch_create((uint32_t)n, (uint32_t)n * SAM_BUILD_CUT_OPENINGS);
    if (sc->entry && sc->points && sc->ids && sc->k && sc->centre && sc->spread && sc->stack && sc->found &&
        sc->rims.rim && sc->rim_ids && sc->k_scratch)
        return 1;
    cut_scratch_free(sc);
    return 0;
}

static int cmp_listed(const void *pa, const void *pb)
{
    const listed *a = pa, *b = pb;
    if (a->estimate != b->estimate)
        return a->estimate > b->estimate ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

/* K of rim v of receiver o from o's shared `points`, with as many pairs
 * as a sample's (which part of the fan is behind, only the pairs tell;
 * with 8, 16 of the 250 rows of a marble ear missed the brute force by
 * more than 5%, with 16, 13 of a ketchup knot's 144). Since rims wait for
 * their rows (keep_rims), their pairs are about 2% of the 10k knot's build. */
static void rim_k(const sam_build_context *ctx, uint32_t o, const float *points, uint32_t v, float k[3])
{
    float k_error;
    sam_build_form_factor_from(ctx, o, points, v, ctx->settings.mc_samples, ctx->settings.seed, 1, k, &k_error);
}

/* Keeps rims v[0, count) of receiver o in `rims`. A rim is a vertex part
 * of whose fan is behind o, but not the vertex itself, which therefore
 * cannot be a sample (reaches says why). Its K waits for weigh_rims, as
 * the listing's rims do (keep_listed_rims); past LIST_TESTS rims, K goes
 * to the rest at once. fold_rims hands a rim's K to the row's sample
 * nearest it. */
static void keep_rims(const sam_build_context *ctx, uint32_t o, const float *points, const uint32_t *v,
                      uint32_t count, rim_set *rims)
{
    for (uint32_t r = 0; r < count; ++r) {
        if (rims->count < LIST_TESTS) {
            rims->rim[rims->count++].v = v[r];
            continue;
        }
        float k[3];
        rim_k(ctx, o, points, v[r], k);
        for (int ch = 0; ch < 3; ++ch)
            rims->rest[ch] += k[ch];
    }
}

/* Of the listing's candidates in `rims` (vertices it met that do not
 * reach receiver o), keeps those that are rims, in their order. Asked only
 * once the listing holds: it gives up on most rows of a mesh fine against
 * the profile, and its candidates' fan tests went with it. */
static void keep_listed_rims(const sam_build_context *ctx, uint32_t o, rim_set *rims)
{
    uint32_t kept = 0;
    for (uint32_t r = 0; r < rims->count; ++r) {
        const uint32_t v = rims->rim[r].v;
        float d;
        if (!sam_build_behind(ctx, o, v) && sam_build_fan_reaches(ctx, o, v, &d))
            rims->rim[kept++].v = v;
    }
    rims->count = kept;
}

/* Each kept rim's K (rim_k). */
static void weigh_rims(const sam_build_context *ctx, uint32_t o, const float *points, rim_set *rims)
{
    for (uint32_t r = 0; r < rims->count; ++r)
        rim_k(ctx, o, points, rims->rim[r].v, rims->rim[r].k);
}

/* Adds the K of receiver o's rims (weigh_rims, from o's `points`) to the
 * entry of e[0, count) whose light comes from nearest it (`centre`, 3 per
 * entry, mm), and the rest by the entries' K. Near, not over the whole
 * row: a rim's light is its neighbours', and spread over the row, a tube
 * lit from one side read it on the other. Entries without K get none. */
static void fold_rims(const sam_build_context *ctx, uint32_t o, const float *points, rim_set *rims,
                      const float *centre, cut_entry *e, uint32_t count)
{
    double total[3] = {0, 0, 0};
    for (uint32_t c = 0; c < count; ++c)
        for (int ch = 0; ch < 3; ++ch)
            total[ch] += e[c].k[ch];
    if (!(total[0] + total[1] + total[2] > 0))
        return;
    weigh_rims(ctx, o, points, rims);
    for (uint32_t r = 0; r < rims->count; ++r) {
        const float *p = ctx->pos + 3 * (size_t)rims->rim[r].v;
        uint32_t best = UINT32_MAX;
        float nearest = INFINITY;
        for (uint32_t c = 0; c < count; ++c) {
            const float d = sam_build_distance(p, centre + 3 * (size_t)c);
            if (e[c].k[0] + e[c].k[1] + e[c].k[2] > 0 && d < nearest) {
                nearest = d;
                best = c;
            }
        }
        for (int ch = 0; ch < 3; ++ch)
            e[best].k[ch] += rims->rim[r].k[ch];
    }
    for (uint32_t c = 0; c < count; ++c)
        for (int ch = 0; ch < 3; ++ch)
            if (total[ch] > 0)
                e[c].k[ch] += (float)(rims->rest[ch] * e[c].k[ch] / total[ch]);
}

/* The flat map's row as the cut: when the min(`budget`, LIST_JUDGED)
 * vertices behind receiver o with the most transport (point estimate) leave
 * out at most LIST_TOLERANCE of the transport of all that reach it, puts
 * the `budget` best into e[] as the cut, sets *scale to the factor that
 * makes their K carry the whole (all that reach o over those kept, by the
 * estimate) and returns their count; otherwise returns UINT32_MAX. The
 * rims it meets go to `rims` (keep_listed_rims). Where
 * the profile is short against the fans (skin on a mesh of 10k vertices),
 * a few vertices carry nearly all the light and each of them is exact,
 * while a lightcut spent its
 * budget on nodes partly behind the receiver (a scan's noisy normals: 16 of
 * 26 entries on the Chinese dragon), whose L_d mixes in members that are
 * not, and scored 2.8 dB under the flat map of N = 32 (docs/builder.md has
 * the tolerance's measures). The search gives up after LIST_TESTS
 * vertices, so on a mesh fine against the profile it costs about four
 * nodes' classification member by member. `stack` holds the tree's levels
 * + 2 entries, `found` LIST_TESTS. */
static uint32_t list_back_side(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t budget,
                               uint32_t *stack, listed *found, cut_entry *e, float *scale, rim_set *rims,
                               uint64_t *tested)
{
    const uint32_t n = ctx->mesh->topo_count;
    uint32_t top = 0, count = 0, tests = 0;
    double total = 0;
    if (tree->node_count == 0)
        return UINT32_MAX;
    stack[top++] = n;
    while (top > 0) {
        const uint32_t id = stack[--top];
        if (id < n) {
            float d;
            if (tests++ == LIST_TESTS) {
                *tested += tests;
                return UINT32_MAX;
            }
            if (reaches(ctx, o, id, &d)) {
                found[count] = (listed){ctx->fan_area[id] * sam_build_rd_mean(ctx, d), id};
                total += found[count++].estimate;
            } else {
                rims->rim[rims->count++].v = id; /* at most LIST_TESTS, as the tests */
            }
            continue;
        }
        const sam_build_node *node = &tree->node[id - n];
        sam_bounds_range b;
        if (sam_build_node_side(ctx, tree, id - n, o, &b) == SAM_BUILD_SIDE_OUT)
            continue;
        stack[top++] = node->child[1];
        stack[top++] = node->child[0];
    }
    *tested += tests;
    qsort(found, count, sizeof *found, cmp_listed);
    const uint32_t judged = budget < LIST_JUDGED ? budget : LIST_JUDGED;
    double left_out = 0, judged_out = 0;
    for (uint32_t c = count; c-- > judged;) {
        judged_out += found[c].estimate;
        if (c >= budget)
            left_out += found[c].estimate;
    }
    if (judged_out > LIST_TOLERANCE * total)
        return UINT32_MAX;
    const uint32_t kept = count < budget ? count : budget;
    *scale = left_out > 0 ? (float)(total / (total - left_out)) : 1.0f;
    for (uint32_t c = 0; c < kept; ++c)
        classify(ctx, tree, o, found[c].id, &e[c], NULL, NULL);
    keep_listed_rims(ctx, o, rims);
    return kept;
}

/* Lightcuts' loop: split the entry with the largest bound until the
 * bounds are small against the total or a split would hold more than
 * `budget` entries. An entry only partly on the back side stays a candidate
 * too: its K will count just its back-side members. What is split off
 * with light through rims alone goes to `rims` (keep_rims; `rim_ids`
 * holds 2 SAM_BUILD_EXACT_MEMBERS). Returns the cut's entries, in e[];
 * adds the entries classified to *classified. */
static uint32_t lightcut(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t budget,
                         const float *points, cut_entry *e, rim_set *rims, uint32_t *rim_ids, uint64_t *classified)
{
    const uint32_t n = ctx->mesh->topo_count;
    const float tol = ctx->settings.cut_tolerance;
    uint32_t count = 0;
    *classified += 1;
    const uint32_t root = tree->node_count ? n : 0;
    uint32_t rim_count[2] = {0, 0};
    switch (classify(ctx, tree, o, root, &e[0], rim_ids, &rim_count[0])) {
    case CUT_ENTRY: count = 1; break;
    case CUT_RIMS: keep_rims(ctx, o, points, rim_ids, rim_count[0], rims); break;
    case CUT_OUT: break;
    }
    for (;;) {
        uint32_t best = UINT32_MAX;
        double total = 0;
        for (uint32_t c = 0; c < count; ++c) {
            total += e[c].estimate;
            if (e[c].id >= n && (best == UINT32_MAX || e[c].priority > e[best].priority))
                best = c;
        }
        if (best == UINT32_MAX || !(e[best].priority > tol * total))
            break;
        const sam_build_node *node = &tree->node[e[best].id - n];
        cut_entry kids[2];
        cut_kind kind[2];
        for (int c = 0; c < 2; ++c)
            kind[c] = classify(ctx, tree, o, node->child[c], &kids[c], rim_ids + c * SAM_BUILD_EXACT_MEMBERS,
                               &rim_count[c]);
        *classified += 2;
        const int live[2] = {kind[0] == CUT_ENTRY, kind[1] == CUT_ENTRY};
        if (count - 1 + (uint32_t)live[0] + (uint32_t)live[1] > budget)
            break;
        for (int c = 0; c < 2; ++c)
            if (kind[c] == CUT_RIMS)
                keep_rims(ctx, o, points, rim_ids + c * SAM_BUILD_EXACT_MEMBERS, rim_count[c], rims);
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
    return count;
}

/* What a budget above N needs to merge a cut's siblings
 * (samfile_merge_siblings) and fold the rest (samfile_fold_row), per
 * sample index (topo vertices, then nodes): the node it is a child of,
 * its area, and its normals summed by area (3 floats; a node's are its
 * members', as samfile_sample_points means them at load, though from the
 * topo normals where the load reads the .sam's, which differ where a mesh
 * file brings normals of its own). */
typedef struct fit_links {
    uint32_t *parent;
    float *area;
    float *normal;
} fit_links;

static void fit_links_free(fit_links *f)
{
    free(f->parent);
    free(f->area);
    free(f->normal);
}

static sam_status fit_links_create(const sam_build_context *ctx, const sam_build_tree *tree, fit_links *f,
                                   sam_error *err)
{
    const size_t n = ctx->mesh->topo_count, all = n + tree->node_count;
    f->parent = malloc(all * sizeof *f->parent);
    f->area = malloc(all * sizeof *f->area);
    f->normal = malloc(3 * all * sizeof *f->normal);
    if (!f->parent || !f->area || !f->normal) {
        fit_links_free(f);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory for the tree's %zu parent links", all);
    }
    for (size_t i = 0; i < all; ++i) {
        f->parent[i] = SAMFILE_NO_SAMPLE;
        f->area[i] = sam_build_sample_area(ctx, tree, (uint32_t)i);
    }
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c)
            f->normal[3 * i + c] = ctx->mesh->topo_normals[3 * i + c] * f->area[i];
    /* Children are numbered after their parents (level by level). */
    for (uint32_t j = tree->node_count; j-- > 0;) {
        const uint32_t *child = tree->node[j].child;
        for (int c = 0; c < 3; ++c)
            f->normal[3 * (n + j) + c] = f->normal[3 * (size_t)child[0] + c] + f->normal[3 * (size_t)child[1] + c];
    }
    for (uint32_t j = 0; j < tree->node_count; ++j)
        f->parent[tree->node[j].child[0]] = f->parent[tree->node[j].child[1]] = (uint32_t)n + j;
    return SAM_OK;
}

/* Receiver o of a cut being fitted, for unit_k. */
typedef struct fit_receiver {
    const sam_build_context *ctx;
    const sam_build_tree *tree;
    uint32_t o;
} fit_receiver;

/* F'_b R_d(|v_b - v|) of sample index id (topo vertex or n + node) for
 * the receiver: what one unit of K' gives at rest (eq. 15). */
static void unit_k(void *user, uint32_t id, float out[3])
{
    const fit_receiver *r = user;
    sam_build_unit_k(r->ctx, sam_build_sample_area(r->ctx, r->tree, id),
                     sam_build_distance(r->ctx->pos + 3 * (size_t)r->o, sam_build_sample_point(r->ctx, r->tree, id)),
                     out);
}

/* Vertex o's cut into its result row; `links` NULL when the budget is N.
 * Returns the entries classified. */
static uint64_t cut_vertex(const sam_build_context *ctx, const sam_build_tree *tree, const fit_links *links,
                           uint32_t o, cut_scratch *sc, sam_build_result *r, uint64_t *form_factors)
{
    const uint32_t n = ctx->mesh->topo_count, budget = cut_budget(ctx), stored = ctx->settings.samples_per_vertex,
                   m = ctx->settings.mc_samples;
    cut_entry *e = sc->entry;
    uint64_t classified = 0;
    float scale = 1.0f;
    rim_set *rims = &sc->rims;
    *rims = (rim_set){rims->rim, 0, {0, 0, 0}};
    sam_build_receiver_points(ctx, o, m, ctx->settings.seed, sc->points);
    uint32_t count =
        list_back_side(ctx, tree, o, budget, sc->stack, sc->found, e, &scale, rims, &classified);
    if (count == UINT32_MAX) {
        /* The listing's rims lie inside the nodes the cut will hold. */
        *rims = (rim_set){rims->rim, 0, {0, 0, 0}};
        count = lightcut(ctx, tree, o, budget, sc->points, e, rims, sc->rim_ids, &classified);
    }
    const uint32_t kept = count;
    if (kept) {
        for (uint32_t c = 0; c < kept; ++c)
            sc->ids[c] = e[c].id;
        sam_build_cut_k(ctx, tree, o, sc->points, sc->ids, kept, budget * SAM_BUILD_CUT_OPENINGS, sc->k_scratch, sc->k,
                        sc->centre, sc->spread);
    }
    for (uint32_t c = 0; c < kept; ++c)
        for (int ch = 0; ch < 3; ++ch)
            e[c].k[ch] = scale * sc->k[3 * (size_t)c + ch];
    fold_rims(ctx, o, sc->points, rims, sc->centre, e, kept);
    for (uint32_t c = 0; c < kept; ++c) {
        for (int ch = 0; ch < 3; ++ch)
            r->k_total[3 * (size_t)o + ch] += e[c].k[ch];
        if (e[c].id >= n)
            e[c].id = sam_build_cut_hold(ctx, tree, o, e[c].id, e[c].k, sc->centre + 3 * (size_t)c, sc->spread[c],
                                         e[c].back, &e[c].tau);
    }
    *form_factors += kept;
    qsort(e, kept, sizeof *e, cmp_entry);
    /* A budget above N merges the cut's siblings into their parents, whose
     * tau reads the pair's light as it was, then folds each entry past the
     * N best into the kept one nearest it in place and facing, as
     * samfile_fit_samples does at load: a finer cut's N read their light
     * where it comes from, where a cut of N entries reads it over coarser
     * nodes. */
    uint32_t id[SAMFILE_MAX_SAMPLES_PER_VERTEX];
    float at[SAMFILE_FOLD_POINT_FLOATS * SAMFILE_MAX_SAMPLES_PER_VERTEX], k[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX],
        tau[SAMFILE_MAX_SAMPLES_PER_VERTEX], folded[3 * SAMFILE_MAX_SAMPLES_PER_VERTEX];
    uint32_t left = kept;
    for (uint32_t c = 0; c < kept; ++c) {
        id[c] = e[c].id;
        tau[c] = e[c].tau;
        memcpy(k + 3 * c, e[c].k, 3 * sizeof *k);
    }
    fit_receiver receiver = {ctx, tree, o};
    if (links && left > stored)
        left = samfile_merge_siblings(links->parent, r->node_children, n, links->area, 1, unit_k, &receiver, id, k, tau,
                                      left, stored);
    const float *po = ctx->pos + 3 * (size_t)o;
    static const float no_normal[3] = {0, 0, 0}; /* a budget of N (no links) folds nothing */
    for (uint32_t c = 0; c < left; ++c)
        samfile_fold_point(sam_build_sample_point(ctx, tree, id[c]),
                           links ? links->normal + 3 * (size_t)id[c] : no_normal, po,
                           at + SAMFILE_FOLD_POINT_FLOATS * c);
    const uint32_t out = left < stored ? left : stored;
    samfile_fold_row(at, SAMFILE_FOLD_POINT_FLOATS, k, left, out, folded);
    for (uint32_t c = 0, slot = 0; c < out; ++c) {
        if (!(k[3 * c] + k[3 * c + 1] + k[3 * c + 2] > 0))
            continue; /* no light through it: no slot (such entries come last) */
        const float area = sam_build_sample_area(ctx, tree, id[c]);
        size_t to = (size_t)o * stored + slot++;
        r->sample[to] = id[c];
        r->tau[to] = tau[c];
        sam_build_kprime(ctx, folded + 3 * c, area, sam_build_distance(po, at + SAMFILE_FOLD_POINT_FLOATS * c),
                         r->kprime + 3 * to);
    }
    return classified;
}

/* Copies the tree's shape into the result. */
static sam_status keep_tree(const sam_build_tree *tree, uint32_t vertex_count, sam_build_result *r, sam_error *err)
{
    r->node_count = tree->node_count;
    r->level_count = tree->level_count;
    r->node_children = malloc(((size_t)tree->node_count * 2 + 1) * sizeof *r->node_children);
    r->level_offsets = malloc(((size_t)tree->level_count + 1) * sizeof *r->level_offsets);
    r->tau = calloc((size_t)vertex_count * r->samples_per_vertex, sizeof *r->tau); /* as sam_build_result_alloc's */
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
    if (cut_budget(ctx) > SAMFILE_MAX_SAMPLES_PER_VERTEX) /* cut_vertex's rows are that long */
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "build: a cut of %u entries; at most %u", cut_budget(ctx),
                        SAMFILE_MAX_SAMPLES_PER_VERTEX);
    sam_build_tree tree;
    sam_status st = sam_build_result_alloc(ctx, ctx->settings.samples_per_vertex, 1, result, err);
    if (st != SAM_OK)
        return st;
    if ((st = sam_build_tree_create(ctx, &tree, err)) != SAM_OK || (st = keep_tree(&tree, ctx->mesh->vertex_count, result, err)) != SAM_OK) {
        sam_build_tree_destroy(&tree);
        sam_build_result_destroy(result);
        return st;
    }
    const uint32_t n = ctx->mesh->topo_count;
    fit_links links = {NULL, NULL, NULL};
    const int fitting = cut_budget(ctx) > ctx->settings.samples_per_vertex;
    if (fitting && (st = fit_links_create(ctx, &tree, &links, err)) != SAM_OK) {
        sam_build_tree_destroy(&tree);
        sam_build_result_destroy(result);
        return st;
    }
    sam_build_progress prog = {progress, user, 0, n, 0, 0};
    uint64_t seen = 0, form_factors = 0;
    int oom = 0;
#pragma omp parallel num_threads(sam_build_thread_count(ctx)) reduction(+ : seen, form_factors)
    {
        cut_scratch sc;
        const int ok = cut_scratch_alloc(ctx, &tree, &sc);
        if (!ok) {
#pragma omp atomic write
            oom = 1;
#pragma omp atomic write
            prog.cancelled = 1;
        }
#pragma omp for schedule(dynamic, 64)
        for (uint32_t o = 0; o < n; ++o)
            if (!sam_build_progress_step(&prog))
                seen += cut_vertex(ctx, &tree, fitting ? &links : NULL, o, &sc, result, &form_factors);
        if (ok)
            cut_scratch_free(&sc);
    }
    sam_build_tree_destroy(&tree);
    fit_links_free(&links);
    if (oom) {
        sam_build_result_destroy(result);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory for per-thread buffers");
    }
    result->candidates_seen = seen;
    result->form_factors = form_factors;
    return sam_build_progress_finish(&prog, result, start, err);
}
