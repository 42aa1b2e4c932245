/* Counter-based random numbers: Philox4x32-10 (Salmon et al., "Parallel random
 * numbers: as easy as 1, 2, 3", SC 2011). A draw is a pure function of
 * (seed, iteration, sample, bounce, dimension), so every device draws the same
 * numbers and images from different devices can be compared sample for sample. */
#ifndef WAVEVCM_RNG_H
#define WAVEVCM_RNG_H

#include "interface/inline.h"

/* The high 32 bits of a 32x32-bit product, written as one 64-bit multiply:
 * PoCL's mul_hi builds it from 16-bit partial products, several times the
 * instructions; x86 and PTX both have the 64-bit (or high-half) multiply. */
INLINE uint mul_hi32(uint a, uint b) { return (uint)(((ulong)a * (ulong)b) >> 32); }

/* Philox4x32-10 on four scalar words (a uint4 made PoCL move lanes in and
 * out of vector registers every round): each round two 32x32->64
 * multiplies, mixed with the key, which then takes a Weyl step. */
INLINE uint4 philox4x32_10(uint4 counter, uint2 key)
{
    const uint M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;
    uint c0 = counter.x, c1 = counter.y, c2 = counter.z, c3 = counter.w, k0 = key.x, k1 = key.y;
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
    return (uint4)(c0, c1, c2, c3);
}

/* 24 high bits to a float in [0, 1): exact, never rounds up to 1. */
INLINE float uint_to_unit_float(uint x) { return (float)(x >> 8) * 0x1.0p-24f; }

/* Four uniform numbers for dimensions [4·block, 4·block + 4) of one sample at
 * one bounce. `sample` is the global sample index within the iteration. */
INLINE float4 rng_uniform4(uint seed, uint iteration, uint sample, uint bounce, uint block)
{
    uint4 bits = philox4x32_10((uint4)(sample, iteration, bounce, block), (uint2)(seed, 0x5EEDu));
    return (float4)(uint_to_unit_float(bits.x), uint_to_unit_float(bits.y),
                    uint_to_unit_float(bits.z), uint_to_unit_float(bits.w));
}

#endif
