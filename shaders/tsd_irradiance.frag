#version 430 core
// The light entering the surface per texel, and the stretch map: the
// millimetres of surface one texel spans along u and v (d'Eon Sec. 5.1),
// from the screen-space derivatives of the world position.
in vec3 v_world;
in vec3 v_entering;

uniform float u_mm_per_unit;

layout(location = 0) out vec4 o_entering;  // rgb, a = 1 where the atlas is covered
layout(location = 1) out vec4 o_stretch;   // mm per texel along u, v

void main()
{
    o_entering = vec4(v_entering, 1.0);
    o_stretch = vec4(length(dFdx(v_world)) * u_mm_per_unit, length(dFdy(v_world)) * u_mm_per_unit, 0.0, 1.0);
}
