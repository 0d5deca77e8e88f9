#version 430 core
// Texture-space diffusion, step 2: one separable pass of d'Eon's 7-tap
// Gaussian with the tap spacing set to the standard deviation this level
// adds, in mm, turned into texels by the stretch map. Each level blurs the
// previous one by the variance it lacks.
//
// Taps fall between texels and are read bilinearly: rounding them to whole
// texels would collapse a narrow Gaussian on a coarse (depth-sized) atlas.
// Off a chart (alpha 0: empty, culled or clipped texels) the centre stands
// in, so light neither leaks into nor vanishes through the atlas's empty
// space; with a bilinear read that is rgb + (1 - alpha) centre, since
// empty texels hold zero.
#include "sam_bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

uniform sampler2D u_source;   // linear filtering, clamped to the edge
layout(rgba32f, binding = SAM_IMAGE_TARGET) writeonly uniform image2D u_target;
layout(rgba32f, binding = SAM_IMAGE_STRETCH) readonly uniform image2D u_stretch;

uniform ivec2 u_direction;
uniform ivec2 u_size;        // the atlas's used corner (depth-sized atlases use less than the image)
uniform float u_sigma_mm;

const float WEIGHT[7] = float[7](0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006);
// The weights' own variance at unit spacing is sum w k^2 = 1.08, not 1:
// spacing taps by sigma / sqrt(1.08) adds exactly sigma^2.
const float SPACING = 0.9622504486493763;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    vec4 centre = texelFetch(u_source, p, 0);
    // Culled, clipped and empty texels: nothing to blur (the optimisations'
    // saving), and nothing the mesh will read.
    if (centre.a <= 0.0) {
        imageStore(u_target, p, centre);
        return;
    }
    vec2 mm_per_texel = imageLoad(u_stretch, p).xy;
    float mm = u_direction.x != 0 ? mm_per_texel.x : mm_per_texel.y;
    float step_texels = mm > 0.0 ? SPACING * u_sigma_mm / mm : 0.0;
    vec2 texel = 1.0 / vec2(textureSize(u_source, 0));
    vec2 lo = 0.5 * texel, hi = (vec2(u_size) - 0.5) * texel;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 7; ++k) {
        vec2 at = (vec2(p) + 0.5 + vec2(u_direction) * float(k - 3) * step_texels) * texel;
        vec4 tap = textureLod(u_source, clamp(at, lo, hi), 0.0);
        sum += WEIGHT[k] * (tap.rgb + (1.0 - tap.a) * centre.rgb);
    }
    imageStore(u_target, p, vec4(sum, 1.0));
}
