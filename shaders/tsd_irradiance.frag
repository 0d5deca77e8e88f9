#version 430 core
// The light entering the surface per texel (times sqrt(albedo), d'Eon
// Sec. 5.3), and the stretch map: the millimetres of surface one texel spans
// along u and v (d'Eon Sec. 5.1), from the derivatives of the world position.
#include "albedo.glsl"

in vec3 v_world;
in vec3 v_entering;
in vec2 v_uv;
in float v_facing;
in float v_cull_cos;

uniform float u_mm_per_unit;
uniform int u_culled;

layout(location = 0) out vec4 o_entering;  // rgb, a = 1 where the blur uses the texel
layout(location = 1) out vec4 o_stretch;   // mm per texel along u, v

void main()
{
    // Derivatives first: they are undefined after a discard.
    vec2 stretch = vec2(length(dFdx(v_world)), length(dFdy(v_world))) * u_mm_per_unit;
    // Culled texels keep the clear's alpha 0 (Jimenez and Gutierrez's
    // listing 2), so the blur passes skip them.
    if (u_culled != 0 && v_facing < v_cull_cos)
        discard;
    o_entering = vec4(v_entering * sqrt(surface_albedo(v_uv)), 1.0);
    o_stretch = vec4(stretch, 0.0, 1.0);
}
