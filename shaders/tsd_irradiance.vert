#version 430 core
// Texture-space diffusion, step 1: the mesh unwrapped into its UV atlas.
#include "sam_bindings.h"
#include "uv_atlas.glsl"
layout(location = 0) in vec4 a_position;
layout(location = 1) in vec4 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec4 a_color; // the vertex colour, or white (sam_runtime_bind_albedo)

layout(std430, binding = SAM_B_IRRADIANCE) readonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = SAM_B_TRANSLUCENCY) readonly buffer Translucency { vec4 translucency[]; };
layout(std430, binding = SAM_B_CURVATURE) readonly buffer Curvature { float curvature[]; };

uniform vec3 u_total_reflectance;
uniform int u_front;
uniform vec3 u_eye;
uniform mat4 u_view_proj;
uniform int u_clipped;
uniform vec2 u_clip_margin;  // clip-space widening of the side planes, x and y
uniform float u_cull_reach;  // mm of surface past the silhouette the blur may draw from
uniform float u_cull_min;    // the least angle past the silhouette kept, radians

out vec3 v_world;
out vec3 v_normal;
out vec3 v_front;            // R_total L_d where the view shows front light
out vec3 v_translucency;     // the per-vertex T
out vec2 v_uv;
out vec3 v_color;
out float v_facing;          // cosine between the normal and the direction to the eye
out float v_cull_cos;        // texels facing the eye less than this are culled
out float gl_ClipDistance[4];

void main()
{
    v_world = a_position.xyz;
    v_normal = a_normal.xyz;
    v_translucency = translucency[gl_VertexID].rgb;
    v_front = u_front != 0 ? irradiance[gl_VertexID].rgb * u_total_reflectance : vec3(0.0);
    v_uv = a_uv;
    v_color = a_color.rgb;
    v_facing = dot(normalize(a_normal.xyz), normalize(u_eye - a_position.xyz));
    // On a surface of curvature k, a texel an angle a past the silhouette
    // lies a / k of surface away from it: keep what the blur can reach.
    float past = clamp(u_cull_reach * abs(curvature[gl_VertexID]), u_cull_min, 1.5707963);
    v_cull_cos = -sin(past);
    // Clip distances are affine in the position, so they interpolate
    // exactly across a triangle unwrapped into UV space (Jimenez and
    // Gutierrez clip in eye space for the same reason).
    // Written positive when not clipping: llvmpipe clips by written
    // distances even with GL_CLIP_DISTANCEi disabled.
    vec4 clip = u_view_proj * vec4(a_position.xyz, 1.0);
    bool off = u_clipped == 0;
    gl_ClipDistance[0] = off ? 1.0 : clip.w + clip.x + u_clip_margin.x;
    gl_ClipDistance[1] = off ? 1.0 : clip.w - clip.x + u_clip_margin.x;
    gl_ClipDistance[2] = off ? 1.0 : clip.w + clip.y + u_clip_margin.y;
    gl_ClipDistance[3] = off ? 1.0 : clip.w - clip.y + u_clip_margin.y;
    gl_Position = vec4(atlas_uv(a_uv) * 2.0 - 1.0, 0.0, 1.0);
}
