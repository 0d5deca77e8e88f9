/*
 * sam_deform: analytic, animated deformers of a mesh's rest positions (the
 * scene files' "deformers", the runtime's deform pass), and their CPU
 * reference.
 *
 * A deformer maps a point p to a new point; a list of them applies in
 * order, each to the previous one's output. Every deformer has a strength
 * s(t) = sin(2 pi t / period_s) for period_s > 0 (periodic, 0 at t = 0),
 * or 1 when period_s = 0 (static). With a = axis, d = direction (for bend
 * made perpendicular to a), c = center, u = (p - c).a:
 *   bend:   the axis line through c curls, towards d, into a circular arc
 *           of curvature k = s angle / length (radians per model unit): the
 *           point at axis coordinate u turns by k u, and its offset along d
 *           and across both is carried with its cross-section (Barr 1984).
 *   twist:  rotation about the axis line through c by k u, k as for bend,
 *           counter-clockwise about a.
 *   squash: scale by f = 1 + s amount along a and by 1 / sqrt(f) across it,
 *           about c (volume preserving); |amount| < 1 keeps f > 0.
 *   wave:   p + d s amplitude sin(2 pi (p.a - speed t) / wavelength), a sine
 *           travelling along a at `speed` model units per second.
 *
 * sam_deform_prepare turns deformers and a time into sam_deform_step
 * values, which the CPU reference (sam_deform_positions) and the GPU pass
 * (shaders/deform.comp) evaluate with the same formulas. A step whose
 * strength makes it the identity is marked so and skipped by both, so a
 * pose with no effective deformer is the rest pose bit for bit.
 *
 * Plain data and pure functions; nothing here keeps global state.
 */
#ifndef SAM_DEFORM_H
#define SAM_DEFORM_H

#include "sam/sam_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Deformers a scene (and the runtime) accepts. */
#define SAM_DEFORM_MAX 8

typedef enum sam_deformer_type {
    SAM_DEFORM_BEND = 0,
    SAM_DEFORM_TWIST = 1,
    SAM_DEFORM_SQUASH = 2,
    SAM_DEFORM_WAVE = 3
} sam_deformer_type;

typedef struct sam_deformer {
    sam_deformer_type type;
    float axis[3];      /* unit; bend and twist: along which the angle grows; squash: the scaled axis;
                         * wave: the way the wave travels */
    float direction[3]; /* unit; bend: the way the ends curl (not parallel to axis); wave: displacement */
    float center[3];    /* bend, twist, squash: a point of the axis line, model units */
    float angle_deg;    /* bend, twist: the angle reached `length` units along the axis */
    float length;       /* bend, twist: > 0, model units */
    float amount;       /* squash: in (-1, 1) */
    float amplitude;    /* wave: model units */
    float wavelength;   /* wave: > 0, model units */
    float speed;        /* wave: model units per second */
    float period_s;     /* >= 0; 0: static */
} sam_deformer;

/* One deformer at one time, as both evaluators use it. */
typedef struct sam_deform_step {
    sam_deformer_type type;
    int identity;       /* 1: this step leaves every point exactly where it is */
    float axis[3];      /* unit */
    float direction[3]; /* unit; bend: perpendicular to axis */
    float center[3];
    /* bend, twist: k (radians per model unit), -, -;
     * squash: f, 1 / sqrt(f), -;
     * wave: displacement amplitude, 2 pi / wavelength, phase at p.a = 0 in [0, 2 pi) */
    float param[3];
} sam_deform_step;

/* The name in scene files ("bend", ...), or "unknown" outside the enum. */
const char *sam_deformer_type_name(sam_deformer_type type);

/* The strength s(t) described above. */
double sam_deform_strength(const sam_deformer *deformer, double time_s);

/* Fills steps[0..count) for time `time_s` from deformers[0..count)
 * (count <= SAM_DEFORM_MAX; both arrays the caller's). Returns 1 when any
 * step is not the identity, 0 when the pose is the rest pose. Deformers
 * are taken as sam_scene accepts them (unit vectors, bend's direction not
 * parallel to its axis, length and wavelength > 0, |amount| < 1). */
int sam_deform_prepare(const sam_deformer *deformers, size_t count, double time_s, sam_deform_step *steps);

/* Applies steps[0..step_count) in order to `count` points: out[3i..3i+2]
 * from in[3i..3i+2] (model units), in double precision. `in` and `out` may
 * be the same array; identity steps are skipped, so with only those `out`
 * is a copy of `in`. */
void sam_deform_positions(const sam_deform_step *steps, size_t step_count, const float *in, float *out,
                          size_t count);

#ifdef __cplusplus
}
#endif

#endif
