#version 430 core
// The sample walk of Maisch and Ropinski Sec. 3.4: poses change little
// between frames, so a vertex's better back-side vertices are found in the
// one-rings of its current samples. A ring neighbour c of sample s that is
// on the back side at the pose (eq. 13-14) and not chosen yet replaces the
// sample with the smallest approximated K when its own is larger.
//
// The walk ranks by eq. 15's K' F'_i R_d(|v_i - v_o|) at the pose, as the
// builder ranks its candidates by the point estimate; the translucency pass
// sums a better-carried K (fan_form_factor.glsl). Ranking by that K instead
// made the walk 20 times slower on llvmpipe and moved the walked T's error
// against a fresh build by at most 0.0013 on the poses of
// tests/test_gl_walk.c. An adopted vertex gets K' = 1: its rest K is taken
// to be the point estimate. K' is the part of K that estimate misses for
// one particular pair of fans; carried over to another vertex it is
// meaningless. Handing on the K' of the replaced slot or of the sample it
// was reached from did: on a twisted ear a far sample's large K' landed on
// a near vertex and T came out 5.6 times the reference's RMS, against 0.12
// with K' = 1 (both with eq. 15's posed K).
//
// Each invocation reads other vertices' positions, normals and fan areas
// and writes only its own samples, so there is no race and the order of
// invocations does not matter; seam copies of one vertex carry the same
// position, normal, ring and samples, so they stay identical. The samples
// stay sorted by approximated K, best first, so a translucency pass using
// fewer samples takes the best. Samples off the back side score 0 (the
// translucency pass skips them) and are the first replaced.
#include "sam_bindings.h"
#include "profile.glsl"

layout(local_size_x = 64) in;

#define MAX_SAMPLES 64
#define NO_SAMPLE 0xFFFFFFFFu
// The walk's rings are those of a row's first WALK_FROM vertex samples, the
// best (rows are sorted by K): the paper's map has 3, and walking from all
// of a cut map's row of 32 vertices (sam_build_cut.c lists them where they
// carry the light) made the walk most of an animated frame. On a twisted
// skin ear the walked T's error against a fresh build went from 0.045 to
// 0.048 (tests/test_gl_walk.c).
#define WALK_FROM 3u
// Ring vertices a row lacks, kept per walk: three rings of valence up to
// 16 hold all of theirs; past that the rest wait for the next frame.
#define MAX_CANDIDATES 48u

#include "sample.glsl"

layout(std430, binding = SAM_B_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = SAM_B_NORMALS) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = SAM_B_SAMPLES) buffer Samples { uint samples[]; };
layout(std430, binding = SAM_B_FAN_AREAS) readonly buffer FanAreas { float fan_area[]; };
layout(std430, binding = SAM_B_ADJ_OFFSETS) readonly buffer AdjOffsets { uint adj_offsets[]; };
layout(std430, binding = SAM_B_ADJACENCY) readonly buffer Adjacency { uint adjacency[]; };
layout(std430, binding = SAM_B_NODE_PARENTS) readonly buffer Parents { uint parents[]; };

uniform uint u_vertex_count;
uniform uint u_stride;
uniform float u_mm_per_unit;
// 1 for a cut map: each of its rows counts every back-side vertex in reach
// once (its nodes, their K handed down the tree where the light comes
// from, its listed vertices with K scaled to carry the tail), and a spare
// slot is one its cut did not need. Its walk fills no spare slot and
// replaces only vertex samples the pose took off the back side: adopting
// a vertex beside them counted its light twice, and swapping a builder's
// sample for one estimated larger changed T at a pose a hair from rest
// by a third on a torus in skin (tests/test_gl_walk.c).
uniform uint u_cut_map;

Sample chosen[MAX_SAMPLES];
float score[MAX_SAMPLES];

// A stored sample is dead once sample_on_back_side fails, as the
// translucency pass drops it; a candidate must pass the stricter
// candidate_on_back_side, so that rounding neither adopts nor drops a
// vertex on the back side's edge.
#include "back_side.glsl"

// The mean over R, G, B of K = K' F'_i R_d(|v_i - v_o|) (eq. 15).
// A cut map's tree nodes stay as built: the walk moves vertex samples
// only, and never onto a vertex that a node of the same cut already holds
// (it would count twice).
bool is_node(uint i)
{
    return i != NO_SAMPLE && i >= u_vertex_count;
}

bool under_cut_node(uint c)
{
    for (uint a = parents[c]; a != NO_SAMPLE; a = parents[u_vertex_count + a])
        for (uint j = 0u; j < u_stride; ++j)
            if (chosen[j].index == u_vertex_count + a)
                return true;
    return false;
}

float approximate_k(uint i, vec3 kprime, vec3 p)
{
    vec3 k = kprime * fan_area[i] * profile_rd(u_mm_per_unit * distance(positions[i].xyz, p));
    return (k.r + k.g + k.b) / 3.0;
}

// Scores every vertex slot of the row (score[] holds the others' already):
// eq. 15's K at the pose, or 0 off the back side.
void score_vertex_slots(uint slots_low, uint slots_high, vec3 p, vec3 n)
{
    for (uint w = 0u; w < 2u; ++w)
        for (uint bits = w == 0u ? slots_low : slots_high; bits != 0u; bits &= bits - 1u) {
            uint k = uint(findLSB(bits)) + 32u * w, i = chosen[k].index;
            if (sample_on_back_side(i, p, n))
                score[k] = approximate_k(i, sample_k(chosen[k]), p);
        }
}

bool taken(uint c)
{
    bool found = false;
    for (uint j = 0u; j < u_stride; ++j)
        found = found || chosen[j].index == c;
    return found;
}

uint worst_slot()
{
    uint worst = 0u;
    for (uint j = 1u; j < u_stride; ++j)
        if (score[j] < score[worst])
            worst = j;
    return worst;
}

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_vertex_count)
        return;
    vec3 p = positions[v].xyz, n = normals[v].xyz;
    // The vertex samples' slots, up to MAX_SAMPLES: they alone are scored
    // by R_d and walked from, each in a loop over these slots only. Loops
    // over every slot with a branch made llvmpipe run the vertex work under
    // a mask for a cut map's nodes too, which are nearly all its samples.
    uint slots_low = 0u, slots_high = 0u; // slots 0-31 and 32-63
    bool cut = false; // the row holds tree nodes
    for (uint k = 0u; k < u_stride; ++k) {
        chosen[k] = SAMPLE_LOAD(samples, sample_slot(v, k, u_vertex_count));
        uint i = chosen[k].index;
        cut = cut || is_node(i);
        score[k] = i == NO_SAMPLE ? -1.0 : is_node(i) ? 3.0e38 : 0.0;
        if (i != NO_SAMPLE && !is_node(i)) {
            if (k < 32u)
                slots_low |= 1u << k;
            else
                slots_high |= 1u << (k - 32u);
        }
    }
    if (u_cut_map != 0u) {
        bool dead = false;
        for (uint w = 0u; w < 2u; ++w)
            for (uint bits = w == 0u ? slots_low : slots_high; bits != 0u; bits &= bits - 1u)
                dead = dead || !sample_on_back_side(chosen[uint(findLSB(bits)) + 32u * w].index, p, n);
        if (!dead)
            return; // the row stays as stored
    }
    // First the ring vertices the row lacks, then, only if there are any,
    // the row's scores (an R_d per vertex sample) and the adoptions. A row
    // the builder listed (32 vertices) mostly holds its best samples' rings
    // already, and scoring it was most of the walk there; such a row keeps
    // its order until the walk adopts into it. Scoring inside the ring
    // loop, where the first candidate came, made llvmpipe score a SIMD
    // group's rows once per lane that found one.
    uint candidates[MAX_CANDIDATES];
    uint candidate_count = 0u;
    // Walk from the samples as they were, not from this frame's adoptions
    // (the candidates are all found before any): one ring per frame; from
    // the first WALK_FROM vertex slots only.
    uint walked = 0u;
    for (uint w = 0u; w < 2u; ++w)
        for (uint bits = w == 0u ? slots_low : slots_high; bits != 0u && walked++ < WALK_FROM; bits &= bits - 1u) {
            uint from = chosen[uint(findLSB(bits)) + 32u * w].index;
            for (uint a = adj_offsets[from]; a < adj_offsets[from + 1u] && candidate_count < MAX_CANDIDATES; ++a) {
                uint c = adjacency[a];
                // A row of vertices only (the builder listed its best
                // ones) has no node to ask: the ancestors' loop over every
                // slot was most of the walk there.
                if (!taken(c) && candidate_on_back_side(c, p, n) && !(cut && under_cut_node(c)))
                    candidates[candidate_count++] = c;
            }
        }
    if (candidate_count == 0u)
        return; // nothing adopted: the row stays as stored
    score_vertex_slots(slots_low, slots_high, p, n);
    if (u_cut_map != 0u)
        for (uint k = 0u; k < u_stride; ++k)
            score[k] = score[k] == 0.0 ? 0.0 : 3.0e38; // only the dead are replaced
    uint worst = worst_slot();
    for (uint j = 0u; j < candidate_count; ++j) {
        uint c = candidates[j];
        if (taken(c)) // in two rings
            continue;
        vec3 kp = vec3(1.0);
        float s = approximate_k(c, kp, p);
        if (s > score[worst]) {
            chosen[worst] = make_sample(c, kp);
            score[worst] = s;
            worst = worst_slot();
        }
    }
    // Insertion sort, best first; empty slots (score -1) end up last, as
    // the translucency pass expects. A cut map's list stays in place: its
    // nodes' tau (STAU) belong to their slots, and adoptions fill the first
    // empty slot, so pads stay last without sorting.
    for (uint k = 1u; k < u_stride && !cut; ++k)
        for (uint j = k; j > 0u && score[j] > score[j - 1u]; --j) {
            Sample t = chosen[j];
            chosen[j] = chosen[j - 1u];
            chosen[j - 1u] = t;
            float f = score[j];
            score[j] = score[j - 1u];
            score[j - 1u] = f;
        }
    for (uint k = 0u; k < u_stride; ++k)
        SAMPLE_STORE(samples, sample_slot(v, k, u_vertex_count), chosen[k]);
}
