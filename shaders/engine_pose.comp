#version 430 core
// An engine's posed positions or normals into SAM's (sam_runtime_pose_from_engine):
// SAM vertex v reads the engine's vertex engine_of[v] (v itself when the
// two orders agree) at a float offset and stride, as the engine laid out
// its own vertex buffer.
#include "sam_bindings.h"

layout(local_size_x = 64) in;

layout(std430, binding = SAM_B_ENGINE_TARGET) writeonly buffer Target { vec4 target[]; };
layout(std430, binding = SAM_B_ENGINE_SOURCE) readonly buffer Source { float source[]; };
layout(std430, binding = SAM_B_ENGINE_MAP) readonly buffer EngineOf { uint engine_of[]; };

uniform uint u_vertex_count;
uniform uint u_offset; // floats from the buffer's start to vertex 0
uniform uint u_stride; // floats from one vertex to the next
uniform bool u_identity;
uniform bool u_normals;
uniform vec3 u_frame; // the runtime's origin in model units: positions are kept relative to it

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    uint at = u_offset + (u_identity ? v : engine_of[v]) * u_stride;
    vec3 p = vec3(source[at], source[at + 1u], source[at + 2u]);
    if (u_normals) {
        // Skinning leaves normals a little off unit length; a zero one (a
        // collapsed triangle) keeps a valid if arbitrary direction.
        float len = length(p);
        target[v] = vec4(len > 0.0 ? p / len : vec3(0.0, 0.0, 1.0), 0.0);
    } else {
        target[v] = vec4(p - u_frame, 1.0);
    }
}
