#version 430 core
// Texture-space diffusion, step 3: the sum of the Gaussian levels with the
// material's 8-Gaussian fit weights (each over the total reflectance, since
// the entering light already carries it).
#include "sam_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = SAM_IMAGE_SOURCE) readonly uniform image2D u_level;
layout(rgba32f, binding = SAM_IMAGE_TARGET) uniform image2D u_sum;

uniform vec3 u_weight;
uniform int u_first;
uniform ivec2 u_size;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    vec4 level = imageLoad(u_level, p);
    vec3 prev = u_first != 0 ? vec3(0.0) : imageLoad(u_sum, p).rgb;
    imageStore(u_sum, p, vec4(prev + u_weight * level.rgb, level.a));
}
