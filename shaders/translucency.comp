#version 430 core
// SAM translucency (Maisch and Ropinski eq. 12) with temporal smoothing
// (eq. 17-18): T(v) = sum_k L_d(b_k) K_k, K_k = K'_k F'_b R_d(|v_b - v|)
// (eq. 15); then T <- (1 - alpha) T_prev + alpha T. On a deformed pose K
// is carried from rest by the fans' quadrature (fan_form_factor.glsl), and
// a vertex sample that has left the back side (eq. 13-14 fail at the pose
// by more than float noise, back_side.glsl) contributes 0: its K would
// add light through the front. It stays stored, so it counts again when
// the pose brings it back (walk.comp replaces it when it can). A cut
// map's sample may be a tree node (index >= u_vertex_count), read from
// the node pass's output as a vertex would be: its centroid, area and L_d
// (moved by the sample's tau along the node's split, towards where its
// light comes from); posed, its K is the rest K times eq. 15's change
// from the rest centroid to the posed one, that change held within
// [1/4, 4]. Eq. 15 alone multiplies K' by R_d at the posed
// centroid; a node's K' is large when its centroid lies far out in R_d's
// tail while its near members carry the light, and there a small move of
// the centroid multiplied T a billionfold (a bent ear, tests/test_gl_walk.c).
// A node is not dropped when its centroid fails eq. 13-14 at the pose, as
// a vertex is: most nodes of a cut straddle the back side's edge (their
// members on the back side carry the K) and fail the test at rest already,
// so dropping them made T fall by up to its whole value as soon as a
// pose began.
//
// With SAM_REST_K the rest pose's K of every sample is read from the
// rest-K pass's buffer (rest_k.comp) instead of evaluated: the rest pass
// then sums L_d K alone, and a posed node's rest K is read, not evaluated.
#include "sam_bindings.h"
#include "profile.glsl"

layout(local_size_x = 64) in;

#include "sample.glsl"

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = SAM_B_SAMPLES) readonly buffer Samples { uint samples[]; };
layout(std430, binding = SAM_B_FAN_AREAS) readonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = SAM_B_IRRADIANCE) readonly buffer Irradiance { vec4 irradiance[]; };
layout(std430, binding = SAM_B_TRANSLUCENCY) buffer Translucency { vec4 translucency[]; };
#include "node.glsl"
layout(std430, binding = SAM_B_NODES) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = SAM_B_SAMPLE_TAU) readonly buffer SampleTau { float sample_tau[]; };
#ifdef SAM_POSED
layout(std430, binding = SAM_B_REST_POSITIONS) readonly buffer RestPositions { vec4 rest_positions[]; };
layout(std430, binding = SAM_B_REST_NODES) readonly buffer RestNodes { Node rest_nodes[]; };
#endif
#ifdef SAM_REST_K
layout(std430, binding = SAM_B_REST_K) readonly buffer RestK { uint rest_k[]; }; // K, not K'
#endif
#if defined(SAM_POSED) && !defined(SAM_POSED_EQ15)
layout(std430, binding = SAM_B_ADJ_OFFSETS) readonly buffer AdjOffsets { uint adj_offsets[]; };
layout(std430, binding = SAM_B_ADJACENCY) readonly buffer Adjacency { uint adjacency[]; };
#endif
#ifdef SAM_POSED
#include "back_side.glsl"
#endif

uniform uint u_vertex_count;
uniform uint u_samples;       // samples used, <= u_stride
uniform float u_mm_per_unit;
uniform float u_alpha;        // 1 - (1e-10)^dt; 1 replaces the history

// Compiled three times for each sam_rest_k mode: the rest pose's program
// (K by eq. 15, which is K itself there, or read from rest_k) and, with
// SAM_POSED, a deformed pose's, which skips samples off the back side and
// carries K from rest, or with SAM_POSED_EQ15 too takes eq. 15 as the
// paper does (cheaper, worse under shear; see sam_runtime_set_posed_k).
// Programs, not branches: a branch made llvmpipe's rest pose pay about 2x
// for the posed path it never took.
#if defined(SAM_POSED) && !defined(SAM_POSED_EQ15)
#include "fan_form_factor.glsl"
// The vertex samples in a row's first 3 slots (QUADRATURE_MASK), the best
// (rows are sorted by K), carry K by the fans' quadrature, about 25 R_d
// each; the rest take eq. 15 at the pose, one. A cut map's row can be 32
// vertices (sam_build_cut.c lists them where they carry the light), and
// the quadrature for all of them cost an animated frame 5 to 8 times the
// paper's map of 3 on llvmpipe; with 3, 1.2 to 1.3 times. On a twisted
// skin ear (builder 1.2) T erred by 0.059 against a fresh build, where the
// quadrature for every sample gave 0.056 and eq. 15's change in distance
// for every one 0.075 (tests/test_gl_walk.c, docs/runtime.md).
#define QUADRATURE_MASK 7u // slots 0, 1 and 2
#endif
#include "eq15_k.glsl"

// L_d where sample k of vertex v takes its light: a vertex's own, or a
// node's to first order where the sample's light comes from (STAU).
vec3 sample_light(uint v, uint k, uint index)
{
    if (index < u_vertex_count)
        return irradiance[index].rgb;
    Node d = nodes[index - u_vertex_count];
    return max(d.ld.rgb + sample_tau[sample_slot(v, k, u_vertex_count)] * d.ld_diff.rgb, vec3(0.0));
}

void store(uint v, vec3 sum)
{
    // mix() may be x + (y - x) a, which with a = 1 leaves the history's last
    // bits in: a reset must not depend on what came before.
    translucency[v] = vec4(u_alpha >= 1.0 ? sum : mix(translucency[v].rgb, sum, u_alpha), 1.0);
}

#if !defined(SAM_POSED) && defined(SAM_REST_K)
void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 sum = vec3(0.0);
    for (uint k = 0u; k < u_samples; ++k) {
        Sample s = SAMPLE_LOAD(rest_k, sample_slot(v, k, u_vertex_count));
        if (s.index == 0xFFFFFFFFu)
            break;
        sum += sample_light(v, k, s.index) * sample_k(s);
    }
    store(v, sum);
}
#elif !defined(SAM_POSED)
void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = positions[v].xyz;
    vec3 sum = vec3(0.0);
    for (uint k = 0u; k < u_samples; ++k) {
        Sample s = SAMPLE_LOAD(samples, sample_slot(v, k, u_vertex_count));
        if (s.index == 0xFFFFFFFFu)
            break;
        sum += sample_light(v, k, s.index) * eq15_k(s.index, sample_k(s), p);
    }
    store(v, sum);
}
#else
void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = positions[v].xyz, n = normals[v].xyz;
    vec3 sum = vec3(0.0);
    // Nodes first; the vertex samples' slots are noted and summed after, in
    // a loop that runs only as often as this vertex has them. In one loop
    // llvmpipe ran the carried K's quadrature for every node sample too
    // (its branches run both ways under a mask), while a cut map's vertex
    // samples are few: the walk's adoptions.
    uint slots_low = 0u, slots_high = 0u; // slots 0-31 and 32-63 (SAMFILE_MAX_SAMPLES_PER_VERTEX)
    for (uint k = 0u; k < u_samples; ++k) {
        Sample s = SAMPLE_LOAD(samples, sample_slot(v, k, u_vertex_count));
        if (s.index == 0xFFFFFFFFu)
            break;
        if (s.index < u_vertex_count) {
            if (k < 32u)
                slots_low |= 1u << k;
            else
                slots_high |= 1u << (k - 32u);
            continue;
        }
        vec3 kprime = sample_k(s);
        vec4 q = nodes[s.index - u_vertex_count].centroid_area;
#ifdef SAM_REST_K
        // The walk never moves a node from its slot, so the slot's rest K is its own.
        Sample r = SAMPLE_LOAD(rest_k, sample_slot(v, k, u_vertex_count));
        vec3 k_rest = sample_k(r);
#else
        vec4 rest = rest_nodes[s.index - u_vertex_count].centroid_area;
        vec3 k_rest = kprime * rest.w * profile_rd(u_mm_per_unit * distance(rest.xyz, rest_positions[v].xyz));
#endif
        vec3 k_pose = kprime * q.w * profile_rd(u_mm_per_unit * distance(q.xyz, p));
        vec3 change = clamp(k_pose / max(k_rest, vec3(1e-30)), vec3(0.25), vec3(4.0));
        sum += sample_light(v, k, s.index) * k_rest * change;
    }
#ifdef SAM_POSED_EQ15
    for (uint w = 0u; w < 2u; ++w)
        for (uint bits = w == 0u ? slots_low : slots_high; bits != 0u; bits &= bits - 1u) {
            Sample s = SAMPLE_LOAD(samples, sample_slot(v, uint(findLSB(bits)) + 32u * w, u_vertex_count));
            vec3 q = positions[s.index].xyz;
            if (sample_on_back_side(s.index, p, n))
                sum += irradiance[s.index].rgb * sample_k(s) * fan_area[s.index] *
                       profile_rd(u_mm_per_unit * distance(q, p));
        }
#else
    // The quadrature's slots in a loop of their own, then the others: in one
    // loop the invocations of a SIMD group reach the two kinds in different
    // iterations, and llvmpipe ran both under a mask.
    for (uint bits = slots_low & QUADRATURE_MASK; bits != 0u; bits &= bits - 1u) {
        Sample s = SAMPLE_LOAD(samples, sample_slot(v, uint(findLSB(bits)), u_vertex_count));
        if (sample_on_back_side(s.index, p, n))
            sum += irradiance[s.index].rgb * posed_form_factor(v, s.index, sample_k(s));
    }
    for (uint w = 0u; w < 2u; ++w)
        for (uint bits = w == 0u ? slots_low & ~QUADRATURE_MASK : slots_high; bits != 0u; bits &= bits - 1u) {
            Sample s = SAMPLE_LOAD(samples, sample_slot(v, uint(findLSB(bits)) + 32u * w, u_vertex_count));
            // Eq. 15 at the pose: a vertex's K' is the builder's for one
            // pair of fans, not a far centroid's, and does not blow up as a
            // node's would (docs/deformation.md). Written out rather than
            // eq15_k, whose node branch this loop never needs.
            vec3 q = positions[s.index].xyz;
            if (sample_on_back_side(s.index, p, n))
                sum += irradiance[s.index].rgb * sample_k(s) * fan_area[s.index] *
                       profile_rd(u_mm_per_unit * distance(q, p));
        }
#endif
    store(v, sum);
}
#endif
