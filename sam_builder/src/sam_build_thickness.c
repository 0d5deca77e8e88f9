/* Per-vertex local thickness by inverted-normal ray casting
 * (sam_thickness.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>
#include <omp.h>

#include "sam/sam_thickness.h"

#define PI 3.14159265358979323846
/* Vertices between two progress reports (and cancellation checks). */
#define BLOCK 4096
#define GOLDEN_FRACTION 0.61803398874989484820

void sam_thickness_default_settings(sam_thickness_settings *s)
{
    s->strata = 8;
    s->statistic = SAM_THICKNESS_MEAN;
    s->offset = 1e-4f;
    s->threads = 0;
}

void sam_thickness_directions(uint32_t strata, float *xyz)
{
    if (strata < 1 || strata > SAM_THICKNESS_MAX_STRATA)
        return;
    /* Cosine-weighted directions have sin^2 theta uniform in [0, 1]: the
     * rings sit at the midpoints of equal-probability bands. */
    for (uint32_t i = 0; i < strata; ++i) {
        double sin2 = (i + 0.5) / strata, s = sqrt(sin2), z = sqrt(1.0 - sin2);
        /* Each ring turned by the golden fraction of a step more than the
         * last: no spoke lines up with another ring's, nor with the axes of
         * a vertex's frame, along which a grid mesh's edges run. */
        double turn = fmod(0.5 + i * GOLDEN_FRACTION, 1.0);
        for (uint32_t j = 0; j < strata; ++j) {
            double phi = 2.0 * PI * (j + turn) / strata;
            float *d = xyz + 3 * ((size_t)i * strata + j);
            d[0] = (float)(s * cos(phi));
            d[1] = (float)(s * sin(phi));
            d[2] = (float)z;
        }
    }
}

static void embree_error(void *user, enum RTCError code, const char *str)
{
    char *msg = user;
    if (!msg[0])
        snprintf(msg, 256, "Embree error %d: %s", (int)code, str ? str : "");
}

/* The first problem of `surface` and the settings, or SAM_OK; the bounding
 * box's diagonal into `*diagonal`. */
static sam_status check_input(const sam_thickness_surface *s, float mm_per_unit, const sam_thickness_settings *set,
                              float *diagonal, sam_error *err)
{
    if (!s || !s->positions || !s->normals || !s->triangles || !s->vertex_count || !s->triangle_count)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "thickness: the surface needs vertices, normals and triangles (got %u vertices, %u triangles)",
                        s ? s->vertex_count : 0, s ? s->triangle_count : 0);
    if (!(mm_per_unit > 0) || !isfinite(mm_per_unit))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: mm_per_unit must be finite and > 0, got %g",
                        (double)mm_per_unit);
    if (set->strata < 1 || set->strata > SAM_THICKNESS_MAX_STRATA)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: strata must be in 1..%d, got %u",
                        SAM_THICKNESS_MAX_STRATA, set->strata);
    if (!(set->offset > 0 && set->offset <= 0.01f))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: offset must be in (0, 0.01], got %g",
                        (double)set->offset);
    if (set->statistic != SAM_THICKNESS_MEAN && set->statistic != SAM_THICKNESS_THROUGH)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: statistic must be mean (0) or through (1), got %d",
                        (int)set->statistic);
    if (set->threads < 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: threads must be >= 0, got %d", set->threads);
    for (uint32_t t = 0; t < 3 * s->triangle_count; ++t)
        if (s->triangles[t] >= s->vertex_count)
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "thickness: triangle %u names vertex %u; there are %u vertices", t / 3, s->triangles[t],
                            s->vertex_count);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < s->vertex_count; ++v) {
        const float *p = s->positions + 3 * (size_t)v, *n = s->normals + 3 * (size_t)v;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: vertex %u's position (%g, %g, %g) is not finite",
                            v, (double)p[0], (double)p[1], (double)p[2]);
        float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if (!(len2 > 0) || !isfinite(len2))
            return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                            "thickness: vertex %u's normal (%g, %g, %g) has no direction", v, (double)n[0],
                            (double)n[1], (double)n[2]);
        for (int c = 0; c < 3; ++c) {
            lo[c] = fminf(lo[c], p[c]);
            hi[c] = fmaxf(hi[c], p[c]);
        }
    }
    *diagonal = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(*diagonal > 0))
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: every vertex lies at one point; nothing to measure");
    return SAM_OK;
}

/* Embree's scene of the triangles, in Embree's own buffers: it reads vertex
 * buffers 16 bytes at a time, past the end of a packed caller array. */
static sam_status make_scene(RTCDevice device, const sam_thickness_surface *s, const char *msg, RTCScene *out,
                             sam_error *err)
{
    RTCScene scene = rtcNewScene(device);
    /* Watertight: a ray through a shared edge must not slip out between
     * its two triangles and take the cap. */
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                        s->vertex_count);
    uint32_t *ib = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                           s->triangle_count);
    if (vb && ib) {
        memcpy(vb, s->positions, 3 * sizeof(float) * s->vertex_count);
        memcpy(ib, s->triangles, 3 * sizeof(uint32_t) * s->triangle_count);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    enum RTCError code = rtcGetDeviceError(device);
    if (code != RTC_ERROR_NONE || !vb || !ib || msg[0]) {
        rtcReleaseScene(scene);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "thickness: building the ray-tracing scene failed (error %d%s%s)",
                        (int)code, msg[0] ? "; " : "", msg);
    }
    *out = scene;
    return SAM_OK;
}

/* What one vertex's rays share. */
typedef struct ray_set {
    RTCScene scene;
    const float *dirs; /* count unit vectors, +z the inverted normal */
    uint32_t count, strata; /* count = strata^2, ring by ring from -n */
    int through;            /* SAM_THICKNESS_THROUGH */
    float offset, cap; /* model units */
} ray_set;

/* The depth of the far surface below vertex p's tangent plane, model
 * units: the mean, or straight through (sam_thickness_statistic). */
static double vertex_depth(const ray_set *rs, const float *p, const float *normal)
{
    float len = sqrtf(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    float m[3] = {-normal[0] / len, -normal[1] / len, -normal[2] / len};
    /* Duff et al.'s branchless basis around m: continuous in m except
     * across m.z = 0, and a fixed function of it, so seam copies of a
     * vertex cast the same rays. */
    float sign = copysignf(1.0f, m[2]), a = -1.0f / (sign + m[2]), b = m[0] * m[1] * a;
    float t[3] = {1.0f + sign * m[0] * m[0] * a, sign * b, -sign * m[0]};
    float u[3] = {b, sign + m[1] * m[1] * a, -m[1]};
    float o[3] = {p[0] + rs->offset * m[0], p[1] + rs->offset * m[1], p[2] + rs->offset * m[2]};
    double sum = 0, through = 0;
    uint32_t through_count = 0;
    for (uint32_t k = 0; k < rs->count; ++k) {
        const float *d = rs->dirs + 3 * (size_t)k;
        struct RTCRayHit rh;
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = o[0], rh.ray.org_y = o[1], rh.ray.org_z = o[2];
        rh.ray.dir_x = d[0] * t[0] + d[1] * u[0] + d[2] * m[0];
        rh.ray.dir_y = d[0] * t[1] + d[1] * u[1] + d[2] * m[1];
        rh.ray.dir_z = d[0] * t[2] + d[1] * u[2] + d[2] * m[2];
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = rs->cap;
        rh.ray.mask = UINT32_MAX;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcIntersect1(rs->scene, &ctx, &rh);
        float dist = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : rs->cap;
        const double depth = (double)rs->offset + (double)dist * d[2];
        sum += depth;
        if (d[2] * d[2] >= 0.75f || k < rs->strata) {
            through += depth;
            through_count++;
        }
    }
    return rs->through ? through / through_count : sum / rs->count;
}

sam_status sam_thickness_compute(const sam_thickness_surface *surface, float mm_per_unit,
                                 const sam_thickness_settings *settings, sam_thickness_progress_fn progress,
                                 void *user, float *thickness_mm, sam_error *err)
{
    sam_thickness_settings set;
    if (settings)
        set = *settings;
    else
        sam_thickness_default_settings(&set);
    float diagonal = 0;
    sam_status st = check_input(surface, mm_per_unit, &set, &diagonal, err);
    if (st != SAM_OK)
        return st;
    if (!thickness_mm)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: no output array");
    ray_set rs = {NULL, NULL, set.strata * set.strata, set.strata, set.statistic == SAM_THICKNESS_THROUGH,
                  set.offset * diagonal, diagonal};
    float *dirs = malloc((size_t)rs.count * 3 * sizeof *dirs);
    if (!dirs)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "thickness: out of memory for %u ray directions", rs.count);
    sam_thickness_directions(set.strata, dirs);
    rs.dirs = dirs;
    char msg[256] = "";
    RTCDevice device = rtcNewDevice(NULL);
    if (!device) {
        free(dirs);
        return sam_fail(err, SAM_ERR_UNSUPPORTED, "thickness: Embree could not create a device (error %d)",
                        (int)rtcGetDeviceError(NULL));
    }
    rtcSetDeviceErrorFunction(device, embree_error, msg);
    if ((st = make_scene(device, surface, msg, &rs.scene, err)) == SAM_OK) {
        const int threads = set.threads > 0 ? set.threads : omp_get_max_threads();
        const uint32_t n = surface->vertex_count;
        /* Blocks, so progress and cancellation come from this thread
         * while the vertices of a block run on all of them. */
        for (uint32_t start = 0; start < n && st == SAM_OK; start += BLOCK) {
            const long end = (long)(n - start < BLOCK ? n : start + BLOCK);
#pragma omp parallel for num_threads(threads) schedule(dynamic, 64)
            for (long v = (long)start; v < end; ++v)
                thickness_mm[v] = (float)(mm_per_unit * vertex_depth(&rs, surface->positions + 3 * (size_t)v,
                                                                      surface->normals + 3 * (size_t)v));
            if (progress && progress(user, (uint64_t)end, n))
                st = sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "thickness: cancelled");
        }
        rtcReleaseScene(rs.scene);
    }
    rtcReleaseDevice(device);
    free(dirs);
    return st;
}
