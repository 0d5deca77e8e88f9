#version 430 core
// The light entering the surface per texel (times sqrt(albedo), d'Eon
// Sec. 5.3), and the stretch map: the millimetres of surface one texel spans
// along u and v (d'Eon Sec. 5.1), from the derivatives of the world position.
// The technique's translucency is evaluated per texel (technique.glsl); an
// override image is read at this texel.
#include "technique.glsl"
#include "albedo.glsl"

in vec3 v_world;
in vec3 v_normal;
in vec3 v_front;
in vec3 v_translucency;
in vec2 v_uv;
in vec3 v_color;
in float v_facing;
in float v_cull_cos;

uniform int u_culled;
// 1: write the G-buffer instead (sam_runtime_gbuffer): position and normal.
uniform int u_gbuffer;

layout(location = 0) out vec4 o_entering;  // rgb, a = 1 where the blur uses the texel
layout(location = 1) out vec4 o_stretch;   // mm per texel along u, v; the triangle + 1

void main()
{
    // Derivatives first: they are undefined after a discard.
    vec2 stretch = vec2(length(dFdx(v_world)), length(dFdy(v_world))) * u_mm_per_unit;
    // Culled texels keep the clear's alpha 0 (Jimenez and Gutierrez's
    // listing 2), so the blur passes skip them.
    if (u_culled != 0 && v_facing < v_cull_cos)
        discard;
    vec3 n = normalize(v_normal);
    if (u_gbuffer != 0) {
        o_entering = vec4(v_world, 1.0);
        o_stretch = vec4(n, 1.0);
        return;
    }
    vec3 entering = v_front + technique_translucency(v_translucency, v_world, n);
    o_entering = vec4(entering * sqrt(surface_albedo(v_uv, v_color)), 1.0);
    // The triangle, for the blur's walks across seams (tsd_cross.glsl):
    // exact in a float below 2^24 triangles, and the walks are off above.
    o_stretch = vec4(stretch, float(gl_PrimitiveID + 1), 1.0);
}
