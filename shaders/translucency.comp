#version 430 core
// SAM translucency (Maisch and Ropinski eq. 12) with temporal smoothing
// (eq. 17-18): T(v) = sum_k L_d(b_k) K_k, K_k = K'_k F'_b R_d(|v_b - v|)
// (eq. 15), so a deformed pose needs no other path; then
// T <- (1 - alpha) T_prev + alpha T. On a deformed pose a sample that has
// left the back side (eq. 13-14 fail at the pose) contributes 0: its K
// would add light through the front. It stays stored, so it counts again
// when the pose brings it back (walk.comp replaces it when it can).
#include "profile.glsl"

layout(local_size_x = 64) in;

struct Sample {
    uint index;       // back-side vertex, 0xFFFFFFFF for none
    float kr, kg, kb; // K' (eq. 15), kept next to its index: one 16-byte read
};

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) readonly buffer Samples { Sample samples[]; };
layout(std430, binding = 3) readonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = 4) readonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = 5) buffer Translucency { vec4 translucency[]; };

uniform uint u_vertex_count;
uniform uint u_stride;        // samples stored per vertex
uniform uint u_samples;       // samples used, <= u_stride
uniform float u_mm_per_unit;
uniform float u_alpha;        // 1 - (1e-10)^dt; 1 replaces the history
uniform bool u_check_sides;   // deformed pose: skip samples off the back side

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = positions[v].xyz, n = normals[v].xyz;
    vec3 sum = vec3(0.0);
    for (uint k = 0u; k < u_samples; ++k) {
        Sample s = samples[v * u_stride + k];
        if (s.index == 0xFFFFFFFFu)
            break;
        if (u_check_sides &&
            !(dot(positions[s.index].xyz - p, n) < 0.0 && dot(normals[s.index].xyz, n) < 0.0))
            continue;
        float d = u_mm_per_unit * distance(positions[s.index].xyz, p);
        vec3 K = vec3(s.kr, s.kg, s.kb) * fan_area[s.index] * profile_rd(d);
        sum += irradiance[s.index].rgb * K;
    }
    // mix() may be x + (y - x) a, which with a = 1 leaves the history's last
    // bits in: a reset must not depend on what came before.
    translucency[v] = vec4(u_alpha >= 1.0 ? sum : mix(translucency[v].rgb, sum, u_alpha), 1.0);
}
