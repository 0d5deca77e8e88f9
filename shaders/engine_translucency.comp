#version 430 core
// SAM's per-vertex translucency in the engine's vertex order
// (sam_runtime_engine_translucency): engine vertex e takes T of the SAM
// vertex it became, or 0 for one no triangle kept.
#include "sam_bindings.h"

layout(local_size_x = 64) in;

layout(std430, binding = SAM_B_TRANSLUCENCY) readonly buffer Translucency { vec4 t[]; };
layout(std430, binding = SAM_B_ENGINE_TARGET) writeonly buffer Target { vec4 target[]; };
layout(std430, binding = SAM_B_ENGINE_MAP) readonly buffer VertexOf { uint vertex_of[]; };

uniform uint u_engine_count;

void main()
{
    uint e = gl_GlobalInvocationID.x;
    if (e >= u_engine_count)
        return;
    uint v = vertex_of[e];
    target[e] = v == 0xFFFFFFFFu ? vec4(0.0) : t[v];
}
