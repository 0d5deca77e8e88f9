#version 430 core
// Texture-space diffusion, step 2: one separable pass of d'Eon's 7-tap
// Gaussian with the tap spacing set to the standard deviation this level
// adds, in mm, turned into texels by the stretch map. Each level blurs the
// previous one by the variance it lacks.
//
// Taps fall between texels and are read bilinearly: rounding them to whole
// texels would collapse a narrow Gaussian on a coarse (depth-sized) atlas.
// A tap that falls off the texel's chart, into empty atlas or onto another
// chart, is found on the surface instead (tsd_cross.glsl): across a UV
// seam, the light of the chart on the other side. Where the surface ends
// (or for culled and clipped texels, alpha 0) the centre stands in, so
// light neither leaks into nor vanishes through the atlas's empty space;
// with a bilinear read that is rgb + (1 - alpha) centre, since empty
// texels hold zero.
//
// Two dispatches per pass: the first blurs every texel whose taps all
// stay on its chart and lists the others; the second (SAM_TSD_LISTED, an
// indirect dispatch over the list) blurs those, crossings and all, so that
// texels on a chart do not wait in a SIMD group or warp for one that
// walks. That saves about a seventh of a marble ear's render on llvmpipe;
// where the Gaussians are wide against the charts nearly every texel
// walks, and the walks themselves are the cost (docs/performance.md).
#include "sam_bindings.h"
#ifdef SAM_TSD_LISTED
layout(local_size_x = 64) in;
#else
layout(local_size_x = 8, local_size_y = 8) in;
#endif

// The texels left to the second dispatch: its indirect dispatch
// arguments (groups of 64, 1, 1), their count, then each texel as
// x | y << 16.
layout(std430, binding = SAM_B_TSD_DEFERRED) buffer Deferred {
    uvec3 deferred_groups;
    uint deferred_count;
    uint deferred[];
};

uniform sampler2D u_source;   // linear filtering, clamped to the edge
uniform sampler2D u_level;    // the level's input: the second pass's source is the first's output
layout(rgba32f, binding = SAM_IMAGE_TARGET) writeonly uniform image2D u_target;
// Stretch: mm per texel along u and v, then the covering triangle + 1 (0: none).
layout(rgba32f, binding = SAM_IMAGE_STRETCH) readonly uniform image2D u_stretch;
uniform int u_cross;         // 1: taps off the chart follow the surface
#include "tsd_cross.glsl"

uniform ivec2 u_direction;
uniform ivec2 u_size;        // the atlas's used corner (depth-sized atlases use less than the image)
uniform float u_sigma_mm;

const float WEIGHT[7] = float[7](0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006);
// The weights' own variance at unit spacing is sum w k^2 = 1.08, not 1:
// spacing taps by sigma / sqrt(1.08) adds exactly sigma^2.
const float SPACING = 0.9622504486493763;
// sin(10 degrees): a chart whose u is turned further from the centre's u
// carried across gets the first pass again (first_pass_at).
const float TURNED = 0.17364817766693;

// The second pass reads the first's output, blurred along each chart's own
// u. A tap that crossed onto a chart turned another way (packers turn
// charts) would read light blurred along the wrong line: there the first
// pass is done again from its input, along the centre's u carried across
// (`side_texels`, texels per mm), on that chart (`chart`), the landing
// point standing in for its taps off it.
vec4 first_pass_at(vec2 at, vec2 side_texels, uint chart, vec2 texel, vec2 lo, vec2 hi)
{
    vec4 land = textureLod(u_level, clamp(at * texel, lo, hi), 0.0);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 7; ++k) {
        vec2 q = at + side_texels * (float(k - 3) * SPACING * u_sigma_mm);
        uint t = cross_triangle_at(q, u_size);
        vec4 v = t > 0u && crossings[t - 1u].w == chart ? textureLod(u_level, clamp(q * texel, lo, hi), 0.0) : vec4(0.0);
        sum += WEIGHT[k] * (v.rgb + (1.0 - v.a) * land.rgb);
    }
    return vec4(sum, land.a);
}

// Blurs texel p into u_target; returns true where it leaves p to the
// second dispatch instead (a tap off its chart, in the first dispatch).
bool blur(ivec2 p)
{
    vec4 centre = texelFetch(u_source, p, 0);
    // Culled, clipped and empty texels: nothing to blur (the optimisations'
    // saving), and nothing the mesh will read.
    if (centre.a <= 0.0) {
        imageStore(u_target, p, centre);
        return false;
    }
    vec3 stretch = imageLoad(u_stretch, p).xyz;
    float mm = u_direction.x != 0 ? stretch.x : stretch.y;
    float step_texels = mm > 0.0 ? SPACING * u_sigma_mm / mm : 0.0;
    vec2 size = vec2(textureSize(u_source, 0)), texel = 1.0 / size;
    vec2 lo = 0.5 * texel, hi = (vec2(u_size) - 0.5) * texel;
    vec4 tap[7];
    uint centre_triangle = uint(stretch.z);
    uint chart = u_cross != 0 && centre_triangle > 0u ? crossings[centre_triangle - 1u].w : NO_CROSSING;
    bool off[7];
    bool any_off = false;
    for (int k = 0; k < 7; ++k) {
        vec2 at = vec2(p) + 0.5 + vec2(u_direction) * float(k - 3) * step_texels;
        tap[k] = textureLod(u_source, clamp(at * texel, lo, hi), 0.0);
        uint t = chart == NO_CROSSING || k == 3 ? 0u : cross_triangle_at(at, u_size);
        off[k] = chart != NO_CROSSING && k != 3 && !(t > 0u && crossings[t - 1u].w == chart);
        any_off = any_off || off[k];
    }
#ifndef SAM_TSD_LISTED
    if (any_off)
        return true;
#else
    if (any_off) {
        // The first pass's axis on the surface, for the second pass's taps that
        // land on charts turned another way: only where a tap leaves the chart.
        vec3 side = vec3(0.0), x0;
        if (u_direction.y != 0)
            cross_from_atlas(centre_triangle - 1u, vec2(p) + 0.5, vec2(1.0, 0.0), vec2(u_size), x0, side);
        // Per side, where the taps' line crossed its first seam: found by the
        // side's first tap off the chart (in the loop's order), and shared by
        // the others.
        CrossSeam crossed[2];
        crossed[0] = crossed[1] = CrossSeam(false, 0u, vec3(0.0), vec2(0.0), vec2(0.0), 0.0, 0.0, 0u, vec2(0.0));
        for (int k = 0; k < 7; ++k) {
            if (!off[k])
                continue;
            vec2 at = vec2(p) + 0.5 + vec2(u_direction) * float(k - 3) * step_texels;
            int s = k > 3 ? 1 : 0;
            uint landed = crossed[s].chart;
            vec2 side_texels = crossed[s].side_texels;
            float mm_out = abs(float(k - 3)) * step_texels * mm;
            if (!cross_after(crossed[s], mm_out, u_size, at)) {
                // From the texel, or past the chart across the side's first
                // seam, on from that seam (one call: each is inlined).
                CrossSeam first, c = crossed[s];
                bool resume = c.valid && mm_out >= c.done_mm;
                if (!cross_tap(resume ? c.triangle : centre_triangle, resume ? c.from : vec2(p) + 0.5,
                               resume ? c.dir : vec2(u_direction) * sign(float(k - 3)),
                               resume ? (mm_out - c.done_mm) * c.per_mm : abs(float(k - 3)) * step_texels,
                               resume ? 1.0 / c.per_mm : mm, u_size, resume ? c.side : side, at, landed, side_texels,
                               first)) {
                    tap[k] = vec4(0.0);
                    continue;
                }
                if (first.valid && !resume)
                    crossed[s] = first;
            }
            tap[k] = u_direction.y != 0 && abs(side_texels.y) > TURNED * length(side_texels)
                         ? first_pass_at(at, side_texels, landed, texel, lo, hi)
                         : textureLod(u_source, clamp(at * texel, lo, hi), 0.0);
        }
    }
#endif
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 7; ++k)
        sum += WEIGHT[k] * (tap[k].rgb + (1.0 - tap[k].a) * centre.rgb);
    imageStore(u_target, p, vec4(sum, 1.0));
    return false;
}

#ifdef SAM_TSD_LISTED
void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i < deferred_count)
        blur(ivec2(deferred[i] & 0xFFFFu, deferred[i] >> 16));
}
#else
// A group lists its texels with one atomic on the shared count: with one
// per texel, the widest Gaussian's passes, which list nearly every texel,
// would queue hundreds of thousands of atomics on one word.
shared uint group_count, group_base;

void main()
{
    if (gl_LocalInvocationIndex == 0u)
        group_count = 0u;
    memoryBarrierShared();
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    bool listed = p.x < u_size.x && p.y < u_size.y && blur(p);
    uint slot = listed ? atomicAdd(group_count, 1u) : 0u;
    memoryBarrierShared();
    barrier();
    if (gl_LocalInvocationIndex == 0u && group_count > 0u) {
        group_base = atomicAdd(deferred_count, group_count);
        atomicMax(deferred_groups.x, (group_base + group_count + 63u) / 64u);
    }
    memoryBarrierShared();
    barrier();
    if (listed)
        deferred[group_base + slot] = uint(p.x) | uint(p.y) << 16;
}
#endif
