#version 430 core
// The node pass of a cut map. A node's area is its children's summed fan
// areas; its centroid, mean normal and L_d are their area-weighted means,
// so a node reads to the translucency pass as one vertex standing for its
// members (samfile.h).
//
// One dispatch per band of SAM_NODE_BAND_LEVELS tree levels, deepest band
// first: each invocation takes one node of the band's top level and sums
// its descendants inside the band, then the node itself, deepest first
// (their children below the band are ready from the dispatch before). One
// dispatch per level cost llvmpipe about 0.1 ms each, most of the pass on
// small maps; a band of a few levels needs no barrier inside. On a GPU each
// node of a band is a chain of dependent memory reads for its invocation,
// so wide bands lose there what they save in dispatches: two levels were
// the fastest of one, two and four on an H200, and cost llvmpipe 0.25 ms
// more than four on a 1.7k-vertex map, the same on an 18k one.
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
layout(std430, binding = SAM_B_NODES) buffer Nodes { Node nodes[]; };
layout(std430, binding = SAM_B_NODE_CHILDREN) readonly buffer Children { uvec2 children[]; };

uniform uint u_vertex_count;
uniform uint u_first;    // the band's top level's first node
uniform uint u_count;    // its nodes
uniform uint u_band_end; // the first node below the band

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
    float w = a.w + b.w, fa = w > 0.0 ? a.w / w : 0.5;
    nodes[j].ld = vec4(w > 0.0 ? fa * a.rgb + (1.0 - fa) * b.rgb : vec3(0.0), 1.0);
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
    // Members of zero area (degenerate fans) weigh nothing; a node of only
    // those sits between its children and carries no light.
    float fa = w > 0.0 ? wa / w : 0.5, fb = 1.0 - fa;
    nodes[j] = Node(vec4(w > 0.0 ? fa * a.ld.rgb + fb * b.ld.rgb : vec3(0.0), 1.0), vec4(b.ld.rgb - a.ld.rgb, 0.0),
                    vec4(fa * a.centroid_area.xyz + fb * b.centroid_area.xyz, w),
                    vec4(fa * a.normal.xyz + fb * b.normal.xyz, 0.0));
}
#endif

const uint BAND_NODES = (1u << SAM_NODE_BAND_LEVELS) - 1u;

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (k >= u_count)
        return;
    // The node's subtree inside the band, breadth first: each level's
    // children come after it, so summing backwards has every child ready.
    // A tree (samfile.h) has at most BAND_NODES of them.
    uint band[BAND_NODES];
    uint count = 1u;
    band[0] = u_first + k;
    for (uint i = 0u; i < count; ++i) {
        uvec2 c = children[band[i]];
        for (int s = 0; s < 2; ++s) {
            uint child = s == 0 ? c.x : c.y;
            if (child >= u_vertex_count && child - u_vertex_count < u_band_end && count < BAND_NODES)
                band[count++] = child - u_vertex_count;
        }
    }
    for (uint i = count; i-- > 0u;)
        sum_node(band[i]);
}
