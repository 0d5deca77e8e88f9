/* The ground truth's samples: placement on the mesh and L_d (eq. 4) with
 * Embree visibility, mirroring shaders/irradiance.comp. */
#include "sam_truth_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "sam/sam_light.h"
#include "sam/sam_rng.h"

/* The fractional part of the golden ratio: the lattice's second axis. */
#define GOLDEN_FRACTION 0.61803398874989484820

/* A ray that ends this fraction short of its light does not hit an emitter
 * modelled as part of the mesh. */
#define RAY_END_SHRINK 1e-4f

static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void embree_error(void *user, enum RTCError code, const char *str)
{
    char *msg = user;
    if (!msg[0])
        snprintf(msg, 256, "Embree error %d: %s", (int)code, str ? str : "");
}

sam_status truth_embree_scene(sam_truth *t, sam_error *err)
{
    rtcSetDeviceErrorFunction(t->device, embree_error, t->embree_message);
    t->scene = rtcNewScene(t->device);
    RTCGeometry geom = rtcNewGeometry(t->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    /* Embree's own buffers: it reads vertex buffers 16 bytes at a time, past
     * the end of a tightly packed caller array. */
    float *vb = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                        t->vertex_count);
    uint32_t *ib = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                           t->triangle_count);
    if (vb && ib) {
        memcpy(vb, t->positions, 3 * sizeof(float) * t->vertex_count);
        memcpy(ib, t->triangles, 3 * sizeof(uint32_t) * t->triangle_count);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(t->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(t->scene);
    enum RTCError code = rtcGetDeviceError(t->device);
    if (code != RTC_ERROR_NONE || !vb || !ib || t->embree_message[0])
        return sam_fail(err, SAM_ERR_UNSUPPORTED,
                        "truth: building the ray-tracing scene failed (rtcGetDeviceError %d%s%s)", (int)code,
                        t->embree_message[0] ? "; " : "", t->embree_message);
    return SAM_OK;
}

/* Sample i: the shifted rank-1 lattice point (u, v) of the overview, on the
 * triangle u picks. Also the geometric normal, turned to the shading side. */
static void place(const sam_truth *t, uint64_t i, float p[3], float n[3], float ng[3])
{
    double u = ((double)i + t->shift[0]) / (double)t->sample_count;
    double target = u * t->total_area;
    /* Rounding must not push the target onto the end of the CDF, where only
     * zero-area triangles could follow. */
    if (target >= t->total_area)
        target = nextafter(t->total_area, 0.0);
    uint32_t lo = 0, hi = t->triangle_count - 1;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (t->area_cdf[mid] > target)
            hi = mid;
        else
            lo = mid + 1;
    }
    double before = lo ? t->area_cdf[lo - 1] : 0.0, area = t->area_cdf[lo] - before;
    double s = area > 0 ? (target - before) / area : 0.5;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    double v = t->shift[1] + (double)i * GOLDEN_FRACTION;
    v -= floor(v);
    double r = sqrt(s), b[3] = {1.0 - r, r * (1.0 - v), r * v};

    const uint32_t *tri = t->triangles + 3 * (size_t)lo;
    const float *a = t->positions + 3 * (size_t)tri[0], *bp = t->positions + 3 * (size_t)tri[1],
                *c = t->positions + 3 * (size_t)tri[2];
    double nn[3], len2 = 0;
    for (int k = 0; k < 3; ++k) {
        p[k] = (float)(b[0] * a[k] + b[1] * bp[k] + b[2] * c[k]);
        nn[k] = b[0] * t->normals[3 * (size_t)tri[0] + k] + b[1] * t->normals[3 * (size_t)tri[1] + k] +
                b[2] * t->normals[3 * (size_t)tri[2] + k];
        len2 += nn[k] * nn[k];
    }
    float e1[3], e2[3];
    for (int k = 0; k < 3; ++k)
        e1[k] = bp[k] - a[k], e2[k] = c[k] - a[k];
    float g[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    float glen = sqrtf(dot3(g, g));
    for (int k = 0; k < 3; ++k)
        ng[k] = g[k] / glen;
    /* Opposite vertex normals can cancel: the face's own normal is then the
     * only direction the sample has. */
    if (len2 > 0) {
        double inv = 1.0 / sqrt(len2);
        for (int k = 0; k < 3; ++k)
            n[k] = (float)(nn[k] * inv);
    } else {
        memcpy(n, ng, 3 * sizeof(float));
    }
    if (dot3(ng, n) < 0)
        for (int k = 0; k < 3; ++k)
            ng[k] = -ng[k];
}

/* 1 when nothing of the mesh lies on the segment org + s dir, s in (0, tfar). */
static int unoccluded(const sam_truth *t, const float org[3], const float dir[3], float tfar)
{
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    struct RTCRay ray = {.org_x = org[0], .org_y = org[1], .org_z = org[2], .tnear = 0.0f,
                         .dir_x = dir[0], .dir_y = dir[1], .dir_z = dir[2], .time = 0.0f,
                         .tfar = tfar, .mask = UINT32_MAX, .id = 0, .flags = 0};
    rtcOccluded1(t->scene, &context, &ray);
    return ray.tfar >= 0.0f;
}

/* The cosine the runtime gives rho_dt (lights.glsl's n_dot_l). */
static float light_cosine(const sam_light *l, const float p[3], const float n[3])
{
    if (l->type == SAM_LIGHT_DIRECTIONAL) {
        float c = -dot3(n, l->direction);
        return c > 0 ? c : 0;
    }
    float to[3];
    if (l->type == SAM_LIGHT_AREA) {
        float c[3] = {0, 0, 0};
        for (uint32_t k = 0; k < l->vertex_count; ++k)
            for (int j = 0; j < 3; ++j)
                c[j] += l->vertices[k][j];
        for (int j = 0; j < 3; ++j)
            to[j] = c[j] / (float)l->vertex_count - p[j];
        float len = sqrtf(dot3(to, to));
        float cosine = len > 0 ? dot3(to, n) / len : 0;
        return cosine < 0 ? 0 : cosine > 1 ? 1 : cosine;
    }
    for (int j = 0; j < 3; ++j)
        to[j] = l->position[j] - p[j];
    return dot3(to, n) / sqrtf(dot3(to, to));
}

/* Visible fraction of an area light from p: area_samples points of a
 * randomly shifted lattice over the polygon's fan triangles, each ray
 * weighted by the point's unoccluded contribution. */
static float area_visibility(const sam_truth *t, const sam_light *l, const float org[3], const float p[3],
                             const float n[3], sam_rng *rng)
{
    float fan[SAM_AREA_LIGHT_MAX_VERTICES - 2], total = 0;
    uint32_t tris = l->vertex_count - 2;
    for (uint32_t k = 0; k < tris; ++k) {
        float e1[3], e2[3];
        for (int j = 0; j < 3; ++j)
            e1[j] = l->vertices[k + 1][j] - l->vertices[0][j], e2[j] = l->vertices[k + 2][j] - l->vertices[0][j];
        float c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        total += 0.5f * sqrtf(dot3(c, c));
        fan[k] = total;
    }
    float shift_u = sam_rng_float(rng), shift_v = sam_rng_float(rng);
    double weighted = 0, weight = 0;
    uint32_t visible = 0;
    for (uint32_t s = 0; s < t->area_samples; ++s) {
        float target = ((float)s + shift_u) / (float)t->area_samples * total;
        uint32_t k = 0;
        while (k + 1 < tris && fan[k] <= target)
            k++;
        float before = k ? fan[k - 1] : 0.0f, span = fan[k] - before;
        float su = span > 0 ? (target - before) / span : 0.5f;
        su = su < 0 ? 0 : su > 1 ? 1 : su;
        double sv = shift_v + (double)s * GOLDEN_FRACTION;
        float v = (float)(sv - floor(sv)), r = sqrtf(su);
        float y[3], d[3], dir[3];
        for (int j = 0; j < 3; ++j) {
            y[j] = (1 - r) * l->vertices[0][j] + r * (1 - v) * l->vertices[k + 1][j] + r * v * l->vertices[k + 2][j];
            d[j] = y[j] - p[j];
            dir[j] = y[j] - org[j];
        }
        float r2 = dot3(d, d);
        float cos_receiver = dot3(d, n), cos_light = -dot3(d, l->normal);
        if (l->two_sided)
            cos_light = fabsf(cos_light);
        float w = cos_receiver > 0 && cos_light > 0 && r2 > 0 ? cos_receiver * cos_light / (r2 * r2) : 0.0f;
        int v_ok = unoccluded(t, org, dir, 1.0f - RAY_END_SHRINK);
        visible += (uint32_t)v_ok;
        weight += w;
        weighted += v_ok ? w : 0.0;
    }
    /* Where the exact irradiance is non-zero but no point got weight (a
     * sliver of the polygon above the horizon), the plain fraction is the
     * only estimate left. */
    return weight > 0 ? (float)(weighted / weight) : (float)visible / (float)t->area_samples;
}

static float visibility(const sam_truth *t, const sam_light *l, const float org[3], const float p[3],
                        const float n[3], sam_rng *rng)
{
    float dir[3];
    switch (l->type) {
    case SAM_LIGHT_POINT:
    case SAM_LIGHT_SPOT:
        for (int j = 0; j < 3; ++j)
            dir[j] = l->position[j] - org[j];
        return (float)unoccluded(t, org, dir, 1.0f - RAY_END_SHRINK);
    case SAM_LIGHT_DIRECTIONAL:
        for (int j = 0; j < 3; ++j)
            dir[j] = -l->direction[j];
        return (float)unoccluded(t, org, dir, INFINITY);
    default:
        return area_visibility(t, l, org, p, n, rng);
    }
}

void truth_sample_at(const sam_truth *t, uint64_t i, float p[3], float n[3], float l_d[3])
{
    float ng[3];
    place(t, i, p, n, ng);
    float org[3];
    for (int j = 0; j < 3; ++j)
        org[j] = p[j] + ng[j] * t->ray_offset;
    /* One stream per sample, so its numbers do not depend on which thread
     * draws it; the offset keeps it apart from the builder's stream (0, i)
     * under the same seed. */
    sam_rng rng;
    sam_rng_seed(&rng, t->seed, 0, i + 0x5bd1e995ull);
    float sum[3] = {0, 0, 0};
    for (size_t k = 0; k < t->light_count; ++k) {
        const sam_light *l = &t->lights[k];
        float e[3];
        sam_light_irradiance(l, p, n, e);
        if (e[0] == 0 && e[1] == 0 && e[2] == 0)
            continue;
        float rho = t->rho_dt ? t->rho_dt(t->rho_dt_user, light_cosine(l, p, n)) : 1.0f;
        float v = l->shadow ? visibility(t, l, org, p, n, &rng) : 1.0f;
        for (int j = 0; j < 3; ++j)
            sum[j] += e[j] * rho * v;
    }
    if (t->has_environment) {
        float env[3];
        sam_light_sh9_irradiance((const float (*)[3])t->sh, n, env);
        for (int j = 0; j < 3; ++j)
            sum[j] += env[j] * t->environment_rho_dt;
    }
    memcpy(l_d, sum, sizeof sum);
}

sam_status truth_compute_samples(sam_truth *t, sam_error *err)
{
    const uint64_t count = t->sample_count;
    truth_sample *all = malloc(sizeof *all * count);
    if (!all)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "truth: out of memory for %llu samples",
                        (unsigned long long)count);
    const float area = (float)(t->total_area / (double)count);
    truth_progress prog = {t, "irradiance", 0, count, 0};
#pragma omp parallel for num_threads(t->threads) schedule(dynamic, 256)
    for (uint64_t i = 0; i < count; ++i) {
        truth_sample *s = &all[i];
        truth_sample_at(t, i, s->p, s->n, s->l);
        for (int j = 0; j < 3; ++j)
            s->l[j] *= area;
        truth_progress_step(&prog);
    }
    truth_progress_finish(&prog);

    /* Unlit samples add nothing to any query: drop them, keeping order. */
    uint64_t lit = 0;
    for (uint64_t i = 0; i < count; ++i)
        if (all[i].l[0] != 0 || all[i].l[1] != 0 || all[i].l[2] != 0)
            all[lit++] = all[i];
    t->lit_count = lit;
    if (lit == 0) {
        free(all);
        t->lit = NULL;
        return SAM_OK;
    }
    truth_sample *shrunk = realloc(all, sizeof *all * lit);
    t->lit = shrunk ? shrunk : all;
    return SAM_OK;
}
