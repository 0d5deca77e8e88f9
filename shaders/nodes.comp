#version 430 core
// The node pass of a cut map. A node's area is its children's summed fan
// areas; its centroid, mean normal and L_d are their area-weighted means,
// so a node reads to the translucency pass as one vertex standing for its
// members (samfile.h).
//
// One dispatch for the whole tree, bottom up as a BVH refit is done on a
// GPU: an invocation starts at a vertex and climbs to its parent; of a
// node's two children the first to arrive stops there, and the second,
// which finds the other one ready, sums the node and climbs on. Summing
// level by level took a dispatch and a barrier per level (or a chain of
// dependent reads per invocation for a band of levels): on an H200 the
// pass cost more than the translucency pass it feeds on an 18k-vertex map.
// Every node is summed from its two children in a fixed order, whoever
// arrives second, so the result does not depend on the scheduling.
//
// With SAM_NODES_LIGHT only L_d is summed: at rest the centroids, areas
// and normals a full pass wrote stay right (sam_runtime_nodes.c says when).
#include "sam_bindings.h"

layout(local_size_x = 64) in;

#include "node.glsl"

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = SAM_B_FAN_AREAS) readonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = SAM_B_IRRADIANCE) readonly buffer Irradiance { vec4 irradiance[]; };
// Coherent: a node is written by one invocation and read by another of
// the same dispatch.
layout(std430, binding = SAM_B_NODES) coherent buffer Nodes { Node nodes[]; };
layout(std430, binding = SAM_B_NODE_CHILDREN) readonly buffer Children { uvec2 children[]; };
layout(std430, binding = SAM_B_NODE_PARENTS) readonly buffer Parents { uint parents[]; };
// Per node, its children that have arrived in this pass; the second one
// puts it back to 0 for the next pass.
layout(std430, binding = SAM_B_NODE_ARRIVALS) coherent buffer Arrivals { uint arrivals[]; };

#define NO_PARENT 0xFFFFFFFFu

uniform uint u_vertex_count;

// A node's L_d from its children's L_d and areas. Both variants below
// compute it here, precise so that neither compiles it with other fused
// multiply-adds: the first full pass after a pose must give the L_d the
// light pass gave before it, bit for bit (on an H200 the two differed in
// the last bit, tests/test_gl_walk.c). Members of zero area (degenerate
// fans) weigh nothing; a node of only those carries no light.
vec3 node_ld(vec3 a, float wa, vec3 b, float wb)
{
    precise float w = wa + wb, fa = wa / w;
    precise vec3 ld = fa * a + (1.0 - fa) * b;
    return w > 0.0 ? ld : vec3(0.0);
}

#ifdef SAM_NODES_LIGHT
// A child's L_d (rgb) and area (w).
vec4 child_light(uint c)
{
    if (c >= u_vertex_count) {
        uint i = c - u_vertex_count;
        return vec4(nodes[i].ld.rgb, nodes[i].centroid_area.w);
    }
    return vec4(irradiance[c].rgb, fan_area[c]);
}

void sum_node(uint j)
{
    vec4 a = child_light(children[j].x), b = child_light(children[j].y);
    nodes[j].ld = vec4(node_ld(a.rgb, a.w, b.rgb, b.w), 1.0);
    nodes[j].ld_diff = vec4(b.rgb - a.rgb, 0.0);
}
#else
Node read_child(uint c)
{
    if (c >= u_vertex_count)
        return nodes[c - u_vertex_count];
    return Node(irradiance[c], vec4(0.0), vec4(positions[c].xyz, fan_area[c]), normals[c]);
}

void sum_node(uint j)
{
    Node a = read_child(children[j].x), b = read_child(children[j].y);
    float wa = a.centroid_area.w, wb = b.centroid_area.w, w = wa + wb;
    // A node of only zero-area members sits between its children.
    float fa = w > 0.0 ? wa / w : 0.5, fb = 1.0 - fa;
    nodes[j] = Node(vec4(node_ld(a.ld.rgb, wa, b.ld.rgb, wb), 1.0), vec4(b.ld.rgb - a.ld.rgb, 0.0),
                    vec4(fa * a.centroid_area.xyz + fb * b.centroid_area.xyz, w),
                    vec4(fa * a.normal.xyz + fb * b.normal.xyz, 0.0));
}
#endif

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    for (uint j = parents[v]; j != NO_PARENT; j = parents[u_vertex_count + j]) {
        if (atomicAdd(arrivals[j], 1u) == 0u)
            return;
        // The sibling's node is read after its arrival was seen.
        memoryBarrierBuffer();
        arrivals[j] = 0u;
        sum_node(j);
        // The node must be visible before its arrival at its parent is.
        memoryBarrierBuffer();
    }
}
