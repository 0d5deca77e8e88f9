#version 430 core
// One mip level of the screen-space blur's light and depth
// (sss_blur.comp), from the level above: each texel is the bilinear
// sample of the level above at its centre, the 2x2 mean where that level's
// size is even, as a blit-based glGenerateMipmap makes it. Both chains in
// one dispatch per level: glGenerateMipmap on each took an NVIDIA H200
// 0.26 to 0.31 ms for the light and 0.10 to 0.15 ms for the depth at
// 1920x1080, 65 to 78% of the whole diffusion (docs/performance.md).
#include "sam_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = SAM_IMAGE_TARGET) writeonly uniform image2D u_light_level;
layout(r32f, binding = SAM_IMAGE_DEPTH) writeonly uniform image2D u_depth_level;
uniform sampler2D u_light_mips; // bilinear within a level, clamped to the edge
uniform sampler2D u_depth_mips;
uniform float u_above; // the level read: the one written minus 1

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(u_light_level);
    if (p.x >= size.x || p.y >= size.y)
        return;
    vec2 at = (vec2(p) + 0.5) / vec2(size);
    imageStore(u_light_level, p, textureLod(u_light_mips, at, u_above));
    imageStore(u_depth_level, p, textureLod(u_depth_mips, at, u_above));
}
