/* The build context: scaled geometry, fan sampling, the R_d table and the
 * Monte Carlo form factor of eq. 11. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sam/sam_rng.h"
#include "sam_build_internal.h"

void sam_build_default_settings(sam_build_settings *s)
{
    memset(s, 0, sizeof *s);
    s->map = SAM_BUILD_MAP_CUT;
    s->samples_per_vertex = 0;
    s->cut_tolerance = 0.01f;
    s->mc_samples = 64;
    s->candidates = 0;
    s->radius_tolerance = 1e-4f;
    s->seed = 1;
    s->threads = 0;
}

const char *sam_build_map_name(sam_build_map map)
{
    switch (map) {
    case SAM_BUILD_MAP_CUT:
        return "cut";
    case SAM_BUILD_MAP_FLAT:
        return "flat";
    case SAM_BUILD_MAP_FLAT_SCALED:
        return "flat-scaled";
    }
    return "?";
}

uint32_t sam_build_samples(const sam_build_settings *s)
{
    if (s->samples_per_vertex)
        return s->samples_per_vertex;
    return s->map == SAM_BUILD_MAP_CUT ? SAM_BUILD_CUT_DEFAULT_SAMPLES : SAM_BUILD_FLAT_DEFAULT_SAMPLES;
}

uint32_t sam_build_cut_budget(const sam_build_settings *s)
{
    const uint32_t n = sam_build_samples(s);
    return s->cut_budget ? s->cut_budget : n > SAM_BUILD_CUT_DEFAULT_BUDGET ? n : SAM_BUILD_CUT_DEFAULT_BUDGET;
}

sam_status sam_build_check_settings(const sam_build_settings *s, float mm_per_unit, sam_error *err)
{
    if (!(mm_per_unit > 0) || !isfinite(mm_per_unit))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "scale: millimetres per unit must be a finite number > 0, got %g",
                        mm_per_unit);
    if (s->samples_per_vertex > SAMFILE_MAX_SAMPLES_PER_VERTEX)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "samples per vertex must be in 1..%d (0: default), got %u",
                        SAMFILE_MAX_SAMPLES_PER_VERTEX, s->samples_per_vertex);
    if (s->map != SAM_BUILD_MAP_CUT && s->map != SAM_BUILD_MAP_FLAT && s->map != SAM_BUILD_MAP_FLAT_SCALED)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "map kind must be cut, flat or flat-scaled, got %d",
                        (int)s->map);
    if (s->cut_budget && (s->cut_budget < sam_build_samples(s) || s->cut_budget > SAMFILE_MAX_SAMPLES_PER_VERTEX))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "cut budget must be 0 (the larger of the samples per vertex and %u) or in %u..%d (at "
                        "least the samples per vertex), got %u",
                        SAM_BUILD_CUT_DEFAULT_BUDGET,
                        sam_build_samples(s), SAMFILE_MAX_SAMPLES_PER_VERTEX, s->cut_budget);
    if (!(s->cut_tolerance > 0 && s->cut_tolerance < 1))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "cut tolerance must be in (0, 1), got %g", s->cut_tolerance);
    if (s->mc_samples < 4 || s->mc_samples > 65536)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "Monte Carlo samples must be in 4..65536, got %u", s->mc_samples);
    if (s->candidates && (s->candidates < sam_build_samples(s) || s->candidates > 4096))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "candidates must be 0 (automatic) or in %u..4096 (at least the samples per vertex), got %u",
                        sam_build_samples(s), s->candidates);
    if (!(s->radius_tolerance > 0 && s->radius_tolerance < 0.5f))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "radius tolerance must be in (0, 0.5), got %g",
                        s->radius_tolerance);
    if (s->threads < 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "threads must be >= 0, got %d", s->threads);
    return SAM_OK;
}

/* ---- R_d */

float sam_build_bound_radius(const sam_build_context *ctx, float threshold)
{
    /* The envelope is non-increasing: find the last index still >= threshold. */
    if (ctx->envelope[0] < threshold)
        return 0.0f;
    int lo = 0, hi = SAM_RD_TABLE_SIZE;
    if (ctx->envelope[hi] >= threshold)
        return ctx->table_radius;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (ctx->envelope[mid] >= threshold)
            lo = mid;
        else
            hi = mid;
    }
    /* Interpolated values in [lo, lo + 1] are bounded by envelope[lo]. */
    return (float)(lo + 1) / ctx->table_inv_step;
}

/* ---- the context */

void sam_build_fan_corners(const sam_build_context *ctx, uint32_t t, uint32_t k, float p[2][3], float n[2][3])
{
    const sam_mesh *m = ctx->mesh;
    const uint32_t a = m->ring[k], b = k > m->ring_offsets[t] ? m->ring[k - 1] : t;
    const float *pt = ctx->pos + 3 * (size_t)t, *pa = ctx->pos + 3 * (size_t)a, *pb = ctx->pos + 3 * (size_t)b;
    const float *nt = m->topo_normals + 3 * (size_t)t, *na = m->topo_normals + 3 * (size_t)a,
                *nb = m->topo_normals + 3 * (size_t)b;
    for (int c = 0; c < 3; ++c) {
        p[0][c] = 0.5f * (pt[c] + pa[c]);
        p[1][c] = (pt[c] + pa[c] + pb[c]) / 3.0f;
        n[0][c] = 0.5f * (nt[c] + na[c]);
        n[1][c] = (nt[c] + na[c] + nb[c]) / 3.0f;
    }
}

/* Per topo vertex, the largest distance (mm) of a fan corner from the
 * vertex, and of the normals interpolated there from the vertex normal,
 * each enlarged a little so that float rounding never makes
 * sam_build_fan_side's shortcut claim more than its corners would. */
static void fan_reach(const sam_build_context *ctx, float *reach)
{
    const sam_mesh *mesh = ctx->mesh;
    for (uint32_t t = 0; t < mesh->topo_count; ++t) {
        const float *v = ctx->pos + 3 * (size_t)t, *nv = mesh->topo_normals + 3 * (size_t)t;
        float far2 = 0.0f, turn2 = 0.0f;
        for (uint32_t k = mesh->ring_offsets[t]; k < mesh->ring_offsets[t + 1]; ++k) {
            float p[2][3], n[2][3];
            sam_build_fan_corners(ctx, t, k, p, n);
            for (int j = 0; j < 2; ++j) {
                float d2 = 0.0f, e2 = 0.0f;
                for (int c = 0; c < 3; ++c) {
                    d2 += (p[j][c] - v[c]) * (p[j][c] - v[c]);
                    e2 += (n[j][c] - nv[c]) * (n[j][c] - nv[c]);
                }
                far2 = fmaxf(far2, d2);
                turn2 = fmaxf(turn2, e2);
            }
        }
        reach[2 * (size_t)t] = sqrtf(far2) * 1.001f + 1e-6f;
        reach[2 * (size_t)t + 1] = sqrtf(turn2) * 1.001f + 1e-6f;
    }
}

sam_status sam_build_context_create(const sam_mesh *mesh, const sam_profile *profile, float mm_per_unit,
                                    const sam_build_settings *settings, sam_build_context **out, sam_error *err)
{
    *out = NULL;
    sam_status st = sam_build_check_settings(settings, mm_per_unit, err);
    if (st != SAM_OK)
        return st;
    if (!mesh || !mesh->topo_count || !profile)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "build: empty mesh or no profile");
    sam_build_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory");
    ctx->mesh = mesh;
    ctx->profile = profile;
    ctx->mm_per_unit = mm_per_unit;
    ctx->settings = *settings;
    /* The builders read N from here, resolved. */
    ctx->settings.samples_per_vertex = sam_build_samples(settings);
    ctx->settings.cut_budget = sam_build_cut_budget(settings);
    ctx->candidates = settings->candidates ? settings->candidates : ctx->settings.samples_per_vertex + 2;
    const uint32_t n = mesh->topo_count, ring_total = mesh->ring_offsets[n];
    ctx->pos = malloc((size_t)n * 3 * sizeof *ctx->pos);
    ctx->fan_area = malloc((size_t)n * sizeof *ctx->fan_area);
    ctx->fan_reach = malloc((size_t)n * 2 * sizeof *ctx->fan_reach);
    ctx->pair_cdf = malloc((size_t)ring_total * sizeof *ctx->pair_cdf);
    ctx->table = malloc((SAM_RD_TABLE_SIZE + 1) * sizeof *ctx->table);
    ctx->envelope = malloc((SAM_RD_TABLE_SIZE + 1) * sizeof *ctx->envelope);
    if (!ctx->pos || !ctx->fan_area || !ctx->fan_reach || !ctx->pair_cdf || !ctx->table || !ctx->envelope) {
        sam_build_context_destroy(ctx);
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "build: out of memory for %u vertices", n);
    }
    for (uint32_t t = 0; t < n; ++t)
        for (int c = 0; c < 3; ++c)
            ctx->pos[3 * (size_t)t + c] = mesh->positions[3 * (size_t)mesh->topo_rep[t] + c] * mm_per_unit;
    /* Fan areas (eq. 16) and the cumulative quad areas used to sample
     * points uniformly on the reduced fan; each quad is a third of its
     * triangle. */
    for (uint32_t t = 0; t < n; ++t) {
        const float *v = ctx->pos + 3 * (size_t)t;
        double sum = 0;
        uint32_t begin = mesh->ring_offsets[t], end = mesh->ring_offsets[t + 1];
        ctx->pair_cdf[begin] = 0;
        for (uint32_t k = begin + 1; k < end; ++k) {
            const float *a = ctx->pos + 3 * (size_t)mesh->ring[k - 1], *b = ctx->pos + 3 * (size_t)mesh->ring[k];
            double e1[3], e2[3];
            for (int c = 0; c < 3; ++c)
                e1[c] = (double)a[c] - v[c], e2[c] = (double)b[c] - v[c];
            double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                   cz = e1[0] * e2[1] - e1[1] * e2[0];
            sum += sqrt(cx * cx + cy * cy + cz * cz) / 6.0;
            ctx->pair_cdf[k] = (float)sum;
            double la = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
            if (la > ctx->max_edge)
                ctx->max_edge = (float)la;
        }
        ctx->fan_area[t] = (float)sum;
        if (ctx->fan_area[t] > ctx->max_fan_area)
            ctx->max_fan_area = ctx->fan_area[t];
    }
    fan_reach(ctx, ctx->fan_reach);
    /* The table spans twice the search radius plus two fan diameters, so
     * every Monte Carlo pair of a candidate inside the radius is tabulated. */
    ctx->search_radius = sam_profile_radius(profile, settings->radius_tolerance);
    ctx->table_radius = 2.0f * ctx->search_radius + 4.0f * ctx->max_edge;
    ctx->table_inv_step = (float)SAM_RD_TABLE_SIZE / ctx->table_radius;
    for (int j = 0; j <= SAM_RD_TABLE_SIZE; ++j) {
        float rgb[3];
        sam_profile_eval(profile, (float)j / ctx->table_inv_step, rgb);
        ctx->table[j][0] = rgb[0];
        ctx->table[j][1] = rgb[1];
        ctx->table[j][2] = rgb[2];
        ctx->table[j][3] = (rgb[0] + rgb[1] + rgb[2]) / 3.0f;
    }
    ctx->envelope[SAM_RD_TABLE_SIZE] = ctx->table[SAM_RD_TABLE_SIZE][3];
    for (int j = SAM_RD_TABLE_SIZE - 1; j >= 0; --j)
        ctx->envelope[j] = fmaxf(ctx->table[j][3], ctx->envelope[j + 1]);
    *out = ctx;
    return SAM_OK;
}

void sam_build_context_destroy(sam_build_context *ctx)
{
    if (!ctx)
        return;
    free(ctx->pos);
    free(ctx->fan_area);
    free(ctx->fan_reach);
    free(ctx->pair_cdf);
    free(ctx->table);
    free(ctx->envelope);
    free(ctx);
}

float sam_build_fan_area(const sam_build_context *ctx, uint32_t t)
{
    return ctx->fan_area[t];
}

int sam_build_is_back_side(const sam_build_context *ctx, uint32_t o, uint32_t i)
{
    return sam_build_behind(ctx, o, i);
}

int sam_build_fan_back_side(const sam_build_context *ctx, uint32_t o, uint32_t i)
{
    return o == i ? 0 : (int)sam_build_fan_side(ctx, o, i);
}

void sam_build_fan_point(const sam_build_context *ctx, uint32_t t, const float uv[3], float out[3], float normal[3])
{
    const sam_mesh *m = ctx->mesh;
    uint32_t begin = m->ring_offsets[t], end = m->ring_offsets[t + 1];
    float target = uv[0] * ctx->fan_area[t];
    uint32_t k = begin + 1;
    while (k + 1 < end && ctx->pair_cdf[k] <= target)
        k++;
    const uint32_t ia = m->ring[k - 1], ib = m->ring[k];
    const float *v = ctx->pos + 3 * (size_t)t;
    const float *a = ctx->pos + 3 * (size_t)ia, *b = ctx->pos + 3 * (size_t)ib;
    /* The quad v, mid(v,a), centroid, mid(v,b) is two triangles of equal
     * area (a sixth of the face each). Where the pair was chosen, the
     * position of `target` inside its quad's share is itself uniform: it
     * picks the half without another random number. */
    float lo = k > begin + 1 ? ctx->pair_cdf[k - 1] : 0.0f, span = ctx->pair_cdf[k] - lo;
    int second = span > 0 && (target - lo) > 0.5f * span;
    float u = uv[1], w = uv[2];
    if (u + w > 1.0f)
        u = 1.0f - u, w = 1.0f - w;
    /* v + u (mid - v) + w (centroid - v), as weights of v, a and b. */
    const float wv = 1.0f - 0.5f * u - (2.0f / 3.0f) * w, wa = (second ? 0.0f : 0.5f * u) + w / 3.0f,
                wb = (second ? 0.5f * u : 0.0f) + w / 3.0f;
    for (int c = 0; c < 3; ++c)
        out[c] = wv * v[c] + wa * a[c] + wb * b[c];
    if (normal) {
        const float *nv = m->topo_normals + 3 * (size_t)t, *na = m->topo_normals + 3 * (size_t)ia,
                    *nb = m->topo_normals + 3 * (size_t)ib;
        for (int c = 0; c < 3; ++c)
            normal[c] = wv * nv[c] + wa * na[c] + wb * nb[c];
    }
}

void sam_build_sample_fan(const sam_build_context *ctx, uint32_t t, sam_rng *rng, float out[3], float normal[3])
{
    float u[3];
    for (int d = 0; d < 3; ++d)
        u[d] = sam_rng_float(rng);
    sam_build_fan_point(ctx, t, u, out, normal);
}

/* R_6's steps, frac(phi^-j) for j = 1..6 with phi the positive root of
 * x^7 = x + 1 (1.11277568...), in 24-bit fixed point. */
static const uint32_t lattice_steps[6] = {15076907u, 13548919u, 12175786u, 10941815u, 9832903u, 8836375u};

void sam_build_lattice_start(sam_build_lattice *lattice, int sender, sam_rng *rng)
{
    for (int d = 0; d < 3; ++d) {
        lattice->shift[d] = (uint32_t)(sam_rng_float(rng) * (float)(1u << SAM_BUILD_LATTICE_BITS));
        lattice->step[d] = lattice_steps[3 * (sender != 0) + d];
    }
}

/* The stream index of vertex o's own points: no candidate index is this. */
#define RECEIVER_STREAM UINT64_MAX

void sam_build_receiver_points(const sam_build_context *ctx, uint32_t o, uint32_t samples, uint64_t seed,
                               float *points)
{
    sam_rng rng;
    sam_rng_seed(&rng, seed, o, RECEIVER_STREAM);
    sam_build_lattice lattice;
    sam_build_lattice_start(&lattice, 0, &rng);
    for (uint32_t s = 0; s < samples; ++s) {
        float *point = points + SAM_BUILD_POINT_FLOATS * (size_t)s, u[3];
        sam_build_lattice_at(&lattice, s, u);
        sam_build_fan_point(ctx, o, u, point, point + 3);
    }
}

uint32_t sam_build_pair_count(const sam_build_context *ctx, uint32_t o, uint32_t i, uint32_t samples)
{
    const float d = sam_build_distance(ctx->pos + 3 * (size_t)o, ctx->pos + 3 * (size_t)i);
    const float reach = ctx->fan_reach[2 * (size_t)o] + ctx->fan_reach[2 * (size_t)i];
    float near[4], far[4];
    if (samples > UINT32_MAX / SAM_BUILD_STEEP_PAIRS)
        return samples;
    sam_build_rd_span(ctx, d, reach, near, far);
    for (int c = 0; c < 3; ++c)
        if (near[c] > SAM_BUILD_STEEP_FALL * far[c] && near[c] > SAM_BUILD_STEEP_NEAR * ctx->table[0][c])
            return samples * SAM_BUILD_STEEP_PAIRS;
    return samples;
}

void sam_build_form_factor_from(const sam_build_context *ctx, uint32_t o, const float *points, uint32_t i,
                                uint32_t samples, uint64_t seed, int pointwise, float k[3], float *k_error)
{
    sam_rng rng;
    sam_rng_seed(&rng, seed, o, i);
    sam_build_lattice lattice;
    sam_build_lattice_start(&lattice, 1, &rng);
    const uint32_t pairs = sam_build_pair_count(ctx, o, i, samples);
    double sum[3] = {0, 0, 0}, sum_mean = 0, sum_sq = 0;
    /* A steep pair's further senders go round o's points again. */
    for (uint32_t s = 0, r = 0; s < pairs; ++s, r = r + 1 == samples ? 0 : r + 1) {
        float xi[3], ni[3], rd[4], u[3];
        const float *xo = points + SAM_BUILD_POINT_FLOATS * (size_t)r;
        sam_build_lattice_at(&lattice, s, u);
        sam_build_fan_point(ctx, i, u, xi, pointwise ? ni : NULL);
        if (pointwise && !sam_build_point_faces_away(xo + 3, ni))
            continue;
        /* The part of F'_i in front of this point's tangent plane sends it
         * nothing. The vertex test (eq. 13-14 between the fans' centres)
         * takes whole fans: where a fold brings a fan within a fraction of
         * a millimetre of o's tangent plane (a scan's rims), most of its
         * R_d comes from points in front of it, and K came out 4 to 10
         * times the transport the ground truth finds at o. Eq. 14 stays
         * the vertices' own: asked point by point, it cut the part of
         * every fan on a thin tube's back-side edge (90 degrees around)
         * that faces o's way, while the fans just short of the edge, whose
         * other part faces away, stay out of the search (docs/builder.md). */
        if (!sam_build_point_behind(xo, xo + 3, xi))
            continue;
        sam_build_rd(ctx, sam_build_distance(xo, xi), rd);
        for (int c = 0; c < 3; ++c)
            sum[c] += rd[c];
        sum_mean += rd[3];
        sum_sq += (double)rd[3] * rd[3];
    }
    /* K = F'_i E[R_d(|x_i - x_o|)] with x_o, x_i uniform on the two fans. */
    double area = ctx->fan_area[i], inv = 1.0 / pairs;
    for (int c = 0; c < 3; ++c)
        k[c] = (float)(area * sum[c] * inv);
    double mean = sum_mean * inv, var = sum_sq * inv - mean * mean;
    if (var < 0)
        var = 0;
    *k_error = (float)(area * sqrt(var / (pairs > 1 ? pairs - 1 : 1)));
}

/* One K_oi with o's points of its own (the public entry points). */
static void form_factor_alone(const sam_build_context *ctx, uint32_t o, uint32_t i, uint32_t samples, uint64_t seed,
                              int pointwise, float k[3], float *k_error)
{
    float *points = malloc((size_t)samples * SAM_BUILD_POINT_FLOATS * sizeof *points);
    if (!points) {
        k[0] = k[1] = k[2] = NAN;
        *k_error = NAN;
        return;
    }
    sam_build_receiver_points(ctx, o, samples, seed, points);
    sam_build_form_factor_from(ctx, o, points, i, samples, seed, pointwise, k, k_error);
    free(points);
}

void sam_build_form_factor(const sam_build_context *ctx, uint32_t o, uint32_t i, uint32_t samples, uint64_t seed,
                           float k[3], float *k_error)
{
    form_factor_alone(ctx, o, i, samples, seed, 0, k, k_error);
}

void sam_build_form_factor_pointwise(const sam_build_context *ctx, uint32_t o, uint32_t i, uint32_t samples,
                                     uint64_t seed, float k[3], float *k_error)
{
    form_factor_alone(ctx, o, i, samples, seed, 1, k, k_error);
}
