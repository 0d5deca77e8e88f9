#include "sam/sam_rng.h"

uint64_t sam_rng_mix(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

void sam_rng_seed(sam_rng *rng, uint64_t seed, uint64_t a, uint64_t b)
{
    /* The 64-bit FNV prime lifts a above b's bits: pairs of 32-bit indices do not collide. */
    rng->state = sam_rng_mix(sam_rng_mix(seed) ^ sam_rng_mix(a * 0x100000001B3ull + b));
}

float sam_rng_float(sam_rng *rng)
{
    uint64_t old = rng->state;
    rng->state = old * 6364136223846793005ull + 1442695040888963407ull;
    uint32_t xorshifted = (uint32_t)(((old >> 18) ^ old) >> 27);
    uint32_t rot = (uint32_t)(old >> 59);
    uint32_t r = (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
    /* The top 24 bits: all a float's mantissa holds, so the result cannot round up to 1. */
    return (float)(r >> 8) * (1.0f / 16777216.0f);
}
