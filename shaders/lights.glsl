#version 430 core
// Irradiance from one light at a surface point: the formulas of
// sam_light_irradiance (sam_core/src/sam_light.c), which the tests compare.
#include "constants.glsl"

struct Light {
    vec4 color_type;    // rgb: color * intensity; w: 0 point, 1 spot, 2 directional, 3 area
    vec4 position;      // xyz (point, spot); w: polygon vertex count (area)
    vec4 direction;     // xyz: spot axis or directional travel (unit); w: cos(inner)
    vec4 params;        // x: cos(outer); y: two-sided (area); z: shadow map index or -1
    vec4 normal;        // xyz: area light's emitting-side normal
    vec4 vertices[8];   // area polygon
};

float spot_falloff(float c, float cos_inner, float cos_outer)
{
    // Inner first: inner == outer is a hard edge, and smoothstep never sees equal edges.
    if (c >= cos_inner)
        return 1.0;
    if (c <= cos_outer)
        return 0.0;
    return smoothstep(cos_outer, cos_inner, c);
}

// Exact irradiance of a convex planar polygon of unit radiance, clipped to
// the receiver's upper half-space (Lambert's polygon formula).
float polygon_irradiance(Light l, vec3 p, vec3 n)
{
    int count = int(l.position.w);
    float side = dot(p - l.vertices[0].xyz, l.normal.xyz);
    if (side == 0.0 || (side < 0.0 && l.params.y == 0.0))
        return 0.0;
    vec3 r[8];
    float h[8];
    for (int i = 0; i < count; ++i) {
        r[i] = l.vertices[i].xyz - p;
        h[i] = dot(r[i], n);
    }
    vec3 clipped[9];
    int m = 0;
    for (int i = 0; i < count; ++i) {
        int j = (i + 1) % count;
        if (h[i] >= 0.0)
            clipped[m++] = r[i];
        if ((h[i] >= 0.0) != (h[j] >= 0.0))
            clipped[m++] = r[i] + (r[j] - r[i]) * (h[i] / (h[i] - h[j]));
    }
    if (m < 3)
        return 0.0;
    for (int i = 0; i < m; ++i) {
        float len = length(clipped[i]);
        if (!(len > 0.0))
            return 0.0;
        clipped[i] /= len;
    }
    float sum = 0.0;
    for (int i = 0; i < m; ++i) {
        vec3 a = clipped[i], b = clipped[(i + 1) % m];
        vec3 c = cross(a, b);
        float len = length(c);
        if (len > 0.0)
            sum += atan(len, dot(a, b)) * dot(c, n) / len;
    }
    return 0.5 * abs(sum);
}

// Irradiance (without shadow) and the cosine used for rho_dt.
vec3 light_irradiance(Light l, vec3 p, vec3 n, out float n_dot_l)
{
    int type = int(l.color_type.w);
    n_dot_l = 0.0;
    float e = 0.0;
    if (type == 0 || type == 1) {
        vec3 to = l.position.xyz - p;
        float d2 = dot(to, to), nl = dot(to, n);
        if (!(d2 > 0.0) || nl <= 0.0)
            return vec3(0.0);
        float d = sqrt(d2);
        e = nl / d / d2;
        n_dot_l = nl / d;
        if (type == 1)
            e *= spot_falloff(-dot(to, l.direction.xyz) / d, l.direction.w, l.params.x);
    } else if (type == 2) {
        n_dot_l = max(-dot(n, l.direction.xyz), 0.0);
        e = n_dot_l;
    } else {
        e = polygon_irradiance(l, p, n);
        // rho_dt of an area light: the cosine towards its centroid.
        vec3 c = vec3(0.0);
        int count = int(l.position.w);
        for (int i = 0; i < count; ++i)
            c += l.vertices[i].xyz;
        vec3 to = c / float(count) - p;
        n_dot_l = clamp(dot(normalize(to), n), 0.0, 1.0);
    }
    return e * l.color_type.rgb;
}

// Light arriving at p from a point, spot or directional light, before the
// cosine (pre-integration and transmittance apply their own falloff over N.L).
vec3 light_radiance(Light l, vec3 p)
{
    int type = int(l.color_type.w);
    if (type == 2)
        return l.color_type.rgb;
    vec3 to = l.position.xyz - p;
    float d2 = dot(to, to);
    float f = 1.0;
    if (type == 1)
        f = spot_falloff(-dot(to, l.direction.xyz) / sqrt(d2), l.direction.w, l.params.x);
    return l.color_type.rgb * f / d2;
}

// The unit direction from p towards the light (an area light's centroid).
vec3 light_direction(Light l, vec3 p)
{
    int type = int(l.color_type.w);
    if (type == 2)
        return -l.direction.xyz;
    if (type == 3) {
        vec3 c = vec3(0.0);
        int count = int(l.position.w);
        for (int i = 0; i < count; ++i)
            c += l.vertices[i].xyz;
        return normalize(c / float(count) - p);
    }
    return normalize(l.position.xyz - p);
}

// How far p lies from the light along its rays, in model units: the
// distance from a point or spot light, the depth along a directional one
// (up to a constant, which cancels in differences).
float light_distance(Light l, vec3 p)
{
    return int(l.color_type.w) == 2 ? dot(p, l.direction.xyz) : distance(p, l.position.xyz);
}
