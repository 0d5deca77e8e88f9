/*
 * sam_light: CPU lighting math. The GL runtime's shaders mirror these
 * formulas, and tests and the ground truth use these functions as the
 * reference, so every formula is written out here exactly.
 *
 * Coordinates are the scene's: right-handed, +Y up. Irradiance is the
 * cosine-weighted integral of incident radiance over the hemisphere around a
 * receiver normal n (a white Lambertian surface then leaves with radiance
 * E / pi).
 *
 * 1. Latitude-longitude environment maps (width W, height H, top row first):
 *      u = (column + 0.5) / W,  v = (row + 0.5) / H       (texel centres)
 *      phi = 2 pi u,  theta = pi v                        (theta from +Y)
 *      dir(u, v) = (sin theta sin phi,  cos theta,  sin theta cos phi)
 *    So the top row looks up (+Y), the middle row at the horizon, u = 0 is
 *    +Z, u = 0.25 is +X, u = 0.5 is -Z, u = 0.75 is -X. Inverse, for a unit
 *    d: phi = atan2(d.x, d.z) wrapped to [0, 2 pi), theta = acos(d.y).
 *    Rotation by rotation_deg = alpha turns the environment about +Y,
 *    counter-clockwise seen from +Y (right-handed: +Z moves towards +X): the
 *    map's direction dir(u, v) lights the scene from dir(u + alpha/360, v).
 *    To look the map up for a world direction d, take u(d) - alpha/360
 *    (wrapped) and v(d).
 *
 * 2. Spherical harmonics (Ramamoorthi & Hanrahan 2001), 9 real basis
 *    functions of a unit direction (x, y, z), index k = l (l + 1) + m:
 *      k=0 Y00  = 0.282094792                   (1 / (2 sqrt(pi)))
 *      k=1 Y1-1 = 0.488602512 y                 (sqrt(3 / (4 pi)))
 *      k=2 Y10  = 0.488602512 z
 *      k=3 Y11  = 0.488602512 x
 *      k=4 Y2-2 = 1.092548431 x y               (sqrt(15 / pi) / 2)
 *      k=5 Y2-1 = 1.092548431 y z
 *      k=6 Y20  = 0.315391565 (3 z^2 - 1)       (sqrt(5 / pi) / 4)
 *      k=7 Y21  = 1.092548431 x z
 *      k=8 Y22  = 0.546274215 (x^2 - y^2)       (sqrt(15 / pi) / 4)
 *    (The Cartesian forms fix the basis; that the polar axis of this
 *    standard basis is z rather than the scene's up axis does not matter:
 *    projection and evaluation use the same functions.)
 *    Radiance coefficients L_k = integral over the sphere of L(d) Y_k(d).
 *    Irradiance E(n) = sum_k A_l(k) L_k Y_k(n), A_0 = pi, A_1 = 2 pi / 3,
 *    A_2 = pi / 4, so a constant radiance L gives E = pi L. E is clamped to
 *    >= 0 per channel: as the paper shows, SH-9 irradiance is within a few
 *    percent of the exact one only for low-frequency environments; a small
 *    bright source (a sun) is blurred and rings, and the series can go
 *    negative facing away from it. Such a source is better taken out of
 *    the map and added as a directional light.
 *
 * 3. Lights (sam_light below; scene files describe them, sam_scene.h),
 *    irradiance at a point p with unit normal n
 *    (clamp(x) = max(x, 0); color and intensity multiply every result):
 *    point:        l = pos - p, d = |l|:  E = clamp(n . l / d) / d^2
 *    spot:         as point, times falloff(c), c = dot(axis, -l / d):
 *                    c >= cos(inner)  -> 1
 *                    c <= cos(outer)  -> 0
 *                    else t = (c - cos outer) / (cos inner - cos outer),
 *                         falloff = t * t * (3 - 2 t)   (smoothstep)
 *                  (tested in this order, so inner == outer is a hard edge
 *                  and GLSL's smoothstep with equal edges is never needed)
 *    directional:  E = clamp(-n . direction)
 *    area:         E = polygon irradiance (below) with radiance 1
 *    A point or spot light at p itself (d = 0) gives 0.
 *
 * 4. Polygon irradiance, exact and unoccluded (Lambert's formula). The light
 *    is a convex planar polygon of radiance L emitting on the side its
 *    normal n_l points to (both sides when two-sided):
 *      s = (p - v_0) . n_l; s <= 0 and one-sided -> E = 0; s == 0 -> E = 0
 *      clip the polygon r_i = v_i - p against the receiver's half-space
 *        n . r >= 0 (Sutherland-Hodgman: keep r_i with n . r_i >= 0, and on
 *        each edge whose end points lie on opposite sides insert
 *        r_a + (r_b - r_a) (n . r_a) / (n . r_a - n . r_b)); fewer than 3
 *        points left -> E = 0
 *      u_i = r_i / |r_i| over the m clipped points, u_m = u_0
 *      S = sum_i atan2(|u_i x u_i+1|, u_i . u_i+1) * n . (u_i x u_i+1) / |u_i x u_i+1|
 *      E = L |S| / 2
 *    atan2(|c|, dot) is the edge's angle acos(u_i . u_i+1), computed without
 *    acos's loss of precision for short edges. S is negative for a polygon
 *    wound counter-clockwise as seen from p and positive for the other
 *    winding; |S| makes the result independent of the winding, and the
 *    emitting side comes from n_l alone.
 *
 * Nothing here keeps global state; every function is reentrant.
 */
#ifndef SAM_LIGHT_H
#define SAM_LIGHT_H

#include "sam/sam_common.h"
#include "sam/sam_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Lights a scene (and the runtime) accepts. */
#define SAM_LIGHT_MAX_COUNT 64
#define SAM_AREA_LIGHT_MAX_VERTICES 8

typedef enum sam_light_type {
    SAM_LIGHT_POINT = 0,
    SAM_LIGHT_SPOT = 1,
    SAM_LIGHT_DIRECTIONAL = 2,
    SAM_LIGHT_AREA = 3
} sam_light_type;

/* One light; plain data. Units and formulas: the overview (3, 4). */
typedef struct sam_light {
    sam_light_type type;
    float color[3];  /* linear RGB, >= 0 */
    float intensity; /* >= 0 */
    int shadow;      /* 1: casts shadows */

    float position[3];       /* point, spot (model units) */
    float direction[3];      /* spot axis, directional: unit, the way light travels */
    float inner_angle_deg;   /* spot: full intensity inside this half-angle */
    float outer_angle_deg;   /* spot: no light outside this half-angle */

    uint32_t vertex_count;                            /* area: 3..8 */
    float vertices[SAM_AREA_LIGHT_MAX_VERTICES][3];   /* area: convex planar polygon */
    float normal[3]; /* area: unit normal of the emitting side (derived from the winding) */
    float area;      /* area: polygon area in model units^2 (derived) */
    int two_sided;   /* area: 1 emits on both sides */
} sam_light;

/* SH basis constants (index k as above). */
#define SAM_SH_C0 0.282094792f /* Y00 */
#define SAM_SH_C1 0.488602512f /* Y1m */
#define SAM_SH_C2 1.092548431f /* Y2-2, Y2-1, Y21 */
#define SAM_SH_C3 0.315391565f /* Y20 */
#define SAM_SH_C4 0.546274215f /* Y22 */

/* Procedural environments for sam_light_make_sky. */
enum {
    SAM_SKY_STUDIO = 0, /* grey floor, soft gradient, three soft rectangular light boxes */
    SAM_SKY_OUTDOOR = 1 /* blue sky to a hazy horizon, ground, a small very bright sun */
};

/* Direction of the lat-long coordinates (u, v) (any reals; u wraps):
 * dir = (sin(pi v) sin(2 pi u), cos(pi v), sin(pi v) cos(2 pi u)), unit. */
void sam_light_latlong_direction(float u, float v, float dir[3]);

/* Inverse of sam_light_latlong_direction for a unit `dir`: u in [0, 1),
 * v in [0, 1]. Along the poles (x = z = 0) u is 0. */
void sam_light_latlong_from_direction(const float dir[3], float *u, float *v);

/* Evaluates the 9 basis functions at the unit direction `dir` into `y`. */
void sam_light_sh9_basis(const float dir[3], float y[9]);

/* Projects the radiance of the lat-long map `env` (3 or 4 channels; alpha
 * is ignored), rotated about +Y by `rotation_deg` and scaled by `intensity`,
 * onto the 9 basis functions: sh[k][c] = intensity * integral L_c Y_k.
 * The map is taken as constant over each texel, and each texel's integral
 * of Y_k over its exact solid angle (theta and phi bands, weight sin theta)
 * is computed in closed form, so a constant map gives exactly
 * L_0 = 2 sqrt(pi) L and L_k = 0 for k > 0 (to rounding) at any size.
 * Negative texels are allowed (compression noise); non-finite ones are not.
 * Cost: O(width * height), trigonometry only per row and column.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL env or sh, zero width or height,
 * NULL pixels, channels not 3/4, more than SAM_IMAGE_MAX_PIXELS pixels,
 * rotation not finite, intensity not finite and >= 0), SAM_ERR_FORMAT
 * (a texel is NaN or infinite: the message gives its column, row, channel
 * and value). On failure `sh` (when not NULL) is zeroed. */
sam_status sam_light_sh9_from_latlong(const sam_image *env, float rotation_deg, float intensity,
                                      float sh[9][3], sam_error *err);

/* Irradiance E(n) = max(0, sum_k A_l L_k Y_k(n)) per channel for the unit
 * normal `n` (not normalised here). The clamp matters only where a small
 * bright source rings: the outdoor sky's sun makes the series negative
 * facing away from it. */
void sam_light_sh9_irradiance(const float sh[9][3], const float n[3], float out[3]);

/* Fills `out` with a new width x height RGB lat-long HDR map of `kind`
 * (SAM_SKY_*), deterministic for given arguments; the caller frees it with
 * sam_image_destroy. Every value fits a half float. Features (azimuths use
 * the lat-long convention: 0 = +Z, 90 = +X):
 *  studio:  floor 0.04 (nadir) to 0.08 (horizon) grey; walls 0.10 at the
 *           horizon to 0.25 at the zenith; three soft-edged boxes (angular
 *           rectangles, 3 degree soft edges): key, warm, radiance ~12, at
 *           elevation 35 azimuth 45, 36 x 24 degrees; fill, cool, ~4, at
 *           elevation 20 azimuth 290, 44 x 28 degrees; top, 7, at
 *           elevation 60 azimuth 180, 30 x 36 degrees.
 *  outdoor: sky from (0.15, 0.30, 0.75) at the zenith to a haze of
 *           (0.90, 0.95, 1.00) at the horizon; ground (0.08, 0.075, 0.06)
 *           brightening towards the horizon; a sun disk of radiance 5000
 *           and angular radius 1.5 degrees (about 3 times the real one, so
 *           a 1024-wide map resolves it) at elevation 40 azimuth 120, with
 *           a faint aureole. Texels the disk touches get the disk's
 *           covered fraction (equal-solid-angle subsamples at most 1/8 of
 *           its radius apart, up to 64 x 64 a texel), so its energy,
 *           5000 x 2.15e-3 sr, is kept at any resolution.
 * Errors: SAM_ERR_INVALID_ARGUMENT (NULL out, width or height zero, more
 * than SAM_IMAGE_MAX_PIXELS pixels, an unknown kind: the message names
 * it), SAM_ERR_OUT_OF_MEMORY. On failure `out` is zeroed. */
sam_status sam_light_make_sky(uint32_t width, uint32_t height, int kind, sam_image *out,
                              sam_error *err);

/* Exact unoccluded irradiance at `p` (unit normal `n`) from a convex planar
 * polygon of `count` (3..SAM_AREA_LIGHT_MAX_VERTICES) `vertices`, with
 * scalar `radiance`, emitting on the side of its unit normal
 * `normal_of_light` (both sides when `two_sided` is non-zero), by the
 * formula of the overview (4). The polygon's winding does not matter.
 * Polygon parts below p's horizon do not contribute. `*irradiance` is set
 * to 0 on failure.
 * Errors: SAM_ERR_INVALID_ARGUMENT (a NULL pointer, count outside
 * 3..SAM_AREA_LIGHT_MAX_VERTICES). No message: this runs per sample. */
sam_status sam_light_polygon_irradiance(const float (*vertices)[3], uint32_t count,
                                        const float normal_of_light[3], int two_sided,
                                        float radiance, const float p[3], const float n[3],
                                        float *irradiance);

/* RGB irradiance at `p` (unit normal `n`) from `light` by the formulas of
 * the overview (3): point, spot, directional, or area (using the light's
 * vertices, vertex_count, normal and two_sided as sam_scene sets them).
 * `out` is zeroed on failure.
 * Errors: SAM_ERR_INVALID_ARGUMENT (a NULL pointer, an unknown type, an
 * area light with vertex_count outside 3..SAM_AREA_LIGHT_MAX_VERTICES). */
sam_status sam_light_irradiance(const sam_light *light, const float p[3], const float n[3],
                                float out[3]);

#ifdef __cplusplus
}
#endif

#endif
