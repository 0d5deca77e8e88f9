#version 430 core
// Local-thickness translucency (Barre-Brisebois and Bouchard, GDC 2011) at
// every vertex, written where SAM's T goes: T = E_back G(t). E_back is the
// light the back side lets in, each light's irradiance on the plane facing
// -n (the inverted normal) times rho_dt of its cosine, as L_d takes it
// (irradiance.comp), plus the environment's SH-9 irradiance at -n; G(t) the
// profile's transmission through a uniformly lit slab of the vertex's
// thickness (sam_profile_slab_transmission, per vertex from the CPU). The
// talk's hand-set power and scale become the material's own G. Nothing is
// shadowed, as engines ship it: the back side counts as lit wherever a
// light faces it.
#include "sam_bindings.h"
#include "lights.glsl"
#include "surface.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = SAM_B_LIGHTS) readonly buffer Lights { Light lights[]; };
layout(std430, binding = SAM_B_TRANSMISSION) readonly buffer Transmission { vec4 transmission[]; };
layout(std430, binding = SAM_B_TRANSLUCENCY) writeonly buffer Translucency { vec4 translucency[]; };

uniform uint u_vertex_count;
uniform uint u_light_count;
uniform float u_distortion;   // the talk's L + N distortion; 0: the plain inverted normal

// Light l's share of E_back at p. The talk's distortion bends the light's
// direction towards the normal, L' = L + n distortion, and takes the cosine
// of -n with L' instead of L; an area light has no single direction, so it
// keeps the exact polygon irradiance on the inverted plane.
vec3 back_light(Light l, vec3 p, vec3 n)
{
    float c;
    if (u_distortion == 0.0 || int(l.color_type.w) == 3) {
        vec3 e = light_irradiance(l, p, -n, c);
        return e == vec3(0.0) ? e : e * rho_dt(c);
    }
    vec3 bent = light_direction(l, p) + n * u_distortion;
    float len = length(bent);
    c = len > 0.0 ? dot(-n, bent) / len : 0.0;
    return c > 0.0 ? light_radiance(l, p) * c * rho_dt(c) : vec3(0.0);
}

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = positions[v].xyz, n = normals[v].xyz;
    vec3 e = environment_irradiance(-n);
    for (uint i = 0u; i < u_light_count; ++i)
        e += back_light(lights[i], p, n);
    translucency[v] = vec4(e * transmission[v].rgb, 1.0);
}
