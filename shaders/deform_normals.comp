#version 430 core
// After the deform pass: every vertex's normal and reduced fan area
// (Maisch and Ropinski eq. 16) from its ring in the adjacency buffer, and
// its mean curvature for pre-integrated shading, as sam_mesh_ring_curvature
// computes it on the CPU (cotangent Laplacian over the ring, mixed Voronoi
// area; stage 1 gives boundary vertices the mean of their interior ring
// neighbours').
// Consecutive ring entries span one fan triangle (sam_mesh.h), so both are
// sums over consecutive pairs. Seam copies of one vertex carry the same
// ring and position, so they get the same bits.
#include "sam_bindings.h"

layout(local_size_x = 64) in;

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_NORMALS) buffer Normals { vec4 normals[]; };
layout(std430, binding = SAM_B_FAN_AREAS) writeonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = SAM_B_ADJ_OFFSETS) readonly buffer AdjOffsets { uint adj_offsets[]; };
layout(std430, binding = SAM_B_ADJACENCY) readonly buffer Adjacency { uint adjacency[]; };
layout(std430, binding = SAM_B_CURVATURE) buffer Curvature { float curvature[]; }; // 1/mm

// The pose's bounding box, as order-preserving keys of the floats (a
// negative float's bits inverted, a positive one's sign bit set), so that
// integer atomics find the float minimum and maximum.
layout(std430, binding = SAM_B_BOUNDS) buffer Bounds { uint box_min[3]; uint box_max[3]; };

uniform uint u_vertex_count;
uniform float u_mm2_per_unit2;
uniform float u_mm_per_unit;
uniform int u_stage; // 0: normals, fan areas, bounds, interior curvature; 1: boundary curvature

uint order_key(float f)
{
    uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}

bool closed_ring(uint t)
{
    uint b = adj_offsets[t], e = adj_offsets[t + 1u];
    return e - b >= 2u && adjacency[b] == adjacency[e - 1u];
}

float cotangent(vec3 u, vec3 w)
{
    float s = length(cross(u, w));
    return s > 0.0 ? dot(u, w) / s : 0.0;
}

// Mean curvature at an interior vertex, 1/model units (positive where convex).
float ring_curvature(uint v, vec3 p, vec3 n)
{
    vec3 lap = vec3(0.0);
    float area = 0.0;
    uint begin = adj_offsets[v], end = adj_offsets[v + 1u];
    for (uint k = begin + 1u; k < end; ++k) {
        vec3 a = positions[adjacency[k - 1u]].xyz, b = positions[adjacency[k]].xyz;
        vec3 vp = a - p, vq = b - p, pq = b - a;
        float cot_q = cotangent(p - b, a - b), cot_p = cotangent(p - a, pq);
        lap += cot_q * vp + cot_p * vq;
        float tri_area = 0.5 * length(cross(vp, vq));
        if (dot(vp, vq) < 0.0)
            area += tri_area / 2.0;
        else if (dot(-vp, pq) < 0.0 || dot(-vq, -pq) < 0.0)
            area += tri_area / 4.0;
        else
            area += (dot(vp, vp) * cot_q + dot(vq, vq) * cot_p) / 8.0;
    }
    // Laplace-Beltrami of position = -2 H n.
    return area > 0.0 ? -dot(lap, n) / (2.0 * area) / 2.0 : 0.0;
}

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    if (u_stage == 1) {
        if (closed_ring(v))
            return;
        float sum = 0.0;
        uint count = 0u;
        for (uint k = adj_offsets[v]; k < adj_offsets[v + 1u]; ++k) {
            uint u = adjacency[k];
            if (closed_ring(u)) {
                sum += curvature[u];
                ++count;
            }
        }
        curvature[v] = count > 0u ? sum / float(count) : 0.0;
        return;
    }
    vec3 p = positions[v].xyz, sum = vec3(0.0);
    for (int c = 0; c < 3; ++c) {
        atomicMin(box_min[c], order_key(p[c]));
        atomicMax(box_max[c], order_key(p[c]));
    }
    float area = 0.0;
    uint begin = adj_offsets[v], end = adj_offsets[v + 1u];
    for (uint k = begin + 1u; k < end; ++k) {
        vec3 c = cross(positions[adjacency[k - 1u]].xyz - p, positions[adjacency[k]].xyz - p);
        sum += c; // twice the triangle's area along its normal: area weighting
        area += length(c);
    }
    fan_area[v] = area / 6.0 * u_mm2_per_unit2;
    // A fan with no area has no normal to give: it keeps the last one.
    if (dot(sum, sum) > 0.0)
        normals[v] = vec4(normalize(sum), 0.0);
    if (closed_ring(v))
        curvature[v] = ring_curvature(v, p, normals[v].xyz) / u_mm_per_unit;
}
