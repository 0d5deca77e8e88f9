#version 430 core
// Forward shading of the mesh: per-vertex T comes from the SAM passes'
// buffers, indexed by the vertex the index buffer names (the front's L_d is
// shaded per pixel).
#include "sam_bindings.h"
layout(location = 0) in vec4 a_position;
layout(location = 1) in vec4 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_color; // the vertex colour, or white (sam_runtime_bind_albedo)

layout(std430, binding = SAM_B_TRANSLUCENCY) readonly buffer Translucency { vec4 translucency[]; };
layout(std430, binding = SAM_B_CURVATURE) readonly buffer Curvature { float curvature[]; };

uniform mat4 u_view_proj;
uniform vec3 u_forward;       // unit view direction: linear depth = (p - eye) . forward
uniform vec3 u_eye;

out vec3 v_position;
out vec3 v_normal;
out vec3 v_to_eye;
out vec3 v_translucency;
out float v_depth;
out float v_curvature;       // 1/mm
out vec2 v_uv;
out vec3 v_color;

void main()
{
    v_position = a_position.xyz;
    v_normal = a_normal.xyz;
    v_to_eye = u_eye - a_position.xyz;
    v_translucency = translucency[gl_VertexID].rgb;
    v_depth = dot(a_position.xyz - u_eye, u_forward);
    v_curvature = curvature[gl_VertexID];
    v_uv = a_uv;
    v_color = a_color.rgb;
    gl_Position = u_view_proj * vec4(a_position.xyz, 1.0);
}
