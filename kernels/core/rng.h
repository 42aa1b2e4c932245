/* Random numbers: each sample (a pixel's camera path, or a light path) draws
 * 4-D blocks, seeded by a hash of (seed, sample, bounce, block). At the first
 * RNG_STRATIFIED_BOUNCES bounces (the camera or light sample and the first
 * scattering: pixel jitter, emission, direct-light samples and the first
 * BSDF sample) a block is two 2-D pairs of an Owen-scrambled, shuffled Sobol
 * sequence indexed by the iteration (Burley, "Practical Hash-based Owen
 * Scrambling", JCGT 9(4), 2020): a pixel's first 2^m iterations are then
 * stratified in each pair, which independent numbers are not, while
 * different pairs, bounces, samples and seeds stay independent. Deeper
 * bounces draw independent hashed numbers: there a pixel's iterations
 * stratify a path space of many dimensions too thinly to lower the error
 * (pt on the Cornell box, 32 iterations at 256x256, 32 seeds: relMSE
 * 0.8 % +- 0.8 % above all-stratified), and a hashed block costs less than
 * half a stratified one (pt's shade takes 14 % less time). Light paths draw
 * hashed numbers at every bounce where no pixel sees one light path more
 * than another (rng_light_uniform4).
 * A draw is a pure function of its arguments and integer arithmetic, so every
 * device draws the same numbers and images from different devices (or MPI
 * ranks) can be compared sample for sample. */
#ifndef WAVEVCM_RNG_H
#define WAVEVCM_RNG_H

#include "interface/inline.h"

#define RNG_STRATIFIED_BOUNCES 2u

/* Four draws, as scalars: a uint4 or float4 would keep PoCL from running
 * the kernel's work-items in SIMD (core/vec3.h). */
typedef struct Uniform4 {
    float x, y, z, w;
    float abiPad; /* see vec3 (core/vec3.h) */
} Uniform4;

/* 24 high bits to a float in [0, 1): exact, never rounds up to 1. */
INLINE float uint_to_unit_float(uint x) { return (float)(x >> 8) * 0x1.0p-24f; }

INLINE uint reverse_bits32(uint x)
{
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00FF00FFu) << 8) | ((x >> 8) & 0x00FF00FFu);
    x = ((x & 0x0F0F0F0Fu) << 4) | ((x >> 4) & 0x0F0F0F0Fu);
    x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
    return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
}

/* Laine and Karras's hash (Burley 2020's constants): bit k of the result
 * depends only on bits 0..k of x, so on bit-reversed digits it is a nested
 * (Owen) scramble. */
INLINE uint laine_karras(uint x, uint seed)
{
    x += seed;
    x ^= x * 0x6C50B47Cu;
    x ^= x * 0xB82F1E52u;
    x ^= x * 0xC7AFE638u;
    x ^= x * 0x8D22F6E6u;
    return x;
}

/* 32 bits mixed so that every input bit changes each output bit with
 * probability about 1/2 (a multiply-xorshift finalizer); also alpha.h's ray
 * hash. */
INLINE uint hash32(uint x)
{
    x ^= x >> 16;
    x *= 0x7FEB352Du;
    x ^= x >> 15;
    x *= 0x846CA68Bu;
    x ^= x >> 16;
    return x;
}

/* Sobol's second dimension, bit-reversed: digit a of the point is the XOR
 * of the index bits b with C(b, a) odd, i.e. a ⊆ b (Lucas), a superset XOR
 * over the five bits of a digit's position. */
INLINE uint sobol1_reversed(uint j)
{
    j ^= (j >> 1) & 0x55555555u;
    j ^= (j >> 2) & 0x33333333u;
    j ^= (j >> 4) & 0x0F0F0F0Fu;
    j ^= (j >> 8) & 0x00FF00FFu;
    j ^= (j >> 16) & 0x0000FFFFu;
    return j;
}

/* Point `reversedIndex` (bit-reversed) of a 2-D Owen-scrambled, shuffled
 * Sobol sequence (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020):
 * the index is shuffled by a nested scramble, which keeps every aligned run
 * of 2^m indices an aligned run, then each coordinate is Owen-scrambled. Any
 * 2^m consecutive points from 0 are then stratified in every elementary
 * interval of area 2^-m; distinct seeds give decorrelated sequences. An Owen
 * scramble of a value v is reverse(laine_karras(reverse(v))); Sobol's first
 * dimension is reverse(j), so its two reversals cancel, and the second is
 * computed bit-reversed for the same reason. */
INLINE void owen_sobol2(uint reversedIndex, uint seed, uint* x, uint* y)
{
    uint j = reverse_bits32(laine_karras(reversedIndex, seed));
    *x = reverse_bits32(laine_karras(j, hash32(seed ^ 0x68E31DA4u)));
    *y = reverse_bits32(laine_karras(sobol1_reversed(j), hash32(seed ^ 0xB5297A4Du)));
}

/* Four independent uniform numbers of block h at `iteration`: four hashes
 * of one hash of the pair, computed side by side. */
INLINE void hashed4(uint h, uint iteration, uint* x, uint* y, uint* z, uint* w)
{
    uint k = hash32(h ^ (iteration * 0x9E3779B9u)); /* a bijection of the iteration for each h */
    *x = hash32(k + 0x68E31DA4u);
    *y = hash32(k + 0xB5297A4Du);
    *z = hash32(k + 0x1B56C4E9u);
    *w = hash32(k + 0x7F4A7C15u);
}

/* The hash that seeds one block of one sample at one bounce. */
INLINE uint rng_block_hash(uint seed, uint sample, uint bounce, uint block)
{
    return hash32(hash32(hash32(hash32(seed) ^ sample) ^ bounce) ^ block);
}

INLINE Uniform4 unit_floats4(uint x, uint y, uint z, uint w)
{
    Uniform4 u = {uint_to_unit_float(x), uint_to_unit_float(y), uint_to_unit_float(z), uint_to_unit_float(w)};
    return u;
}

/* Four uniform numbers for dimensions [4·block, 4·block + 4) of one sample
 * at one bounce; `sample` is the pixel (camera paths) or light path index,
 * and the iteration is the index into that sample's sequence. Below
 * RNG_STRATIFIED_BOUNCES, dimensions (y, z) and (x, w) are two 2-D stratified
 * pairs: callers take a 2-D continuous sample from (y, z), a discrete choice
 * from x and Russian roulette from w. */
INLINE Uniform4 rng_uniform4(uint seed, uint iteration, uint sample, uint bounce, uint block)
{
    uint h = rng_block_hash(seed, sample, bounce, block);
    uint x, y, z, w;
    if (bounce < RNG_STRATIFIED_BOUNCES) {
        uint r = reverse_bits32(iteration);
        owen_sobol2(r, h, &y, &z);
        owen_sobol2(r, hash32(h ^ 0x1B873593u), &x, &w);
    } else {
        hashed4(h, iteration, &x, &y, &z, &w);
    }
    return unit_floats4(x, y, z, w);
}

/* The same block drawn as independent hashed numbers at every bounce. */
INLINE Uniform4 rng_hashed_uniform4(uint seed, uint iteration, uint sample, uint bounce, uint block)
{
    uint x, y, z, w;
    hashed4(rng_block_hash(seed, sample, bounce, block), iteration, &x, &y, &z, &w);
    return unit_floats4(x, y, z, w);
}

/* A light path's blocks. Under vertex connection (bpt, vcm) light path p is
 * the one that camera sample p connects to at every iteration, so its
 * stratification over iterations lowers that pixel's error: drawn hashed,
 * relMSE at 32 iterations rose 2.1 % +- 0.2 % (bpt) and 5.2 % +- 0.8 % (vcm)
 * on the Cornell box. Under lt, ppm and bpm a light path reaches pixels
 * independently of its index, stratification measured no lower error
 * (docs/performance.md), and hashed blocks make generate_light 1.6x as
 * fast. */
INLINE Uniform4 rng_light_uniform4(uint seed, uint iteration, uint lightPath, uint bounce, uint block)
{
#ifdef VERTEX_CONNECTION
    return rng_uniform4(seed, iteration, lightPath, bounce, block);
#else
    return rng_hashed_uniform4(seed, iteration, lightPath, bounce, block);
#endif
}

#endif
