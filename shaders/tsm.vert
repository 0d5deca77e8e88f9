#version 430 core
// A translucent shadow map (d'Eon Sec. 5.2): the mesh seen from a light
// through the shadow map's own view-projection.
layout(location = 0) in vec4 a_position;
layout(location = 1) in vec4 a_normal;
layout(location = 2) in vec2 a_uv;

uniform mat4 u_view_proj;

out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;

void main()
{
    v_world = a_position.xyz;
    v_normal = a_normal.xyz;
    v_uv = a_uv;
    gl_Position = u_view_proj * vec4(a_position.xyz, 1.0);
}
