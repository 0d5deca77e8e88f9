#version 430 core
// Texture-space diffusion, step 1: the mesh unwrapped into its UV atlas.
layout(location = 0) in vec4 a_position;
layout(location = 2) in vec2 a_uv;

layout(std430, binding = 4) readonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 5) readonly buffer Translucency { vec4 translucency[]; };

uniform vec3 u_total_reflectance;
uniform int u_front;

out vec3 v_world;
out vec3 v_entering;

void main()
{
    v_world = a_position.xyz;
    v_entering = translucency[gl_VertexID].rgb;
    if (u_front != 0)
        v_entering += irradiance[gl_VertexID].rgb * u_total_reflectance;
    gl_Position = vec4(a_uv * 2.0 - 1.0, 0.0, 1.0);
}
