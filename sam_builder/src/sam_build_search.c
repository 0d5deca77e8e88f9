#define _POSIX_C_SOURCE 200809L
/* The fast builder (Embree point queries with a shrinking radius, cheap
 * ranking, Monte Carlo on the best few) and the O(m^2) reference. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <embree3/rtcore.h>
#include <omp.h>

#include "sam_build_internal.h"

sam_status sam_build_result_alloc(const sam_build_context *ctx, uint32_t stride, int cut, sam_build_result *r,
                                  sam_error *err)
{
    memset(r, 0, sizeof *r);
    /* The per-sample arrays get a row per render vertex (nv >= n) from the
     * start: sam_build_move_to_samfile grows them to that in place, and a
     * realloc that had to move one would hold it twice at the build's peak. */
    size_t n = ctx->mesh->topo_count, nv = ctx->mesh->vertex_count, s = stride;
    r->topo_count = (uint32_t)n;
    r->samples_per_vertex = (uint32_t)s;
    r->sample = malloc(nv * s * sizeof *r->sample);
    if (cut) {
        r->k_total = calloc(n * 3, sizeof *r->k_total);
    } else {
        r->k = calloc(n * s * 3, sizeof *r->k);
        r->k_error = calloc(n * s, sizeof *r->k_error);
    }
    r->kprime = calloc(nv * s * 3, sizeof *r->kprime);
    r->fan_area = malloc(n * sizeof *r->fan_area);
    if (!r->sample || (cut ? !r->k_total : !r->k || !r->k_error) || !r->kprime || !r->fan_area) {
        sam_build_result_destroy(r);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory for the results of %zu vertices", n);
    }
    for (size_t i = 0; i < n * s; ++i)
        r->sample[i] = SAM_BUILD_NO_SAMPLE;
    memcpy(r->fan_area, ctx->fan_area, n * sizeof *r->fan_area);
    r->search_radius_mm = ctx->search_radius;
    return SAM_OK;
}

void sam_build_result_destroy(sam_build_result *r)
{
    if (!r)
        return;
    free(r->sample);
    free(r->k);
    free(r->k_error);
    free(r->k_total);
    free(r->kprime);
    free(r->fan_area);
    free(r->node_children);
    free(r->level_offsets);
    free(r->tau);
    memset(r, 0, sizeof *r);
}

void sam_build_unit_k(const sam_build_context *ctx, float area, float distance, float out[3])
{
    sam_profile_eval(ctx->profile, distance, out);
    for (int c = 0; c < 3; ++c)
        out[c] *= area;
}

void sam_build_kprime(const sam_build_context *ctx, const float k[3], float area, float distance, float out[3])
{
    float denom[3];
    sam_build_unit_k(ctx, area, distance, denom);
    /* Where R_d underflows, K does too; K' = 1 is its far-field limit.
     * A node's centroid can lie where one channel's R_d is denormal
     * while a nearer member still carries a little K: the same limit
     * keeps K' finite (and that channel's sliver of light is lost). */
    for (int c = 0; c < 3; ++c)
        out[c] = denom[c] > SAM_BUILD_KPRIME_MIN_DENOM ? k[c] / denom[c] : 1.0f;
}

/* A scored candidate. Order: larger value first, then smaller index, so
 * every choice is a deterministic function of the candidate set. */
typedef struct scored {
    float value;
    uint32_t index;
} scored;

static int better(scored a, scored b)
{
    return a.value > b.value || (a.value == b.value && a.index < b.index);
}

/* Min-heap of the best `cap` candidates: the root is the worst kept. */
typedef struct best_heap {
    scored *item;
    uint32_t count, cap;
} best_heap;

static void heap_offer(best_heap *h, scored s)
{
    uint32_t i;
    if (h->count < h->cap) {
        i = h->count++;
        while (i > 0 && better(h->item[(i - 1) / 2], s)) {
            h->item[i] = h->item[(i - 1) / 2];
            i = (i - 1) / 2;
        }
        h->item[i] = s;
        return;
    }
    if (!better(s, h->item[0]))
        return;
    i = 0;
    for (;;) {
        uint32_t l = 2 * i + 1, r = l + 1, m = i;
        scored worst = s;
        if (l < h->count && better(worst, h->item[l]))
            m = l, worst = h->item[l];
        if (r < h->count && better(worst, h->item[r]))
            m = r;
        if (m == i)
            break;
        h->item[i] = h->item[m];
        i = m;
    }
    h->item[i] = s;
}

static int cmp_scored(const void *pa, const void *pb)
{
    scored a = *(const scored *)pa, b = *(const scored *)pb;
    return better(a, b) ? -1 : better(b, a) ? 1 : 0;
}

/* One worker thread's buffers: candidates with their K and error, and the
 * receiver's Monte Carlo points. */
typedef struct scratch {
    scored *cand;
    float (*k)[3];
    float *kerr;
    float *points;
} scratch;

static int scratch_alloc(scratch *s, size_t candidates, uint32_t mc_samples)
{
    s->cand = malloc(candidates * sizeof *s->cand);
    s->k = malloc(candidates * sizeof *s->k);
    s->kerr = malloc(candidates * sizeof *s->kerr);
    s->points = malloc((size_t)mc_samples * SAM_BUILD_POINT_FLOATS * sizeof *s->points);
    return s->cand && s->k && s->kerr && s->points;
}

static void scratch_free(scratch *s)
{
    free(s->cand);
    free(s->k);
    free(s->kerr);
    free(s->points);
}

/* Monte Carlo for the `count` candidates in s->cand, then the best N by
 * mean-RGB K into the result row of vertex o. */
static void choose(const sam_build_context *ctx, uint32_t o, scratch *sc, uint32_t count, sam_build_result *r)
{
    scored *cand = sc->cand;
    float(*k)[3] = sc->k;
    float *kerr = sc->kerr, *points = sc->points;
    const uint32_t n = ctx->settings.samples_per_vertex, m = ctx->settings.mc_samples;
    if (count)
        sam_build_receiver_points(ctx, o, m, ctx->settings.seed, points);
    for (uint32_t c = 0; c < count; ++c) {
        sam_build_form_factor_from(ctx, o, points, cand[c].index, m, ctx->settings.seed, 0, k[c], &kerr[c]);
        cand[c].value = (k[c][0] + k[c][1] + k[c][2]) / 3.0f;
    }
    /* Keep each candidate's K with it while sorting by K. */
    for (uint32_t keep = 0; keep < n && keep < count; ++keep) {
        uint32_t best = keep;
        for (uint32_t c = keep + 1; c < count; ++c)
            if (better(cand[c], cand[best]))
                best = c;
        scored ts = cand[keep];
        cand[keep] = cand[best];
        cand[best] = ts;
        float tk[3], te = kerr[keep];
        memcpy(tk, k[keep], sizeof tk);
        memcpy(k[keep], k[best], sizeof tk);
        memcpy(k[best], tk, sizeof tk);
        kerr[keep] = kerr[best];
        kerr[best] = te;
        if (!(cand[keep].value > 0))
            break; /* a zero form factor carries no light: leave the slot empty */
        size_t slot = (size_t)o * n + keep;
        uint32_t i = cand[keep].index;
        r->sample[slot] = i;
        r->k_error[slot] = kerr[keep];
        memcpy(r->k + 3 * slot, k[keep], 3 * sizeof(float));
        sam_build_kprime(ctx, k[keep], ctx->fan_area[i],
                         sam_build_distance(ctx->pos + 3 * (size_t)o, ctx->pos + 3 * (size_t)i), r->kprime + 3 * slot);
    }
}

/* Vertices are grouped into clusters of up to CLUSTER_SIZE neighbours in
 * Morton order; a cluster is one Embree primitive, so the query visits far
 * fewer primitives, and a whole cluster is skipped when it lies above the
 * tangent plane, when all its normals face the query's side, or when even
 * its largest fan at its nearest point could not make the candidate list. */
#define CLUSTER_SIZE 16

typedef struct cluster {
    float lo[3], hi[3];
    float axis[3];       /* unit mean normal */
    float cone_sin;      /* sin of the widest member normal's angle to axis; > 1: no usable cone */
    float max_fan_area;  /* mm^2 */
    uint32_t first, count; /* into the cluster-ordered vertex list */
} cluster;

typedef struct cluster_set {
    cluster *cluster;
    uint32_t count;
    uint32_t *vertex;    /* topo vertices in cluster order */
} cluster_set;

typedef struct morton_key {
    uint64_t code;
    uint32_t index;
} morton_key;

static int cmp_morton(const void *pa, const void *pb)
{
    const morton_key *a = pa, *b = pb;
    return a->code < b->code ? -1 : a->code > b->code ? 1 : (a->index > b->index) - (a->index < b->index);
}

static uint64_t spread3(uint32_t x)
{
    uint64_t v = x & 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

static void cluster_set_free(cluster_set *cs)
{
    free(cs->cluster);
    free(cs->vertex);
    memset(cs, 0, sizeof *cs);
}

static int cluster_set_build(const sam_build_context *ctx, cluster_set *cs)
{
    const uint32_t n = ctx->mesh->topo_count;
    memset(cs, 0, sizeof *cs);
    morton_key *key = malloc((size_t)n * sizeof *key);
    cs->count = (n + CLUSTER_SIZE - 1) / CLUSTER_SIZE;
    cs->cluster = malloc((size_t)cs->count * sizeof *cs->cluster);
    cs->vertex = malloc((size_t)n * sizeof *cs->vertex);
    if (!key || !cs->cluster || !cs->vertex) {
        free(key);
        cluster_set_free(cs);
        return 0;
    }
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t t = 0; t < n; ++t)
        for (int c = 0; c < 3; ++c) {
            lo[c] = fminf(lo[c], ctx->pos[3 * (size_t)t + c]);
            hi[c] = fmaxf(hi[c], ctx->pos[3 * (size_t)t + c]);
        }
    for (uint32_t t = 0; t < n; ++t) {
        uint64_t code = 0;
        for (int c = 0; c < 3; ++c) {
            float ext = hi[c] - lo[c];
            uint32_t q = ext > 0 ? (uint32_t)((ctx->pos[3 * (size_t)t + c] - lo[c]) / ext * 2097151.0f) : 0;
            code |= spread3(q) << c;
        }
        key[t] = (morton_key){code, t};
    }
    qsort(key, n, sizeof *key, cmp_morton);
    for (uint32_t t = 0; t < n; ++t)
        cs->vertex[t] = key[t].index;
    free(key);
    for (uint32_t ci = 0; ci < cs->count; ++ci) {
        cluster *cl = &cs->cluster[ci];
        cl->first = ci * CLUSTER_SIZE;
        cl->count = n - cl->first < CLUSTER_SIZE ? n - cl->first : CLUSTER_SIZE;
        double axis[3] = {0, 0, 0};
        for (int c = 0; c < 3; ++c)
            cl->lo[c] = INFINITY, cl->hi[c] = -INFINITY;
        cl->max_fan_area = 0;
        for (uint32_t k = 0; k < cl->count; ++k) {
            uint32_t t = cs->vertex[cl->first + k];
            for (int c = 0; c < 3; ++c) {
                cl->lo[c] = fminf(cl->lo[c], ctx->pos[3 * (size_t)t + c]);
                cl->hi[c] = fmaxf(cl->hi[c], ctx->pos[3 * (size_t)t + c]);
                axis[c] += ctx->mesh->topo_normals[3 * (size_t)t + c];
            }
            cl->max_fan_area = fmaxf(cl->max_fan_area, ctx->fan_area[t]);
        }
        double len = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        double cos_min = len > 0 ? 1.0 : -1.0;
        for (int c = 0; c < 3; ++c)
            cl->axis[c] = len > 0 ? (float)(axis[c] / len) : 0.0f;
        for (uint32_t k = 0; k < cl->count && len > 0; ++k) {
            const float *nt = ctx->mesh->topo_normals + 3 * (size_t)cs->vertex[cl->first + k];
            cos_min = fmin(cos_min, cl->axis[0] * nt[0] + cl->axis[1] * nt[1] + cl->axis[2] * nt[2]);
        }
        cl->cone_sin = cos_min > 0 ? (float)sqrt(1.0 - cos_min * cos_min) : 2.0f;
    }
    return 1;
}

typedef struct query_state {
    const sam_build_context *ctx;
    const cluster_set *clusters;
    uint32_t o;
    float normal[3];
    float radius0;
    float radius_for;  /* the heap threshold the current radius was computed for */
    best_heap heap;
    uint64_t seen;
} query_state;

/* Offers vertex i to the candidate list of q->o. */
static void offer_vertex(query_state *q, uint32_t i)
{
    const sam_build_context *ctx = q->ctx;
    if (i == q->o)
        return;
    const float *po = ctx->pos + 3 * (size_t)q->o, *pi = ctx->pos + 3 * (size_t)i;
    float dx = pi[0] - po[0], dy = pi[1] - po[1], dz = pi[2] - po[2];
    const float *ni = ctx->mesh->topo_normals + 3 * (size_t)i;
    /* eq. 13 and 14 */
    if (dx * q->normal[0] + dy * q->normal[1] + dz * q->normal[2] >= 0.0f ||
        ni[0] * q->normal[0] + ni[1] * q->normal[1] + ni[2] * q->normal[2] >= 0.0f)
        return;
    float d = sqrtf(dx * dx + dy * dy + dz * dz);
    if (d > q->radius0)
        return; /* outside the initial radius: never a candidate, whatever the traversal */
    q->seen++;
    scored s = {ctx->fan_area[i] * sam_build_rd_mean(ctx, d), i};
    if (s.value > 0)
        heap_offer(&q->heap, s);
}

/* Upper bound of the mean R_d at distances >= r (R_d decreases with r). */
static float rd_bound(const sam_build_context *ctx, float r)
{
    if (r >= ctx->table_radius)
        return sam_build_rd_mean(ctx, r);
    return ctx->envelope[(int)(r * ctx->table_inv_step)];
}

static bool point_query(struct RTCPointQueryFunctionArguments *args)
{
    query_state *q = args->userPtr;
    const sam_build_context *ctx = q->ctx;
    const cluster *cl = &q->clusters->cluster[args->primID];
    const float *po = ctx->pos + 3 * (size_t)q->o;
    /* Nearest point of the box, and the box's lowest point along n_o. */
    double d2 = 0, below = 0, scale = 0;
    for (int c = 0; c < 3; ++c) {
        double x = po[c] < cl->lo[c] ? cl->lo[c] - po[c] : po[c] > cl->hi[c] ? po[c] - cl->hi[c] : 0.0;
        d2 += x * x;
        double centre = 0.5 * ((double)cl->lo[c] + cl->hi[c]) - po[c], half = 0.5 * ((double)cl->hi[c] - cl->lo[c]);
        below += centre * q->normal[c] - half * fabs(q->normal[c]);
        scale += fabs(centre) + half;
    }
    float dmin = (float)sqrt(d2);
    if (dmin > q->radius0)
        return false;
    /* The whole box above the tangent plane (eq. 13 fails for all), with a
     * margin for the float arithmetic of the per-vertex test. */
    if (below > 1e-5 * scale)
        return false;
    /* All normals within 90 degrees of n_o (eq. 14 fails for all). */
    if (cl->cone_sin <= 1.0f &&
        cl->axis[0] * q->normal[0] + cl->axis[1] * q->normal[1] + cl->axis[2] * q->normal[2] >= cl->cone_sin + 1e-4f)
        return false;
    if (q->heap.count == q->heap.cap && cl->max_fan_area * rd_bound(ctx, dmin) < q->heap.item[0].value)
        return false;
    for (uint32_t k = 0; k < cl->count; ++k)
        offer_vertex(q, q->clusters->vertex[cl->first + k]);
    if (q->heap.count < q->heap.cap)
        return false;
    /* Every vertex farther than this has F' R_d <= max F' * R_d < the worst
     * kept. Recomputed only when the threshold rose by 5%: a stale, larger
     * radius is still safe. */
    float threshold = q->heap.item[0].value;
    if (threshold < 1.05f * q->radius_for)
        return false;
    q->radius_for = threshold;
    float r = sam_build_bound_radius(ctx, threshold / ctx->max_fan_area);
    if (r < args->query->radius) {
        args->query->radius = r;
        return true;
    }
    return false;
}

static void bounds_fn(const struct RTCBoundsFunctionArguments *args)
{
    const cluster *cl = (const cluster *)args->geometryUserPtr + args->primID;
    args->bounds_o->lower_x = cl->lo[0];
    args->bounds_o->lower_y = cl->lo[1];
    args->bounds_o->lower_z = cl->lo[2];
    args->bounds_o->upper_x = cl->hi[0];
    args->bounds_o->upper_y = cl->hi[1];
    args->bounds_o->upper_z = cl->hi[2];
}

static void embree_error(void *user, enum RTCError code, const char *str)
{
    char *msg = user;
    if (!msg[0])
        snprintf(msg, 256, "Embree error %d: %s", (int)code, str ? str : "");
}

int sam_build_progress_step(sam_build_progress *p)
{
    uint64_t done;
#pragma omp atomic capture
    done = ++p->done;
    int cancelled;
#pragma omp atomic read
    cancelled = p->cancelled;
    if (cancelled)
        return 1;
    if (p->fn && omp_get_thread_num() == 0 && (done >= p->next_report || done == p->total)) {
        p->next_report = done + p->total / 200 + 1;
        if (p->fn(p->user, done, p->total)) {
#pragma omp atomic write
            p->cancelled = 1;
            return 1;
        }
    }
    return 0;
}

sam_status sam_build_progress_finish(sam_build_progress *p, sam_build_result *r, double start, sam_error *err)
{
    if (p->cancelled) {
        sam_build_result_destroy(r);
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "build cancelled after %llu of %llu vertices",
                        (unsigned long long)p->done, (unsigned long long)p->total);
    }
    if (p->fn)
        p->fn(p->user, p->total, p->total);
    r->seconds = sam_seconds() - start;
    return SAM_OK;
}

int sam_build_thread_count(const sam_build_context *ctx)
{
    return ctx->settings.threads > 0 ? ctx->settings.threads : omp_get_max_threads();
}

/* One vertex's search: gathers vertex o's candidates in sc, choose()s its
 * samples into the result and adds to the counters. */
typedef void (*vertex_search_fn)(const sam_build_context *ctx, const void *data, uint32_t o, scratch *sc,
                                 sam_build_result *result, uint64_t *seen, uint64_t *form_factors);

/* The per-vertex loop both builds share: threads with their own scratch
 * (room for `capacity` candidates), dynamic chunks of `chunk` vertices,
 * progress and cancellation, and the result's counters and time. `what`
 * names the build in messages. On failure the result is destroyed. */
static sam_status search_vertices(const sam_build_context *ctx, vertex_search_fn search, const void *data,
                                  uint32_t capacity, int chunk, const char *what, sam_build_progress_fn progress,
                                  void *user, double start, sam_build_result *result, sam_error *err)
{
    const uint32_t n = ctx->mesh->topo_count;
    sam_build_progress prog = {progress, user, 0, n, 0, 0};
    uint64_t seen = 0, form_factors = 0;
    int oom = 0;
#pragma omp parallel num_threads(sam_build_thread_count(ctx)) reduction(+ : seen, form_factors)
    {
        scratch sc;
        if (!scratch_alloc(&sc, capacity, ctx->settings.mc_samples)) {
#pragma omp atomic write
            oom = 1;
#pragma omp atomic write
            prog.cancelled = 1;
        }
#pragma omp for schedule(dynamic, chunk)
        for (uint32_t o = 0; o < n; ++o)
            if (!sam_build_progress_step(&prog))
                search(ctx, data, o, &sc, result, &seen, &form_factors);
        scratch_free(&sc);
    }
    if (oom) {
        sam_build_result_destroy(result);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "%s: out of memory for per-thread buffers", what);
    }
    result->candidates_seen = seen;
    result->form_factors = form_factors;
    return sam_build_progress_finish(&prog, result, start, err);
}

/* What the fast search's vertices share: the clusters and their BVH. */
typedef struct search_data {
    RTCScene scene;
    const cluster_set *clusters;
} search_data;

/* The fast build: candidates from a point query of the cluster BVH. */
static void search_fast(const sam_build_context *ctx, const void *data, uint32_t o, scratch *sc,
                        sam_build_result *result, uint64_t *seen, uint64_t *form_factors)
{
    const search_data *d = data;
    query_state q = {ctx, d->clusters, o, {0, 0, 0}, ctx->search_radius, 0.0f, {sc->cand, 0, ctx->candidates}, 0};
    memcpy(q.normal, ctx->mesh->topo_normals + 3 * (size_t)o, sizeof q.normal);
    struct RTCPointQuery query;
    query.x = ctx->pos[3 * (size_t)o];
    query.y = ctx->pos[3 * (size_t)o + 1];
    query.z = ctx->pos[3 * (size_t)o + 2];
    query.time = 0.0f;
    query.radius = ctx->search_radius;
    struct RTCPointQueryContext qc;
    rtcInitPointQueryContext(&qc);
    rtcPointQuery(d->scene, &query, &qc, point_query, &q);
    *seen += q.seen;
    qsort(sc->cand, q.heap.count, sizeof *sc->cand, cmp_scored);
    choose(ctx, o, sc, q.heap.count, result);
    *form_factors += q.heap.count;
}

sam_status sam_build_run_flat(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                              sam_build_result *result, sam_error *err)
{
    double start = sam_seconds();
    sam_status st = sam_build_result_alloc(ctx, ctx->settings.samples_per_vertex, 0, result, err);
    if (st != SAM_OK)
        return st;
    cluster_set clusters;
    if (!cluster_set_build(ctx, &clusters)) {
        sam_build_result_destroy(result);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory for the search structure");
    }
    char embree_msg[256] = "";
    RTCDevice device = rtcNewDevice(NULL);
    if (!device) {
        cluster_set_free(&clusters);
        sam_build_result_destroy(result);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "build: Embree could not create a device (error %d)",
                        (int)rtcGetDeviceError(NULL));
    }
    rtcSetDeviceErrorFunction(device, embree_error, embree_msg);
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, clusters.count);
    rtcSetGeometryUserData(geom, clusters.cluster);
    rtcSetGeometryBoundsFunction(geom, bounds_fn, clusters.cluster);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    if (embree_msg[0]) {
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
        cluster_set_free(&clusters);
        sam_build_result_destroy(result);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "build: %s", embree_msg);
    }

    const search_data data = {scene, &clusters};
    st = search_vertices(ctx, search_fast, &data, ctx->candidates, 64, "build", progress, user, start, result, err);
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    cluster_set_free(&clusters);
    return st;
}

/* The reference: every back-side vertex is a candidate. */
static void search_all(const sam_build_context *ctx, const void *data, uint32_t o, scratch *sc,
                       sam_build_result *result, uint64_t *seen, uint64_t *form_factors)
{
    (void)data;
    uint32_t count = 0;
    for (uint32_t i = 0; i < ctx->mesh->topo_count; ++i)
        if (i != o && sam_build_behind(ctx, o, i))
            sc->cand[count++] = (scored){0.0f, i};
    *seen += count;
    *form_factors += count;
    choose(ctx, o, sc, count, result);
}

sam_status sam_build_reference(const sam_build_context *ctx, sam_build_progress_fn progress, void *user,
                               sam_build_result *result, sam_error *err)
{
    double start = sam_seconds();
    sam_status st = sam_build_result_alloc(ctx, ctx->settings.samples_per_vertex, 0, result, err);
    if (st != SAM_OK)
        return st;
    return search_vertices(ctx, search_all, NULL, ctx->mesh->topo_count, 16, "reference build", progress, user,
                           start, result, err);
}
