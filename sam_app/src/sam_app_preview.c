/* sam_preview's job (sam_app_preview.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "sam/sam_app_preview.h"
#include "sam/sam_image.h"
#include "sam/sam_profile.h"
#include "sam/samfile.h"

typedef struct vec3 {
    float x, y, z;
} vec3;

static vec3 v3(const float *p) { return (vec3){p[0], p[1], p[2]}; }
static vec3 sub(vec3 a, vec3 b) { return (vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static float dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static vec3 cross(vec3 a, vec3 b) { return (vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
static vec3 scale(vec3 a, float s) { return (vec3){a.x * s, a.y * s, a.z * s}; }
static vec3 norm(vec3 a)
{
    float l = sqrtf(dot(a, a));
    return l > 0 ? scale(a, 1 / l) : a;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

void sam_app_preview_defaults(sam_app_preview_job *job)
{
    job->in = job->out = NULL;
    job->size = 512;
    job->axis = -1;
    job->sign = 1;
}

/* The orthographic camera and the light behind the object. */
typedef struct preview_camera {
    vec3 centre, fwd, up, right, light;
    float radius;
    int axis;
} preview_camera;

/* Camera along the thinnest bounding-box axis unless `axis` >= 0. */
static preview_camera place_camera(const samfile_data *d, int axis, int sign)
{
    preview_camera cam;
    vec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < d->vertex_count; ++v) {
        vec3 p = v3(d->positions + 3 * (size_t)v);
        lo = (vec3){fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z)};
        hi = (vec3){fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z)};
    }
    vec3 ext = sub(hi, lo);
    cam.centre = scale((vec3){lo.x + hi.x, lo.y + hi.y, lo.z + hi.z}, 0.5f);
    if (axis < 0)
        axis = ext.x <= ext.y && ext.x <= ext.z ? 0 : ext.y <= ext.z ? 1 : 2;
    float f[3] = {0, 0, 0};
    f[axis] = (float)-sign; /* the camera sits on the +axis side, looking back */
    cam.axis = axis;
    cam.fwd = v3(f);
    cam.up = axis == 1 ? (vec3){0, 0, 1} : (vec3){0, 1, 0};
    cam.right = norm(cross(cam.fwd, cam.up));
    cam.up = cross(cam.right, cam.fwd);
    cam.radius = 0.5f * sqrtf(dot(ext, ext));
    cam.light = sub(cam.centre, scale(cam.fwd, -3.0f * cam.radius)); /* behind the object */
    return cam;
}

/* L_d: irradiance from the light at each vertex, shadowed by Embree rays. */
static void irradiance(const samfile_data *d, const preview_camera *cam, float *ld)
{
    const float radius = cam->radius;
    RTCDevice device = rtcNewDevice(NULL);
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, d->positions, 0, 3 * sizeof(float),
                               d->vertex_count);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, d->triangles, 0,
                               3 * sizeof(uint32_t), d->triangle_count);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    for (uint32_t v = 0; v < d->vertex_count; ++v) {
        vec3 p = v3(d->positions + 3 * (size_t)v), nrm = v3(d->normals + 3 * (size_t)v);
        vec3 to = sub(cam->light, p);
        float dist = sqrtf(dot(to, to)), cosine = dot(nrm, to) / dist;
        ld[v] = 0;
        if (cosine <= 0)
            continue;
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        struct RTCRay ray = {.org_x = p.x, .org_y = p.y, .org_z = p.z, .tnear = 1e-4f * radius,
                             .dir_x = to.x / dist, .dir_y = to.y / dist, .dir_z = to.z / dist,
                             .tfar = dist, .mask = 0xffffffff, .flags = 0};
        rtcOccluded1(scene, &ctx, &ray);
        if (ray.tfar >= 0) /* not occluded */
            ld[v] = cosine * (radius * radius) / (dist * dist) * 4.0f;
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
}

/* The displayed colour per vertex: T(v) = sum_k L_d(b_k) K' F'_b R_d(|v_b - v|)
 * (a node's L_d moved by its tau),
 * exposed on the 95th percentile of the lit vertices (a few rim vertices
 * whose two sides nearly touch are far brighter), tonemapped x / (1 + x),
 * plus the dim grey headlight that shows the shape. */
static void shade(const samfile_data *d, const samfile_info *info, const preview_camera *cam, const float *points,
                  float *rgb, float *bright)
{
    const uint32_t nv = d->vertex_count, n = d->samples_per_vertex;
    uint32_t lit = 0;
    for (uint32_t v = 0; v < nv; ++v) {
        float t[3] = {0, 0, 0};
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t b = d->sample_index[(size_t)v * n + k];
            if (b == SAMFILE_NO_SAMPLE)
                break;
            /* A vertex or a cut map's node: position, area, L_d. */
            const float *s = points + 6 * (size_t)b;
            const float ld = fmaxf(s[4] + (d->node_count ? d->sample_tau[(size_t)v * n + k] : 0.0f) * s[5], 0.0f);
            float kv[3];
            samfile_sample_k(d, points, 6, v, k, &info->profile, info->mm_per_unit, kv);
            for (int c = 0; c < 3; ++c)
                t[c] += ld * kv[c];
        }
        memcpy(rgb + 3 * (size_t)v, t, sizeof t);
        float m = fmaxf(t[0], fmaxf(t[1], t[2]));
        if (m > 0)
            bright[lit++] = m;
    }
    float expose = 0;
    if (lit) {
        qsort(bright, lit, sizeof *bright, cmp_float);
        expose = 2.0f / bright[(size_t)(0.95 * (lit - 1))];
    }
    for (uint32_t v = 0; v < nv; ++v) {
        float head = 0.06f * fmaxf(0.0f, -dot(v3(d->normals + 3 * (size_t)v), cam->fwd));
        for (int c = 0; c < 3; ++c) {
            float x = rgb[3 * (size_t)v + c] * expose;
            rgb[3 * (size_t)v + c] = head + x / (1.0f + x);
        }
    }
}

/* Orthographic, the object filling 90% of the frame, depth-tested. */
static void rasterise(const samfile_data *d, const preview_camera *cam, const float *rgb, float *depth,
                      sam_image *img)
{
    const long size = img->width;
    for (long i = 0; i < size * size; ++i) {
        depth[i] = INFINITY;
        img->pixels[3 * i] = img->pixels[3 * i + 1] = img->pixels[3 * i + 2] = 0.01f;
    }
    float pix = (float)size / (2.0f * cam->radius * 1.05f);
    for (uint32_t f = 0; f < d->triangle_count; ++f) {
        float sx[3], sy[3], sz[3];
        for (int c = 0; c < 3; ++c) {
            vec3 p = sub(v3(d->positions + 3 * (size_t)d->triangles[3 * f + c]), cam->centre);
            sx[c] = 0.5f * size + dot(p, cam->right) * pix;
            sy[c] = 0.5f * size - dot(p, cam->up) * pix;
            sz[c] = dot(p, cam->fwd);
        }
        float area = (sx[1] - sx[0]) * (sy[2] - sy[0]) - (sx[2] - sx[0]) * (sy[1] - sy[0]);
        if (fabsf(area) < 1e-12f)
            continue;
        int x0 = (int)fmaxf(0, floorf(fminf(sx[0], fminf(sx[1], sx[2]))));
        int x1 = (int)fminf((float)size - 1, ceilf(fmaxf(sx[0], fmaxf(sx[1], sx[2]))));
        int y0 = (int)fmaxf(0, floorf(fminf(sy[0], fminf(sy[1], sy[2]))));
        int y1 = (int)fminf((float)size - 1, ceilf(fmaxf(sy[0], fmaxf(sy[1], sy[2]))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                float px = x + 0.5f, py = y + 0.5f;
                float w0 = ((sx[1] - px) * (sy[2] - py) - (sx[2] - px) * (sy[1] - py)) / area;
                float w1 = ((sx[2] - px) * (sy[0] - py) - (sx[0] - px) * (sy[2] - py)) / area;
                float w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0)
                    continue;
                float z = w0 * sz[0] + w1 * sz[1] + w2 * sz[2];
                size_t at = (size_t)y * size + x;
                if (z >= depth[at])
                    continue;
                depth[at] = z;
                for (int c = 0; c < 3; ++c)
                    img->pixels[3 * at + c] = w0 * rgb[3 * (size_t)d->triangles[3 * f] + c] +
                                              w1 * rgb[3 * (size_t)d->triangles[3 * f + 1] + c] +
                                              w2 * rgb[3 * (size_t)d->triangles[3 * f + 2] + c];
            }
    }
}

sam_status sam_app_preview_write(const sam_app_preview_job *job, const char *tool, sam_error *err)
{
    if (!job->in || !job->out || job->size < 16 || job->size > 4096 || job->axis < -1 || job->axis > 2)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "preview: no input or output, or size %ld / axis %d out of range",
                        job->size, job->axis);
    samfile_data d;
    sam_status st = samfile_read(job->in, &d, err);
    if (st != SAM_OK)
        return st;
    /* The material and scale the map was built with. */
    samfile_info info;
    st = samfile_info_read(&d, job->in, &info, err);
    if (st == SAM_OK && !info.has_material)
        st = sam_fail(err, SAM_ERR_FORMAT, "%s: INFO has no material", job->in);
    const size_t nv = d.vertex_count, side = (size_t)job->size;
    float *ld = malloc(nv * sizeof *ld), *rgb = malloc(nv * 3 * sizeof *rgb), *bright = malloc(nv * sizeof *bright);
    float *depth = malloc(side * side * sizeof *depth);
    /* Every sample's position, area and L_d (samfile_sample_points). */
    float *points = malloc((nv + d.node_count) * 6 * sizeof *points);
    sam_image img = {0};
    if (st == SAM_OK && (!ld || !rgb || !bright || !depth || !points))
        st = sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "preview: out of memory for %zu vertices", nv);
    if (st == SAM_OK)
        st = sam_image_create(&img, (uint32_t)side, (uint32_t)side, 3, err);
    preview_camera cam = place_camera(&d, job->axis, job->sign);
    if (st == SAM_OK) {
        irradiance(&d, &cam, ld);
        samfile_sample_points(&d, ld, 1, points, NULL);
        shade(&d, &info, &cam, points, rgb, bright);
        rasterise(&d, &cam, rgb, depth, &img);
        st = sam_image_write_png(job->out, &img, SAM_PNG_SRGB, err);
    }
    if (st == SAM_OK)
        fprintf(stderr, "%s: wrote %s (%s, back-lit, view along %s%c)\n", tool, job->out, info.profile.name,
                job->sign < 0 ? "-" : "+", "xyz"[cam.axis]);
    sam_image_destroy(&img);
    free(depth);
    free(points);
    free(bright);
    free(ld);
    free(rgb);
    samfile_free(&d);
    return st;
}
