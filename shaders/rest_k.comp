#version 430 core
// Each stored sample's K at the rest pose, K = K' F'_b R_d(|v_b - v|)
// (eq. 15), written once per map (sam_runtime_rest_k.h). At rest K never
// changes, and R_d is most of what the translucency pass paid per sample
// (8 Gaussians, or the dipole's two poles): with K read from here the rest
// pass only sums L_d K, and a posed frame takes a tree node's rest K from
// here too. The inputs are bound to the rest pose: the live buffers before
// any deformation, else the copies the first deformation kept.
#include "sam_bindings.h"
#include "profile.glsl"

layout(local_size_x = 64) in;

#include "sample.glsl"
#include "node.glsl"

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_SAMPLES) readonly buffer Samples { uint samples[]; };
layout(std430, binding = SAM_B_FAN_AREAS) readonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = SAM_B_NODES) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = SAM_B_REST_K) writeonly buffer RestK { uint rest_k[]; };

uniform uint u_vertex_count;
uniform uint u_stride; // samples stored per vertex
uniform float u_mm_per_unit;

#include "eq15_k.glsl"

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = positions[v].xyz;
    for (uint k = 0u; k < u_stride; ++k) {
        uint i = sample_slot(v, k, u_vertex_count);
        Sample s = SAMPLE_LOAD(samples, i);
        if (s.index == 0xFFFFFFFFu) {
            SAMPLE_STORE(rest_k, i, Sample(s.index, uvec2(0u)));
            continue;
        }
        vec3 k_rest = eq15_k(s.index, sample_k(s), p);
        SAMPLE_STORE(rest_k, i, make_sample(s.index, k_rest));
    }
}
