#version 430 core
// One pass of separable screen-space subsurface scattering (Jimenez et al.
// 2015): a 1D blur of the light entering the surface along u_direction,
// with the profile's kernel, its offsets in millimetres turned into pixels
// from each pixel's depth and the field of view. Taps on the background or
// across a depth jump larger than u_depth_jump fall back to the centre
// colour, so the blur follows the surface and never bleeds across objects.
// rgb: entering light; a: linear depth in model units (0 = background).
#include "sam_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = SAM_IMAGE_SOURCE) readonly uniform image2D u_source;
layout(rgba32f, binding = SAM_IMAGE_TARGET) writeonly uniform image2D u_target;

uniform ivec2 u_direction;
uniform int u_taps;
uniform float u_offset_mm[33];
uniform vec3 u_weight[33];
uniform float u_mm_per_unit;
uniform float u_pixels_per_unit_at_depth_one; // height / (2 tan(fov/2))
uniform float u_depth_jump;                   // model units

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(u_source);
    if (p.x >= size.x || p.y >= size.y)
        return;
    vec4 centre = imageLoad(u_source, p);
    if (centre.a <= 0.0) {
        imageStore(u_target, p, centre);
        return;
    }
    // Pixels per millimetre at this depth.
    float pixels_per_mm = u_pixels_per_unit_at_depth_one / (centre.a * u_mm_per_unit);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < u_taps; ++k) {
        float offset = u_offset_mm[k] * pixels_per_mm;
        ivec2 q = clamp(p + ivec2(round(vec2(u_direction) * offset)), ivec2(0), size - 1);
        vec4 tap = imageLoad(u_source, q);
        if (tap.a <= 0.0 || abs(tap.a - centre.a) > u_depth_jump)
            tap = centre;
        sum += u_weight[k] * tap.rgb;
    }
    imageStore(u_target, p, vec4(sum, centre.a));
}
