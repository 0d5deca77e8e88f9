#version 430 core
// One pass of separable screen-space subsurface scattering (Jimenez et al.
// 2015): a 1D blur of the light entering the surface along u_direction,
// with the profile's kernel, its offsets in millimetres turned into pixels
// from each pixel's depth and the field of view. Taps on the background
// fall back to the centre colour, and so, smoothly, do taps across a depth
// difference approaching u_depth_jump, so the blur follows the surface and
// never bleeds across objects.
// u_source: rgb entering light; a: linear depth in model units (0 =
// background). u_light_mips and u_depth_mips: the same, times coverage
// (sss_prefilter.comp), mipmapped.
#include "sam_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = SAM_IMAGE_SOURCE) readonly uniform image2D u_source;
layout(rgba32f, binding = SAM_IMAGE_TARGET) writeonly uniform image2D u_target;
uniform sampler2D u_light_mips; // trilinear, clamped to the edge
uniform sampler2D u_depth_mips;

uniform ivec2 u_direction;
uniform int u_taps;
uniform float u_offset_mm[33];
uniform float u_share_mm[33]; // the stretch of the kernel's axis each tap stands for
uniform vec3 u_weight[33];
uniform float u_mm_per_unit;
uniform float u_pixels_per_unit_at_depth_one; // height / (2 tan(fov/2))
uniform float u_depth_jump;                   // model units

// The light around `at` (texture coordinates), averaged over about
// 2^lod pixels, where it covers the object; the centre's where it does not.
// Across a depth difference it fades to the centre's, smoothly from half
// the jump to the jump: a tap cut off at the jump itself comes back at
// every row where some tap's depth difference crosses it, and on a surface
// seen at a slant each such row was a band. At lod 0 this is the linear
// interpolation of the two pixels the tap falls between: rounded to the
// nearest pixel, a tap jumps a whole pixel where the depth crosses a
// rounding boundary, and each such row or column showed as a band.
vec3 tap_at(vec2 at, float lod, vec4 centre)
{
    vec4 light = textureLod(u_light_mips, at, lod);
    if (light.a <= 1e-6)
        return centre.rgb;
    float depth = textureLod(u_depth_mips, at, lod).r / light.a;
    float keep = light.a * (1.0 - smoothstep(0.5 * u_depth_jump, u_depth_jump, abs(depth - centre.a)));
    return mix(centre.rgb, light.rgb / light.a, keep);
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
    vec2 texel = 1.0 / vec2(size);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < u_taps; ++k) {
        vec2 at = (vec2(p) + 0.5 + vec2(u_direction) * (u_offset_mm[k] * pixels_per_mm)) * texel;
        float lod = log2(max(u_share_mm[k] * pixels_per_mm, 1.0));
        sum += u_weight[k] * tap_at(at, lod, centre);
    }
    imageStore(u_target, p, vec4(sum, centre.a));
}
