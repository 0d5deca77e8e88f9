/* Which node holds a cut entry's K for its receiver, and where along it
 * the runtime reads its light (sam_build_cut_hold). The runtime lends a
 * node sample its members' mean L_d, moved by tau along its split, while a
 * node's light comes mostly from its part nearest the receiver: the entry
 * goes down the tree towards where its light comes from (concentrate), a
 * node partly behind the receiver to a node wholly behind (focus), and a
 * node whose centroid cannot hold its K to a descendant that can
 * (carrier). */
#include <math.h>

#include "sam_build_internal.h"

/* Where along node j's split its light comes from: the K-weighted centre's
 * offset from the centroid, projected on the line between its children's
 * centroids, in units of that line (clamped to [-1, 1]). The runtime reads
 * the node's L_d moved by tau times the children's difference: exact for
 * L_d that changes linearly along the split. */
static float node_tau(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t j, const float k_centre[3])
{
    const sam_build_node *node = &tree->node[j];
    const float *c0 = sam_build_sample_point(ctx, tree, node->child[0]),
                *c1 = sam_build_sample_point(ctx, tree, node->child[1]);
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

/* The part of K (summed over channels) that K' = K / (F' R_d) of a sample
 * at distance d (mm) with area F' cannot hold: the channels where R_d
 * underflows, for which sam_build_kprime gives K' = 1. */
static float kprime_loss(const sam_build_context *ctx, const float k[3], float area, float d)
{
    float unit[3], lost = 0.0f;
    sam_build_unit_k(ctx, area, d, unit);
    for (int c = 0; c < 3; ++c)
        if (!(unit[c] > SAM_BUILD_KPRIME_MIN_DENOM))
            lost += k[c];
    return lost;
}

/* How many of node j's members have some of their fan behind receiver o. */
static uint32_t members_behind(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t j)
{
    const sam_build_node *node = &tree->node[j];
    uint32_t behind = 0;
    for (uint32_t m = 0; m < node->count; ++m) {
        const uint32_t v = tree->perm[node->first + m];
        behind += (uint32_t)(v != o && sam_build_fan_side(ctx, o, v) != SAM_BUILD_FAN_NONE);
    }
    return behind;
}

/* The node that carries node `id`'s K for receiver o: the node itself, or,
 * when its centroid lies so far out in R_d's tail that eq. 15 cannot hold a
 * thousandth of its K there, the largest of its descendants towards where
 * its light comes from (`centre`, mm) that can and lies wholly behind o,
 * carrying the whole K; the node itself when none can. A node straddling a
 * thin part, a few members touching the receiver and its centroid tens of
 * mm away, lost all its light at run time (K' = 1). A descendant, not a
 * member vertex: the runtime carries a node's K through a pose by eq. 15's
 * change and keeps it on the back side, but asks a vertex sample eq. 13-14
 * at the pose and carries it by its fans' quadrature, and a vertex carrying
 * a whole node's K broke the engine's rest pose (docs/builder.md). Wholly
 * behind: a descendant that was merely nearer lent the receiver the L_d of
 * the thin part's lit front: 2.3 dB lower on the Chinese dragon. */
static uint32_t carrier(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t id,
                        const float k[3], const float centre[3])
{
    const uint32_t n = ctx->mesh->topo_count;
    const float *po = ctx->pos + 3 * (size_t)o;
    const float negligible = 1e-3f * (k[0] + k[1] + k[2]);
    if (kprime_loss(ctx, k, tree->node[id - n].area, sam_build_distance(po, tree->node[id - n].centroid)) <= negligible)
        return id;
    for (uint32_t at = id;;) {
        const sam_build_node *node = &tree->node[at - n];
        uint32_t next = UINT32_MAX, next_behind = 0;
        float next_d = INFINITY;
        for (int c = 0; c < 2; ++c) {
            const uint32_t child = node->child[c];
            if (child < n)
                continue; /* a vertex: carried as one, it would leave the back side at a pose */
            const uint32_t behind = members_behind(ctx, tree, o, child - n);
            const float d = sam_build_distance(centre, tree->node[child - n].centroid);
            if (behind > 0 && d < next_d) {
                next_d = d;
                next = child;
                next_behind = behind;
            }
        }
        if (next == UINT32_MAX)
            return id;
        at = next;
        const sam_build_node *kid = &tree->node[at - n];
        if (next_behind == kid->count &&
            kprime_loss(ctx, k, kid->area, sam_build_distance(po, kid->centroid)) <= negligible)
            return at;
    }
}

/* Whether node j is at least `spread` (mm) in half-diagonal: large enough
 * to read the L_d of light spread that far. */
static int spans(const sam_build_tree *tree, uint32_t j, float spread)
{
    const sam_build_node *k = &tree->node[j];
    float diagonal2 = 0;
    for (int a = 0; a < 3; ++a)
        diagonal2 += (k->hi[a] - k->lo[a]) * (k->hi[a] - k->lo[a]);
    return 0.25f * diagonal2 >= spread * spread;
}

/* The child of node j (topo_count + node index) whose members hold tree
 * position `at`; UINT32_MAX when none does, as when the member there is a
 * vertex child of j itself. */
static uint32_t child_holding(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t j, uint32_t at)
{
    const uint32_t n = ctx->mesh->topo_count;
    for (int c = 0; c < 2; ++c) {
        const uint32_t kid = tree->node[j].child[c];
        if (kid >= n && at >= tree->node[kid - n].first && at - tree->node[kid - n].first < tree->node[kid - n].count)
            return kid;
    }
    return UINT32_MAX;
}

/* The smallest node on the way down from `id` to the member at tree
 * position `at` that spans `spread`: `id` itself when its child on the way
 * does not, or is a vertex. */
static uint32_t narrow(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t id, uint32_t at,
                       float spread)
{
    const uint32_t n = ctx->mesh->topo_count;
    for (;;) {
        const uint32_t next = child_holding(ctx, tree, id - n, at);
        if (next == UINT32_MAX || !spans(tree, next - n, spread))
            return id;
        id = next;
    }
}

/* The node that holds cut node `id`'s K for receiver o. The runtime lends
 * a node sample the L_d of all its members (their mean), so a node only
 * partly behind o mixes in members in front of it, on a thin part the
 * other face's light or shadow: on the knot in ketchup the cut's
 * translucency then erred by 2.3 times what it does with this. Such a
 * node, of at most SAM_BUILD_EXACT_MEMBERS members (concentrate narrows a
 * larger one first), hands its K to the node around its back-side member nearest
 * `centre` (where its light comes from): the first node on the way down
 * to that member that lies wholly behind o, narrowed on that way while it
 * is at least `spread` (the K's, mm) in half-diagonal, as concentrate
 * narrows; else the member's parent (whose tau, as every node's, leans
 * towards `centre`). Not narrowed, the first such node on a carved head
 * in marble held members from 0.1 to 56 mm from the receiver: its K came
 * from a crease's far side in shadow, its mean L_d from the lit rest, and
 * the forehead glowed (docs/comparison.md). Not the member
 * itself: the runtime takes a vertex sample for one pair of fans (the walk
 * adopts its neighbours as if their light were not counted, and the pose
 * re-asks eq. 13-14 and its fans' quadrature), and a vertex carrying a
 * node's K broke the engine's rest pose by 18% of T
 * (tests/test_gl_engine.c). */
static uint32_t focus(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t id,
                      const float centre[3], float spread)
{
    const uint32_t n = ctx->mesh->topo_count;
    const sam_build_node *node = &tree->node[id - n];
    if (node->count > SAM_BUILD_EXACT_MEMBERS)
        return id;
    uint32_t best = UINT32_MAX, at = 0, behind = 0;
    float nearest = INFINITY, d;
    for (uint32_t m = 0; m < node->count; ++m) {
        const uint32_t v = tree->perm[node->first + m];
        if (!sam_build_fan_reaches(ctx, o, v, &d))
            continue;
        behind++;
        const float to_centre = sam_build_distance(centre, ctx->pos + 3 * (size_t)v);
        if (to_centre < nearest) {
            nearest = to_centre;
            best = v;
            at = node->first + m;
        }
    }
    if (behind == node->count || best == UINT32_MAX)
        return id;
    for (;;) {
        const uint32_t next = child_holding(ctx, tree, id - n, at);
        if (next == UINT32_MAX)
            return id; /* the member's parent */
        if (members_behind(ctx, tree, o, next - n) == tree->node[next - n].count)
            return narrow(ctx, tree, next, at, spread);
        id = next;
    }
}

/* The node that holds cut node `id`'s K: the smallest node on the way down
 * that holds `centre` (where its light comes from, the K-weighted centre,
 * mm) in its box and is at least `spread` (the K-weighted spread about it,
 * mm) in half-diagonal; of two such children, the one whose centroid is
 * nearer. The runtime reads a node's L_d as its members' area mean, while
 * its light comes mostly from its edge nearest the receiver: where L_d
 * changes across it (a shadow's edge, the terminator around a tube), the
 * whole node's mean stands for light its K does not see. Read from the cut
 * node itself, the knot's translucency erred by 1.6 times, the area-lit
 * slab's by 1.8 times what it does here (docs/builder.md). No smaller than
 * the spread: such a node would read L_d at one point of an area the light
 * comes from. Descendants of a node wholly behind are wholly behind too,
 * and carried as every node is.
 *
 * A node partly behind (`mixed`) goes down only while it has more than
 * SAM_BUILD_EXACT_MEMBERS members, and only into children that reach o:
 * focus takes it from there, member by member. Such a node, split by normal near the
 * root, can span a whole figure while its K comes from a crease a
 * millimetre from the receiver: on a 100 mm figure in marble (the
 * statue), the lips' K read the mean L_d of surfaces facing alike over the
 * whole body, lit from behind, where the lips' own back side lies in
 * shadow: a glow around the mouth 40 times the vertex sum (docs/builder.md). */
static uint32_t concentrate(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t id,
                            const float centre[3], float spread, int mixed)
{
    const uint32_t n = ctx->mesh->topo_count;
    for (;;) {
        const sam_build_node *node = &tree->node[id - n];
        if (mixed && node->count <= SAM_BUILD_EXACT_MEMBERS)
            return id;
        uint32_t next = UINT32_MAX;
        float next_d = INFINITY;
        for (int c = 0; c < 2; ++c) {
            const uint32_t kid = node->child[c];
            if (kid < n)
                continue;
            const sam_build_node *k = &tree->node[kid - n];
            int inside = 1;
            for (int a = 0; a < 3; ++a)
                inside &= centre[a] >= k->lo[a] && centre[a] <= k->hi[a];
            const float d = sam_build_distance(centre, k->centroid);
            sam_bounds_range b;
            if (inside && spans(tree, kid - n, spread) && d < next_d &&
                (!mixed || sam_build_node_side(ctx, tree, kid - n, o, &b) != SAM_BUILD_SIDE_OUT)) {
                next = kid;
                next_d = d;
            }
        }
        if (next == UINT32_MAX)
            return id;
        id = next;
    }
}

uint32_t sam_build_cut_hold(const sam_build_context *ctx, const sam_build_tree *tree, uint32_t o, uint32_t id,
                            const float k[3], const float centre[3], float spread, int back, float *tau)
{
    const uint32_t n = ctx->mesh->topo_count;
    uint32_t held = concentrate(ctx, tree, o, id, centre, spread, !back);
    if (!back)
        held = focus(ctx, tree, o, held, centre, spread);
    held = carrier(ctx, tree, o, held, k, centre);
    *tau = node_tau(ctx, tree, held - n, centre);
    return held;
}
