#version 430 core
// The translucency a technique adds to the light entering the surface, per
// fragment of the shading pass (diffusion none, screen, pre-integrated) or
// of the texture-space atlas: the SAM's per-vertex T (or the local-thickness
// technique's, bound in its place), nothing, Jimenez et al.'s shadow-map
// transmittance, or a caller's image (the override). It
// takes the place of T: R_total L_d + translucency is what the surface lets in.
#include "sam_bindings.h"
#include "lights.glsl"
#include "shadows.glsl"

layout(std430, binding = SAM_B_LIGHTS) readonly buffer Lights { Light lights[]; };

const int TECHNIQUE_VERTEX = 0;         // the per-vertex T buffer
const int TECHNIQUE_NONE = 1;
const int TECHNIQUE_TRANSMITTANCE = 2;
const int TECHNIQUE_OVERRIDE = 3;       // u_override at this fragment's pixel or texel
const int TECHNIQUE_THICKNESS = 4;      // the local-thickness pass's per-vertex T, bound where T is

uniform int u_technique;
uniform uint u_all_light_count;         // every light, whatever u_front says
uniform float u_mm_per_unit;
uniform sampler2D u_override;

// The material's Gaussian fit (d'Eon App. A): rgb weights summing to the
// total reflectance, w the variance in mm^2.
uniform int u_fit_count;
uniform vec4 u_fit[8];

// The shadow maps read as distances (sampler objects without comparison).
uniform samplerCube u_cube_distance[4];
uniform sampler2D u_flat_distance[4];
uniform float u_normal_offset;          // model units into the object for light_thickness's lookup

// sum_i w_i exp(-d^2 / (2 v_i)) for a thickness of d mm. Jimenez et al.
// write exp(-d^2 / v_i), but with G(v, r) = exp(-r^2 / 2v) / (2 pi v) the
// 3D Gaussian separates as G(v, sqrt(r^2 + d^2)) = exp(-d^2 / 2v) G(v, r):
// a slab of thickness d passes exp(-d^2 / 2v) of a uniformly lit face's light.
vec3 fit_through(float d)
{
    vec3 sum = vec3(0.0);
    for (int i = 0; i < u_fit_count; ++i)
        sum += u_fit[i].rgb * exp(-d * d / (2.0 * u_fit[i].w));
    return sum;
}

// The object's thickness between p and light l in model units, or -1 where
// l has no shadow map or p lies outside it: p's own distance from the light
// minus the distance the map stores where it sees the point p moved inside
// along -n. Only the lookup moves: at a silhouette the map's texel at p
// itself may hold p's own surface, and moving p's distance as well would
// thin every slab by the offset.
float light_thickness(Light l, vec3 p, vec3 n)
{
    int index = int(l.params.z);
    if (index < 0)
        return -1.0;
    vec3 q = p - n * u_normal_offset;
    if (l.params.w != 0.0) {
        float stored = texture(u_cube_distance[index], q - u_cube_origin[index]).r * u_cube_far[index];
        return abs(distance(p, u_cube_origin[index]) - stored);
    }
    vec4 clip = u_flat_matrix[index] * vec4(q, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    if (clip.w <= 0.0 || any(greaterThan(abs(ndc.xy), vec2(1.0))))
        return -1.0;
    float stored = texture(u_flat_distance[index], ndc.xy * 0.5 + 0.5).r;
    if (u_flat_far[index] > 0.0)
        return abs(distance(p, u_flat_origin[index]) - stored * u_flat_far[index]);
    // Orthographic: depth is linear, window depth times the range.
    vec4 own = u_flat_matrix[index] * vec4(p, 1.0);
    return abs(own.z / own.w * 0.5 + 0.5 - stored) * u_flat_range[index];
}

// Jimenez et al. 2010: per shadowed point, spot or directional light, the
// profile through the thickness times the light's unshadowed irradiance as
// if facing it, times saturate(0.3 + N.-L) (their wrap term). Area lights
// and the environment have no single direction through the object: none.
vec3 transmittance(vec3 p, vec3 n)
{
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < u_all_light_count; ++i) {
        Light l = lights[i];
        if (int(l.color_type.w) == 3)
            continue;
        float s = light_thickness(l, p, n);
        if (s < 0.0)
            continue;
        float wrap = clamp(0.3 + dot(-n, light_direction(l, p)), 0.0, 1.0);
        if (wrap > 0.0)
            sum += fit_through(s * u_mm_per_unit) * light_radiance(l, p) * wrap;
    }
    return sum;
}

// vertex_t: the interpolated per-vertex T; p, n: the fragment's position and normal.
vec3 technique_translucency(vec3 vertex_t, vec3 p, vec3 n)
{
    if (u_technique == TECHNIQUE_VERTEX || u_technique == TECHNIQUE_THICKNESS)
        return vertex_t;
    if (u_technique == TECHNIQUE_TRANSMITTANCE)
        return transmittance(p, n);
    if (u_technique == TECHNIQUE_OVERRIDE)
        return texelFetch(u_override, ivec2(gl_FragCoord.xy), 0).rgb;
    return vec3(0.0);
}
