/*
 * sam_preview: a CPU picture of what a .sam holds, before the GPU runtime
 * exists or where there is no GPU. One point light shines on the object
 * from behind (from the side facing away from the camera); L_d at every
 * vertex comes from that light with exact visibility (Embree shadow rays);
 * the translucency T(v) = sum_k L_d(b_k) K_k (SAM eq. 12, K from K' by
 * eq. 15) is what glows through thin parts. The surface gets a dim
 * headlight so its shape stays readable. Rasterised with a z-buffer,
 * colours interpolated per vertex, written as an sRGB PNG.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "sam/sam_image.h"
#include "sam/sam_profile.h"
#include "sam/samfile.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: sam_preview FILE.sam -o OUT.png [--size N] [--view x|y|z|-x|-y|-z]\n"
            "\n"
            "Renders the translucency a .sam encodes, on the CPU: a point light behind the\n"
            "object (with Embree shadows), the light carried through by the stored back-side\n"
            "samples (SAM eq. 12) in colour, the surface dimly lit from the camera in grey.\n"
            "  -o OUT.png   output (sRGB PNG, written atomically)\n"
            "  --size N     image height and width in pixels, 16..4096 (default 512)\n"
            "  --view AXIS  the camera looks along AXIS; default: along the object's thinnest\n"
            "               extent, so the light shines through it towards the camera\n");
}

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

static int fail(const char *msg)
{
    fprintf(stderr, "sam_preview: %s\n", msg);
    return 1;
}

int main(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    long size = 512;
    int axis = -1, sign = 1;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "-o") && i + 1 < argc) {
            out = argv[++i];
        } else if (!strcmp(argv[i], "--size") && i + 1 < argc) {
            char *end;
            size = strtol(argv[++i], &end, 10);
            if (*end || size < 16 || size > 4096) {
                fprintf(stderr, "sam_preview: --size must be an integer in 16..4096, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(argv[i], "--view") && i + 1 < argc) {
            const char *a = argv[++i];
            sign = a[0] == '-' ? -1 : 1;
            a += a[0] == '-';
            axis = !strcmp(a, "x") ? 0 : !strcmp(a, "y") ? 1 : !strcmp(a, "z") ? 2 : -2;
            if (axis == -2) {
                fprintf(stderr, "sam_preview: --view must be x, y, z, -x, -y or -z, got \"%s\"\n", argv[i]);
                return 2;
            }
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "sam_preview: unknown or incomplete option \"%s\" (see --help)\n", argv[i]);
            return 2;
        } else if (!in) {
            in = argv[i];
        } else {
            fprintf(stderr, "sam_preview: unexpected argument \"%s\"\n", argv[i]);
            return 2;
        }
    }
    if (!in || !out) {
        usage(stderr);
        return 2;
    }
    samfile_data d;
    sam_error err;
    if (samfile_read(in, &d, &err) != SAM_OK)
        return fail(err.message);
    /* The material and scale the map was built with. */
    samfile_info info;
    sam_status st = samfile_info_read(&d, in, &info, &err);
    if (st == SAM_OK && !info.has_material)
        st = sam_fail(&err, SAM_ERR_FORMAT, "%s: INFO has no material", in);
    if (st != SAM_OK) {
        samfile_free(&d);
        return fail(err.message);
    }
    const sam_profile profile = info.profile;
    const float mm_per_unit = info.mm_per_unit;
    const uint32_t nv = d.vertex_count, nt = d.triangle_count, n = d.samples_per_vertex;

    /* Camera along the thinnest bounding-box axis unless told otherwise. */
    vec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < nv; ++v) {
        vec3 p = v3(d.positions + 3 * (size_t)v);
        lo = (vec3){fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z)};
        hi = (vec3){fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z)};
    }
    vec3 ext = sub(hi, lo), centre = scale((vec3){lo.x + hi.x, lo.y + hi.y, lo.z + hi.z}, 0.5f);
    if (axis < 0)
        axis = ext.x <= ext.y && ext.x <= ext.z ? 0 : ext.y <= ext.z ? 1 : 2;
    float f[3] = {0, 0, 0};
    f[axis] = (float)-sign; /* the camera sits on the +axis side, looking back */
    vec3 fwd = v3(f);
    vec3 up = axis == 1 ? (vec3){0, 0, 1} : (vec3){0, 1, 0};
    vec3 right = norm(cross(fwd, up));
    up = cross(right, fwd);
    float radius = 0.5f * sqrtf(dot(ext, ext));
    vec3 light = sub(centre, scale(fwd, -3.0f * radius)); /* behind the object */

    /* L_d: irradiance from the light at each vertex, shadowed. */
    float *ld = malloc((size_t)nv * sizeof *ld);
    float *rgb = malloc((size_t)nv * 3 * sizeof *rgb);
    if (!ld || !rgb) {
        free(ld);
        free(rgb);
        samfile_free(&d);
        return fail("out of memory");
    }
    RTCDevice device = rtcNewDevice(NULL);
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, d.positions, 0, 3 * sizeof(float),
                               nv);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, d.triangles, 0,
                               3 * sizeof(uint32_t), nt);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    for (uint32_t v = 0; v < nv; ++v) {
        vec3 p = v3(d.positions + 3 * (size_t)v), nrm = v3(d.normals + 3 * (size_t)v);
        vec3 to = sub(light, p);
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
    /* T(v) = sum_k L_d(b_k) K' F'_b R_d(|v_b - v|) */
    float *bright = malloc((size_t)nv * sizeof *bright);
    uint32_t lit = 0;
    for (uint32_t v = 0; v < nv; ++v) {
        float t[3] = {0, 0, 0};
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t b = d.sample_index[(size_t)v * n + k];
            if (b == SAMFILE_NO_SAMPLE)
                break;
            vec3 dv = sub(v3(d.positions + 3 * (size_t)b), v3(d.positions + 3 * (size_t)v));
            float rd[3];
            sam_profile_eval(&profile, mm_per_unit * sqrtf(dot(dv, dv)), rd);
            for (int c = 0; c < 3; ++c)
                t[c] += ld[b] * d.sample_kprime[3 * ((size_t)v * n + k) + c] * d.fan_area[b] * rd[c];
        }
        memcpy(rgb + 3 * (size_t)v, t, sizeof t);
        float m = fmaxf(t[0], fmaxf(t[1], t[2]));
        if (bright && m > 0)
            bright[lit++] = m;
    }
    /* Expose on the 95th percentile of the lit vertices (a few rim vertices
     * whose two sides nearly touch are far brighter), tonemap x / (1 + x),
     * and add the dim grey headlight that shows the shape. */
    float expose = 0;
    if (lit) {
        qsort(bright, lit, sizeof *bright, cmp_float);
        expose = 2.0f / bright[(size_t)(0.95 * (lit - 1))];
    }
    free(bright);
    for (uint32_t v = 0; v < nv; ++v) {
        float head = 0.06f * fmaxf(0.0f, -dot(v3(d.normals + 3 * (size_t)v), fwd));
        for (int c = 0; c < 3; ++c) {
            float x = rgb[3 * (size_t)v + c] * expose;
            rgb[3 * (size_t)v + c] = head + x / (1.0f + x);
        }
    }

    /* Rasterise: orthographic, the object filling 90% of the frame. */
    sam_image img;
    if (sam_image_create(&img, (uint32_t)size, (uint32_t)size, 3, &err) != SAM_OK) {
        free(ld);
        free(rgb);
        samfile_free(&d);
        return fail(err.message);
    }
    float *depth = malloc((size_t)size * size * sizeof *depth);
    for (long i = 0; i < size * size; ++i) {
        depth[i] = INFINITY;
        img.pixels[3 * i] = img.pixels[3 * i + 1] = img.pixels[3 * i + 2] = 0.01f;
    }
    float pix = (float)size / (2.0f * radius * 1.05f);
    for (uint32_t f = 0; f < nt; ++f) {
        float sx[3], sy[3], sz[3];
        for (int c = 0; c < 3; ++c) {
            vec3 p = sub(v3(d.positions + 3 * (size_t)d.triangles[3 * f + c]), centre);
            sx[c] = 0.5f * size + dot(p, right) * pix;
            sy[c] = 0.5f * size - dot(p, up) * pix;
            sz[c] = dot(p, fwd);
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
                    img.pixels[3 * at + c] = w0 * rgb[3 * (size_t)d.triangles[3 * f] + c] +
                                             w1 * rgb[3 * (size_t)d.triangles[3 * f + 1] + c] +
                                             w2 * rgb[3 * (size_t)d.triangles[3 * f + 2] + c];
            }
    }
    st = sam_image_write_png(out, &img, SAM_PNG_SRGB, &err);
    sam_image_destroy(&img);
    free(depth);
    free(ld);
    free(rgb);
    samfile_free(&d);
    if (st != SAM_OK)
        return fail(err.message);
    fprintf(stderr, "sam_preview: wrote %s (%s, back-lit, view along %s%c)\n", out, profile.name,
            sign < 0 ? "-" : "+", "xyz"[axis]);
    return 0;
}
