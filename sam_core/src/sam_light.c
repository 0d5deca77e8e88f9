#include "sam/sam_light.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI_D 3.14159265358979323846

/* ------------------------------------------------------------------------ */
/* Lat-long mapping and SH basis                                             */

void sam_light_latlong_direction(float u, float v, float dir[3])
{
    double phi = 2.0 * PI_D * u, theta = PI_D * v;
    double s = sin(theta);
    dir[0] = (float)(s * sin(phi));
    dir[1] = (float)cos(theta);
    dir[2] = (float)(s * cos(phi));
}

void sam_light_latlong_from_direction(const float dir[3], float *u, float *v)
{
    double phi = atan2((double)dir[0], (double)dir[2]);
    if (phi < 0)
        phi += 2.0 * PI_D;
    double y = dir[1] < -1.0f ? -1.0 : dir[1] > 1.0f ? 1.0 : dir[1];
    float uu = (float)(phi / (2.0 * PI_D));
    /* phi just below 2 pi can round to u = 1 in float. */
    *u = uu < 1.0f ? uu : 0.0f;
    *v = (float)(acos(y) / PI_D);
}

void sam_light_sh9_basis(const float dir[3], float y[9])
{
    float x = dir[0], yy = dir[1], z = dir[2];
    y[0] = SAM_SH_C0;
    y[1] = SAM_SH_C1 * yy;
    y[2] = SAM_SH_C1 * z;
    y[3] = SAM_SH_C1 * x;
    y[4] = SAM_SH_C2 * x * yy;
    y[5] = SAM_SH_C2 * yy * z;
    y[6] = SAM_SH_C3 * (3.0f * z * z - 1.0f);
    y[7] = SAM_SH_C2 * x * z;
    y[8] = SAM_SH_C4 * (x * x - yy * yy);
}

/* ------------------------------------------------------------------------ */
/* SH projection                                                             */

/*
 * With x = sin t sin f, y = cos t, z = sin t cos f and dw = sin t dt df, the
 * integral of every monomial of degree <= 2 over a texel [t0,t1] x [f0,f1]
 * factors into a theta integral times a phi integral. These are the
 * antiderivatives' differences, in double because they cancel.
 */
enum { TH_1, TH_S, TH_Y, TH_SY, TH_SS, TH_YY, TH_COUNT };   /* times sin t dt */
enum { PH_1, PH_S, PH_C, PH_SS, PH_CC, PH_SC, PH_COUNT };   /* df */

static void theta_integrals(double t0, double t1, double out[TH_COUNT])
{
    double c0 = cos(t0), c1 = cos(t1), s0 = sin(t0), s1 = sin(t1);
    out[TH_1] = c0 - c1;                                           /* sin t */
    out[TH_S] = (t1 - t0) / 2 - (sin(2 * t1) - sin(2 * t0)) / 4;   /* sin^2 t */
    out[TH_Y] = (c0 * c0 - c1 * c1) / 2;                           /* cos t sin t */
    out[TH_SY] = (s1 * s1 * s1 - s0 * s0 * s0) / 3;                /* sin^2 t cos t */
    out[TH_YY] = (c0 * c0 * c0 - c1 * c1 * c1) / 3;                /* cos^2 t sin t */
    out[TH_SS] = out[TH_1] - out[TH_YY];                           /* sin^3 t */
}

static void phi_integrals(double f0, double f1, double out[PH_COUNT])
{
    double s0 = sin(f0), s1 = sin(f1);
    out[PH_1] = f1 - f0;
    out[PH_S] = cos(f0) - cos(f1);
    out[PH_C] = s1 - s0;
    out[PH_SS] = (f1 - f0) / 2 - (sin(2 * f1) - sin(2 * f0)) / 4;
    out[PH_CC] = out[PH_1] - out[PH_SS];
    out[PH_SC] = (s1 * s1 - s0 * s0) / 2;
}

sam_status sam_light_sh9_from_latlong(const sam_image *env, float rotation_deg, float intensity,
                                      float sh[9][3], sam_error *err)
{
    if (sh)
        memset(sh, 0, 9 * sizeof sh[0]);
    if (!env || !sh)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "sh9_from_latlong: %s is NULL",
                        !env ? "env" : "sh");
    if (env->width == 0 || env->height == 0 || !env->pixels ||
        (env->channels != 3 && env->channels != 4) ||
        (uint64_t)env->width * env->height > SAM_IMAGE_MAX_PIXELS)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "sh9_from_latlong: invalid environment image %ux%u with %u channels%s",
                        env->width, env->height, env->channels, env->pixels ? "" : " and no pixels");
    if (!isfinite(rotation_deg) || !isfinite(intensity) || intensity < 0)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "sh9_from_latlong: rotation %g must be finite and intensity %g finite "
                        "and >= 0",
                        rotation_deg, intensity);

    const uint32_t w = env->width, h = env->height, nc = env->channels;
    double *phi = malloc((size_t)w * PH_COUNT * sizeof *phi);
    if (!phi)
        return sam_fail(err, SAM_ERR_OUT_OF_MEMORY, "sh9_from_latlong: out of memory for %u columns",
                        w);
    /* Rotating the environment adds alpha to every texel's phi (header). */
    double alpha = fmod((double)rotation_deg, 360.0) * PI_D / 180.0;
    for (uint32_t col = 0; col < w; ++col)
        phi_integrals(2 * PI_D * col / w + alpha, 2 * PI_D * (col + 1) / w + alpha,
                      phi + (size_t)col * PH_COUNT);

    /* Monomial integrals of L: 1, x, y, z, xy, yz, xz, x^2, y^2, z^2. */
    enum { M1, MX, MY, MZ, MXY, MYZ, MXZ, MXX, MYY, MZZ, M_COUNT };
    double mono[M_COUNT][3] = {{0}};
    for (uint32_t row = 0; row < h; ++row) {
        double th[TH_COUNT];
        theta_integrals(PI_D * row / h, PI_D * (row + 1) / h, th);
        double rowsum[PH_COUNT][3] = {{0}};
        const float *px = env->pixels + (size_t)row * w * nc;
        for (uint32_t col = 0; col < w; ++col, px += nc) {
            const double *f = phi + (size_t)col * PH_COUNT;
            for (int c = 0; c < 3; ++c) {
                if (!isfinite(px[c])) {
                    free(phi);
                    memset(sh, 0, 9 * sizeof sh[0]);
                    return sam_fail(err, SAM_ERR_FORMAT,
                                    "sh9_from_latlong: environment texel (column %u, row %u) "
                                    "channel %d is %g: expected a finite value",
                                    col, row, c, px[c]);
                }
                for (int k = 0; k < PH_COUNT; ++k)
                    rowsum[k][c] += px[c] * f[k];
            }
        }
        for (int c = 0; c < 3; ++c) {
            mono[M1][c] += th[TH_1] * rowsum[PH_1][c];
            mono[MX][c] += th[TH_S] * rowsum[PH_S][c];
            mono[MY][c] += th[TH_Y] * rowsum[PH_1][c];
            mono[MZ][c] += th[TH_S] * rowsum[PH_C][c];
            mono[MXY][c] += th[TH_SY] * rowsum[PH_S][c];
            mono[MYZ][c] += th[TH_SY] * rowsum[PH_C][c];
            mono[MXZ][c] += th[TH_SS] * rowsum[PH_SC][c];
            mono[MXX][c] += th[TH_SS] * rowsum[PH_SS][c];
            mono[MYY][c] += th[TH_YY] * rowsum[PH_1][c];
            mono[MZZ][c] += th[TH_SS] * rowsum[PH_CC][c];
        }
    }
    free(phi);
    for (int c = 0; c < 3; ++c) {
        double (*m)[3] = mono;
        double k[9] = {
            SAM_SH_C0 * m[M1][c],
            SAM_SH_C1 * m[MY][c],
            SAM_SH_C1 * m[MZ][c],
            SAM_SH_C1 * m[MX][c],
            SAM_SH_C2 * m[MXY][c],
            SAM_SH_C2 * m[MYZ][c],
            SAM_SH_C3 * (3 * m[MZZ][c] - m[M1][c]),
            SAM_SH_C2 * m[MXZ][c],
            SAM_SH_C4 * (m[MXX][c] - m[MYY][c]),
        };
        for (int i = 0; i < 9; ++i)
            sh[i][c] = (float)(intensity * k[i]);
    }
    return SAM_OK;
}

void sam_light_sh9_irradiance(const float sh[9][3], const float n[3], float out[3])
{
    static const float band[9] = {
        (float)PI_D,
        (float)(2 * PI_D / 3), (float)(2 * PI_D / 3), (float)(2 * PI_D / 3),
        (float)(PI_D / 4), (float)(PI_D / 4), (float)(PI_D / 4), (float)(PI_D / 4), (float)(PI_D / 4),
    };
    float y[9];
    sam_light_sh9_basis(n, y);
    for (int c = 0; c < 3; ++c) {
        float e = 0;
        for (int k = 0; k < 9; ++k)
            e += band[k] * sh[k][c] * y[k];
        out[c] = e > 0 ? e : 0;
    }
}

/* ------------------------------------------------------------------------ */
/* Procedural skies                                                          */

static double smoothstep_d(double e0, double e1, double x)
{
    double t = (x - e0) / (e1 - e0);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return t * t * (3 - 2 * t);
}

static double mix_d(double a, double b, double t)
{
    return a + (b - a) * t;
}

static void dir_from_angles(double elevation_deg, double azimuth_deg, double d[3])
{
    double e = elevation_deg * PI_D / 180, a = azimuth_deg * PI_D / 180;
    d[0] = cos(e) * sin(a);
    d[1] = sin(e);
    d[2] = cos(e) * cos(a);
}

static double dot3d(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A soft-edged rectangle in angles, as seen from the centre of the environment. */
typedef struct light_box {
    double centre[3], across[3], up[3]; /* orthonormal: across is horizontal */
    double half_across, half_up;        /* half extents, radians */
    double radiance[3];
} light_box;

static light_box make_box(double elevation_deg, double azimuth_deg, double width_deg,
                          double height_deg, double r, double g, double b)
{
    light_box box;
    double e = elevation_deg * PI_D / 180, a = azimuth_deg * PI_D / 180;
    dir_from_angles(elevation_deg, azimuth_deg, box.centre);
    /* d/d(azimuth) and d/d(elevation) of the centre, normalised. */
    box.across[0] = cos(a);
    box.across[1] = 0;
    box.across[2] = -sin(a);
    box.up[0] = -sin(e) * sin(a);
    box.up[1] = cos(e);
    box.up[2] = -sin(e) * cos(a);
    box.half_across = width_deg * PI_D / 360;
    box.half_up = height_deg * PI_D / 360;
    box.radiance[0] = r;
    box.radiance[1] = g;
    box.radiance[2] = b;
    return box;
}

static double box_weight(const light_box *box, const double d[3])
{
    static const double soft = 1.5 * PI_D / 180; /* half the 3-degree edge */
    double f = dot3d(d, box->centre);
    if (f <= 0)
        return 0;
    double a = fabs(atan2(dot3d(d, box->across), f)), b = fabs(atan2(dot3d(d, box->up), f));
    return (1 - smoothstep_d(box->half_across - soft, box->half_across + soft, a)) *
           (1 - smoothstep_d(box->half_up - soft, box->half_up + soft, b));
}

static void studio_radiance(const light_box boxes[3], const double d[3], double out[3])
{
    double floor = 0.04 + 0.04 * (1 + (d[1] < 0 ? d[1] : 0));
    double wall = 0.10 + 0.15 * (d[1] > 0 ? d[1] : 0);
    /* The cyclorama meets the floor in a soft band, not a hard seam. */
    double base = mix_d(floor, wall, smoothstep_d(-0.03, 0.03, d[1]));
    for (int c = 0; c < 3; ++c)
        out[c] = base;
    for (int i = 0; i < 3; ++i) {
        double wgt = box_weight(&boxes[i], d);
        for (int c = 0; c < 3; ++c)
            out[c] += wgt * boxes[i].radiance[c];
    }
}

#define SUN_ELEVATION_DEG 40.0
#define SUN_AZIMUTH_DEG 120.0
#define SUN_RADIUS_DEG 1.5
#define SUN_RADIANCE 5000.0
/* Subsamples per texel side: at most 1/8 of the sun's radius apart, from
 * 4 x 4 up to 64 x 64. */
#define SUN_MIN_SUBSAMPLES 4
#define SUN_MAX_SUBSAMPLES 64

/* Sky and ground without the sun disk (the aureole included). */
static void outdoor_radiance(const double sun[3], const double d[3], double out[3])
{
    static const double zenith[3] = {0.15, 0.30, 0.75}, haze[3] = {0.90, 0.95, 1.00};
    static const double ground[3] = {0.08, 0.075, 0.06}, ground_haze[3] = {0.30, 0.30, 0.30};
    double up = d[1] > 0 ? d[1] : 0, down = d[1] < 0 ? -d[1] : 0;
    double t_sky = sqrt(up), t_ground = exp(-25 * down);
    double blend = smoothstep_d(-0.015, 0.015, d[1]);
    double cosang = dot3d(d, sun);
    double angle = acos(cosang > 1 ? 1 : cosang < -1 ? -1 : cosang);
    double aureole = 3.0 * exp(-angle / 0.08) * blend;
    for (int c = 0; c < 3; ++c) {
        double sky = mix_d(haze[c], zenith[c], t_sky);
        double gnd = mix_d(ground[c], ground_haze[c], t_ground);
        out[c] = mix_d(gnd, sky, blend) + aureole;
    }
}

/* Fraction of the texel [t0,t1] x [f0,f1] covered by the sun disk, from
 * subsamples uniform in cos(theta) and phi (equal solid angles). */
static double sun_coverage(const double sun[3], double cos_radius, int subsamples, double t0,
                           double t1, double f0, double f1)
{
    double c0 = cos(t0), c1 = cos(t1);
    int inside = 0;
    for (int i = 0; i < subsamples; ++i) {
        double ct = mix_d(c0, c1, (i + 0.5) / subsamples);
        double st = sqrt(1 - ct * ct > 0 ? 1 - ct * ct : 0);
        for (int j = 0; j < subsamples; ++j) {
            double f = mix_d(f0, f1, (j + 0.5) / subsamples);
            double d[3] = {st * sin(f), ct, st * cos(f)};
            inside += dot3d(d, sun) >= cos_radius;
        }
    }
    return (double)inside / ((double)subsamples * subsamples);
}

sam_status sam_light_make_sky(uint32_t width, uint32_t height, int kind, sam_image *out,
                              sam_error *err)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (!out)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT, "make_sky: out is NULL");
    if (kind != SAM_SKY_STUDIO && kind != SAM_SKY_OUTDOOR)
        return sam_fail(err, SAM_ERR_INVALID_ARGUMENT,
                        "make_sky: unknown sky kind %d (expected %d studio or %d outdoor)", kind,
                        SAM_SKY_STUDIO, SAM_SKY_OUTDOOR);
    sam_status st = sam_image_create(out, width, height, 3, err);
    if (st != SAM_OK)
        return st;

    const light_box boxes[3] = {
        make_box(35, 45, 36, 24, 12.5, 12.0, 11.0),  /* key, warm */
        make_box(20, 290, 44, 28, 3.8, 4.0, 4.4),    /* fill, cool */
        make_box(60, 180, 30, 36, 7.0, 7.0, 7.0),    /* top */
    };
    double sun[3];
    dir_from_angles(SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG, sun);
    const double sun_radius = SUN_RADIUS_DEG * PI_D / 180, cos_sun = cos(sun_radius);
    const double dt = PI_D / height, df = 2 * PI_D / width;
    double spacing = 8 * (dt > df ? dt : df) / sun_radius;
    int subsamples = spacing > SUN_MAX_SUBSAMPLES ? SUN_MAX_SUBSAMPLES
                     : spacing < SUN_MIN_SUBSAMPLES ? SUN_MIN_SUBSAMPLES
                                                     : (int)ceil(spacing);

    for (uint32_t row = 0; row < height; ++row) {
        double t0 = row * dt, theta = (row + 0.5) * dt;
        for (uint32_t col = 0; col < width; ++col) {
            double f0 = col * df, phi = (col + 0.5) * df;
            double d[3] = {sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi)};
            double rgb[3];
            if (kind == SAM_SKY_STUDIO) {
                studio_radiance(boxes, d, rgb);
            } else {
                outdoor_radiance(sun, d, rgb);
                /* Every point of a texel is within dt + df of its centre. */
                double cosang = dot3d(d, sun);
                double angle = acos(cosang > 1 ? 1 : cosang < -1 ? -1 : cosang);
                if (angle < sun_radius + dt + df) {
                    double cover = sun_coverage(sun, cos_sun, subsamples, t0, t0 + dt, f0, f0 + df);
                    for (int c = 0; c < 3; ++c)
                        rgb[c] = mix_d(rgb[c], SUN_RADIANCE, cover);
                }
            }
            float *px = out->pixels + 3 * ((size_t)row * width + col);
            for (int c = 0; c < 3; ++c)
                px[c] = (float)rgb[c];
        }
    }
    return SAM_OK;
}

/* ------------------------------------------------------------------------ */
/* Polygon and punctual lights                                               */

sam_status sam_light_polygon_irradiance(const float (*vertices)[3], uint32_t count,
                                        const float normal_of_light[3], int two_sided,
                                        float radiance, const float p[3], const float n[3],
                                        float *irradiance)
{
    if (irradiance)
        *irradiance = 0;
    if (!vertices || !normal_of_light || !p || !n || !irradiance || count < 3 ||
        count > SAM_AREA_LIGHT_MAX_VERTICES)
        return SAM_ERR_INVALID_ARGUMENT;

    double side = 0;
    for (int k = 0; k < 3; ++k)
        side += ((double)p[k] - vertices[0][k]) * normal_of_light[k];
    if (side == 0 || (side < 0 && !two_sided))
        return SAM_OK;

    /* Clip against the receiver's upper half-space: one plane adds at most
     * one vertex to a convex polygon. */
    double r[SAM_AREA_LIGHT_MAX_VERTICES][3], h[SAM_AREA_LIGHT_MAX_VERTICES];
    for (uint32_t i = 0; i < count; ++i) {
        h[i] = 0;
        for (int k = 0; k < 3; ++k) {
            r[i][k] = (double)vertices[i][k] - p[k];
            h[i] += r[i][k] * n[k];
        }
    }
    double clipped[SAM_AREA_LIGHT_MAX_VERTICES + 1][3];
    uint32_t m = 0;
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t j = (i + 1) % count;
        if (h[i] >= 0) {
            memcpy(clipped[m++], r[i], sizeof r[i]);
        }
        if ((h[i] >= 0) != (h[j] >= 0)) {
            double t = h[i] / (h[i] - h[j]);
            for (int k = 0; k < 3; ++k)
                clipped[m][k] = r[i][k] + (r[j][k] - r[i][k]) * t;
            ++m;
        }
    }
    if (m < 3)
        return SAM_OK;

    for (uint32_t i = 0; i < m; ++i) {
        double len = sqrt(dot3d(clipped[i], clipped[i]));
        /* A vertex at p itself: p lies on the light's edge, in its plane,
         * which side != 0 excludes up to rounding. */
        if (!(len > 0))
            return SAM_OK;
        for (int k = 0; k < 3; ++k)
            clipped[i][k] /= len;
    }
    double sum = 0;
    for (uint32_t i = 0; i < m; ++i) {
        const double *a = clipped[i], *b = clipped[(i + 1) % m];
        double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                       a[0] * b[1] - a[1] * b[0]};
        double len = sqrt(dot3d(c, c));
        if (len > 0)
            sum += atan2(len, dot3d(a, b)) * (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]) / len;
    }
    *irradiance = (float)(radiance * 0.5 * fabs(sum));
    return SAM_OK;
}

sam_status sam_light_irradiance(const sam_light *light, const float p[3], const float n[3],
                                float out[3])
{
    if (out)
        out[0] = out[1] = out[2] = 0;
    if (!light || !p || !n || !out)
        return SAM_ERR_INVALID_ARGUMENT;
    double e = 0;
    switch (light->type) {
    case SAM_LIGHT_POINT:
    case SAM_LIGHT_SPOT: {
        double l[3], d2 = 0, ndotl = 0;
        for (int k = 0; k < 3; ++k) {
            l[k] = (double)light->position[k] - p[k];
            d2 += l[k] * l[k];
            ndotl += l[k] * n[k];
        }
        if (!(d2 > 0) || ndotl <= 0)
            break;
        double d = sqrt(d2);
        e = ndotl / d / d2;
        if (light->type == SAM_LIGHT_SPOT) {
            double c = -(l[0] * light->direction[0] + l[1] * light->direction[1] +
                         l[2] * light->direction[2]) / d;
            double cos_inner = cos(light->inner_angle_deg * PI_D / 180);
            double cos_outer = cos(light->outer_angle_deg * PI_D / 180);
            /* Testing inner first makes inner == outer a hard edge. */
            if (c < cos_inner)
                e = c <= cos_outer ? 0 : e * smoothstep_d(cos_outer, cos_inner, c);
        }
        break;
    }
    case SAM_LIGHT_DIRECTIONAL: {
        double c = -((double)n[0] * light->direction[0] + (double)n[1] * light->direction[1] +
                     (double)n[2] * light->direction[2]);
        e = c > 0 ? c : 0;
        break;
    }
    case SAM_LIGHT_AREA: {
        float polygon;
        if (sam_light_polygon_irradiance((const float (*)[3])light->vertices,
                                         light->vertex_count, light->normal, light->two_sided, 1.0f,
                                         p, n, &polygon) != SAM_OK)
            return SAM_ERR_INVALID_ARGUMENT;
        e = polygon;
        break;
    }
    default:
        return SAM_ERR_INVALID_ARGUMENT;
    }
    for (int c = 0; c < 3; ++c)
        out[c] = (float)(e * light->color[c] * light->intensity);
    return SAM_OK;
}
