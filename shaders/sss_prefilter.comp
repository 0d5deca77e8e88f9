#version 430 core
// Before each pass of the screen-space blur: the light entering the surface
// and its depth, both times the pixel's coverage (1 on the object, 0 on the
// background), into level 0 of two mipmapped textures. Their mipmaps let a
// tap stand for its whole share of the kernel: a tap many pixels from its
// neighbours that reads one pixel switches at once from the surface to the
// centre's colour as it crosses a silhouette, and draws a copy of every
// silhouette and shadow edge at each tap's offset (marble and milk close
// up, where the kernel spans hundreds of pixels).
#include "sam_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = SAM_IMAGE_SOURCE) readonly uniform image2D u_source;
layout(rgba32f, binding = SAM_IMAGE_TARGET) writeonly uniform image2D u_light; // rgb x coverage, coverage
layout(r32f, binding = SAM_IMAGE_DEPTH) writeonly uniform image2D u_depth;     // depth x coverage

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= imageSize(u_source).x || p.y >= imageSize(u_source).y)
        return;
    vec4 s = imageLoad(u_source, p);
    float coverage = s.a > 0.0 ? 1.0 : 0.0;
    imageStore(u_light, p, vec4(s.rgb * coverage, coverage));
    imageStore(u_depth, p, vec4(s.a * coverage));
}
