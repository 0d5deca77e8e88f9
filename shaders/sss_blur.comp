#version 430 core
// One pass of separable screen-space subsurface scattering (Jimenez et al.
// 2015): a 1D blur of the light entering the surface along u_direction,
// with the profile's kernel, its offsets in millimetres turned into pixels
// from each pixel's depth and the field of view. Taps on the background
// fall back to the centre colour, and so, smoothly, do taps across a depth
// difference approaching u_depth_jump, so the blur follows the surface and
// never bleeds across objects.
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

// The light at pixel q, or the centre's where q is background; across a
// depth difference it fades to the centre's, smoothly from half the jump
// to the jump. A tap cut off at the jump itself comes back at every row
// where some tap's depth difference crosses it, and on a surface seen at
// a slant each such row was a band.
vec3 tap_at(ivec2 q, ivec2 size, vec4 centre)
{
    vec4 tap = imageLoad(u_source, clamp(q, ivec2(0), size - 1));
    if (tap.a <= 0.0)
        return centre.rgb;
    return mix(tap.rgb, centre.rgb, smoothstep(0.5 * u_depth_jump, u_depth_jump, abs(tap.a - centre.a)));
}

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
        // A tap between pixels reads both, weighted by distance: rounded to
        // the nearest pixel, a tap jumps a whole pixel where the depth
        // crosses a rounding boundary, and each such row or column of the
        // picture showed as a band across smooth surfaces.
        float offset = u_offset_mm[k] * pixels_per_mm, base = floor(offset), f = offset - base;
        sum += u_weight[k] * mix(tap_at(p + u_direction * int(base), size, centre),
                                 tap_at(p + u_direction * (int(base) + 1), size, centre), f);
    }
    imageStore(u_target, p, vec4(sum, centre.a));
}
