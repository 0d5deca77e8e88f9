/*
 * sam_rng: the small deterministic random stream (PCG32, O'Neill's XSH-RR
 * output) that the builder's form factors and the ground truth's samples
 * draw from. A stream is keyed by a seed and a pair of integers and its
 * numbers depend on those alone, so results do not change with the thread
 * count or the order work is done in. A stream is plain data; no global
 * state.
 */
#ifndef SAM_RNG_H
#define SAM_RNG_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sam_rng {
    uint64_t state;
} sam_rng;

/* SplitMix64's finaliser: a bijection of 64-bit values in which nearby
 * inputs give unrelated outputs (for seeds and key hashing). */
uint64_t sam_rng_mix(uint64_t x);

/* Starts the stream for the pair (a, b) under `seed`. Distinct pairs give
 * independent streams; the same (seed, a, b) always gives the same numbers. */
void sam_rng_seed(sam_rng *rng, uint64_t seed, uint64_t a, uint64_t b);

/* The next number, uniform in [0, 1): a multiple of 2^-24, so exactly
 * representable and never 1. */
float sam_rng_float(sam_rng *rng);

#ifdef __cplusplus
}
#endif

#endif
