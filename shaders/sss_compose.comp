#version 430 core
// After the blur: radiance = blurred entering light * factor + specular.
#include "sam_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = SAM_IMAGE_BLURRED) readonly uniform image2D u_blurred;
layout(rgba32f, binding = SAM_IMAGE_FACTOR) readonly uniform image2D u_factor;
layout(rgba32f, binding = SAM_IMAGE_SPECULAR) readonly uniform image2D u_specular;
layout(rgba32f, binding = SAM_IMAGE_COMPOSED) writeonly uniform image2D u_out;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(u_out);
    if (p.x >= size.x || p.y >= size.y)
        return;
    vec4 b = imageLoad(u_blurred, p);
    if (b.a <= 0.0) {
        imageStore(u_out, p, vec4(0.0));
        return;
    }
    imageStore(u_out, p, vec4(b.rgb * imageLoad(u_factor, p).rgb + imageLoad(u_specular, p).rgb, 1.0));
}
