/* Counter-based random numbers: Philox4x32-10 (Salmon et al., "Parallel random
 * numbers: as easy as 1, 2, 3", SC 2011). A draw is a pure function of
 * (seed, iteration, sample, bounce, dimension), so every device draws the same
 * numbers and images from different devices can be compared sample for sample. */
#ifndef WAVEVCM_RNG_H
#define WAVEVCM_RNG_H

#include "interface/inline.h"

/* Four draws, as scalars: a uint4 or float4 would keep PoCL from running
 * the kernel's work-items in SIMD (core/vec3.h). */
typedef struct Uniform4 {
    float x, y, z, w;
    float abiPad; /* see vec3 (core/vec3.h) */
} Uniform4;

/* The high 32 bits of a 32x32-bit product, written as one 64-bit multiply:
 * PoCL's mul_hi builds it from 16-bit partial products, several times the
 * instructions; x86 and PTX both have the 64-bit (or high-half) multiply. */
INLINE uint mul_hi32(uint a, uint b) { return (uint)(((ulong)a * (ulong)b) >> 32); }

/* Philox4x32-10 on four scalar words, in place: each round two 32x32->64
 * multiplies, mixed with the key, which then takes a Weyl step. Unrolled:
 * a loop inside the work-item would keep the work-items' loop from being
 * vectorized. */
INLINE void philox4x32_10(uint* w0, uint* w1, uint* w2, uint* w3, uint k0, uint k1)
{
    const uint M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;
    uint c0 = *w0, c1 = *w1, c2 = *w2, c3 = *w3;
#pragma unroll
    for (int i = 0; i < 10; ++i) {
        uint hi0 = mul_hi32(M0, c0), lo0 = M0 * c0;
        uint hi1 = mul_hi32(M1, c2), lo1 = M1 * c2;
        c0 = hi1 ^ c1 ^ k0;
        c1 = lo1;
        c2 = hi0 ^ c3 ^ k1;
        c3 = lo0;
        k0 += 0x9E3779B9u;
        k1 += 0xBB67AE85u;
    }
    *w0 = c0;
    *w1 = c1;
    *w2 = c2;
    *w3 = c3;
}

/* 24 high bits to a float in [0, 1): exact, never rounds up to 1. */
INLINE float uint_to_unit_float(uint x) { return (float)(x >> 8) * 0x1.0p-24f; }

/* Four uniform numbers for dimensions [4·block, 4·block + 4) of one sample at
 * one bounce. `sample` is the global sample index within the iteration. */
INLINE Uniform4 rng_uniform4(uint seed, uint iteration, uint sample, uint bounce, uint block)
{
    uint c0 = sample, c1 = iteration, c2 = bounce, c3 = block;
    philox4x32_10(&c0, &c1, &c2, &c3, seed, 0x5EEDu);
    Uniform4 u = {uint_to_unit_float(c0), uint_to_unit_float(c1), uint_to_unit_float(c2), uint_to_unit_float(c3)};
    return u;
}

#endif
