#version 430 core
// The node pass of a cut map: one tree level per dispatch, deepest first.
// A node's area is its children's summed fan areas; its centroid, mean
// normal and L_d are their area-weighted means, so a node reads to the
// translucency pass as one vertex standing for its members (samfile.h).
#include "sam_bindings.h"

layout(local_size_x = 64) in;

struct Node {
    vec4 centroid_area; // centroid (model units), area (mm^2)
    vec4 ld;            // area-weighted mean L_d
    vec4 normal;        // area-weighted mean normal (not unit)
    vec4 ld_diff;       // L_d(child 1) - L_d(child 0): a sample moves along it by its tau
};

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = SAM_B_FAN_AREAS) readonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = SAM_B_IRRADIANCE) readonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = SAM_B_NODES) buffer Nodes { Node nodes[]; };
layout(std430, binding = SAM_B_NODE_CHILDREN) readonly buffer Children { uvec2 children[]; };

uniform uint u_vertex_count;
uniform uint u_first; // the level's first node
uniform uint u_count; // its nodes

Node read_child(uint c)
{
    if (c >= u_vertex_count)
        return nodes[c - u_vertex_count];
    return Node(vec4(positions[c].xyz, fan_area[c]), irradiance[c], normals[c], vec4(0.0));
}

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (k >= u_count)
        return;
    uint j = u_first + k;
    Node a = read_child(children[j].x), b = read_child(children[j].y);
    float wa = a.centroid_area.w, wb = b.centroid_area.w, w = wa + wb;
    // Members of zero area (degenerate fans) weigh nothing; a node of only
    // those sits between its children and carries no light.
    float fa = w > 0.0 ? wa / w : 0.5, fb = 1.0 - fa;
    nodes[j] = Node(vec4(fa * a.centroid_area.xyz + fb * b.centroid_area.xyz, w),
                    vec4(w > 0.0 ? fa * a.ld.rgb + fb * b.ld.rgb : vec3(0.0), 1.0),
                    vec4(fa * a.normal.xyz + fb * b.normal.xyz, 0.0), vec4(b.ld.rgb - a.ld.rgb, 0.0));
}
