#version 430 core
// Deformed positions from the rest positions, or from the keyframe pose
// interpolated at the time (sam_runtime_set_keyframes): the deformers of
// sam_deform.h, applied in order, with the formulas of sam_deform.c (its
// CPU reference). Identity steps are left out by the caller, so with none
// and no keyframe pose this pass does not run and the rest pose stays bit
// for bit.
#include "sam_bindings.h"

layout(local_size_x = 64) in;

#define MAX_STEPS 8
#define BEND 0
#define TWIST 1
#define SQUASH 2
#define WAVE 3

layout(std430, binding = SAM_B_POSITIONS) writeonly buffer Positions { vec4 positions[]; };
// Bound to bindings 1 and 2 for this pass only (the normals' and the
// samples' slots otherwise). Keyframe k's vertex v is keys[k * count + v].
layout(std430, binding = SAM_B_KEY_POSITIONS) readonly buffer KeyPositions { vec4 keys[]; };
layout(std430, binding = SAM_B_DEFORM_REST) readonly buffer RestPositions { vec4 rest[]; };

uniform uint u_vertex_count;
uniform int u_step_count;
uniform int u_type[MAX_STEPS];
uniform vec3 u_axis[MAX_STEPS];
uniform vec3 u_direction[MAX_STEPS];
uniform vec3 u_center[MAX_STEPS];
uniform vec3 u_param[MAX_STEPS]; // sam_deform_step.param
// The keyframe pose: key a + (key b - key a) * w; key -1 is the rest pose.
uniform int u_key_a;
uniform int u_key_b;
uniform float u_key_w;

vec3 key(int k, uint v)
{
    return k < 0 ? rest[v].xyz : keys[uint(k) * u_vertex_count + v].xyz;
}

// sin(x) / x. GLSL leaves sin's precision to the driver, and an NVIDIA
// H200's sin of a tiny angle is not the angle: one period on, a periodic
// bend's curvature is sin(2 pi) times its own, about 1e-16, and sin(k u) / k
// lost the distance u along the axis, moving vertices by 0.4 of the mesh's
// size (tests/test_gl_deform.c). Below a quarter radian the series is
// exact to float rounding.
float sinc(float x)
{
    float x2 = x * x;
    return abs(x) < 0.25 ? 1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0)) : sin(x) / x;
}

vec3 deform(int i, vec3 p)
{
    vec3 a = u_axis[i], n = u_direction[i], v = p - u_center[i];
    float u = dot(v, a);
    if (u_type[i] == BEND) {
        // sin(phi) / k = u sinc(phi), and 2 sin^2(phi / 2) / k = u phi sinc^2(phi / 2) / 2,
        // exact as k -> 0; cos(phi) = 1 - 2 sin^2(phi / 2).
        float w = dot(v, n), phi = u_param[i].x * u, s = sinc(phi), hs = sinc(0.5 * phi);
        float h2 = 0.5 * u * phi * hs * hs; // 2 sin^2(phi / 2) / k
        float along = u * s - w * phi * s, across = w * (1.0 - h2 * u_param[i].x) + h2;
        return u_center[i] + (v - u * a - w * n) + along * a + across * n;
    }
    if (u_type[i] == TWIST) {
        float phi = u_param[i].x * u, hs = sinc(0.5 * phi), one_minus_cos = 0.5 * phi * phi * hs * hs;
        return u_center[i] + v * (1.0 - one_minus_cos) + cross(a, v) * (phi * sinc(phi)) + a * (u * one_minus_cos);
    }
    if (u_type[i] == SQUASH)
        return u_center[i] + (u * u_param[i].x) * a + (v - u * a) * u_param[i].y;
    return p + n * (u_param[i].x * sin(u_param[i].y * dot(p, a) + u_param[i].z));
}

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = rest[v].xyz;
    if (u_key_b >= 0) {
        vec3 a = key(u_key_a, v);
        p = a + (key(u_key_b, v) - a) * u_key_w;
    }
    for (int i = 0; i < u_step_count; ++i)
        p = deform(i, p);
    positions[v] = vec4(p, 1.0);
}
