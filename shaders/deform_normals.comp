#version 430 core
// After the deform pass: every vertex's normal and reduced fan area
// (Maisch and Ropinski eq. 16) from its ring in the adjacency buffer.
// Consecutive ring entries span one fan triangle (sam_mesh.h), so both are
// sums over consecutive pairs. Seam copies of one vertex carry the same
// ring and position, so they get the same bits.

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) buffer Normals { vec4 normals[]; };
layout(std430, binding = 3) writeonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = 6) readonly buffer AdjOffsets { uint adj_offsets[]; };
layout(std430, binding = 7) readonly buffer Adjacency { uint adjacency[]; };

// The pose's bounding box, as order-preserving keys of the floats (a
// negative float's bits inverted, a positive one's sign bit set), so that
// integer atomics find the float minimum and maximum.
layout(std430, binding = 16) buffer Bounds { uint box_min[3]; uint box_max[3]; };

uniform uint u_vertex_count;
uniform float u_mm2_per_unit2;

uint order_key(float f)
{
    uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
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
}
