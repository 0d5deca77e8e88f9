#version 430 core
// The light-facing surface's atlas UV, its distance from the light and its normal.
#include "sam_bindings.h"
#include "lights.glsl"
#include "uv_atlas.glsl"

layout(std430, binding = SAM_B_LIGHTS) readonly buffer Lights { Light lights[]; };

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

uniform uint u_light;

layout(location = 0) out vec4 o_uv_distance;
layout(location = 1) out vec4 o_normal;

void main()
{
    o_uv_distance = vec4(atlas_uv(v_uv), light_distance(lights[u_light], v_world), 1.0);
    o_normal = vec4(normalize(v_normal), 1.0);
}
