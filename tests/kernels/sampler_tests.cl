/* Test-only kernel for core/rng.h: the draws rng_uniform4 (or, if hashed,
 * rng_hashed_uniform4) gives work-item i, which is iteration first +
 * i·iterationStep of sample firstSample + i·sampleStep (one of the steps 0). */
#include "core/rng.h"

__kernel void sampler_draws(uint seed, uint first, uint iterationStep, uint firstSample, uint sampleStep,
                            uint bounce, uint block, uint hashed, int n, __global float4* out)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    uint iteration = first + (uint)i * iterationStep, sample = firstSample + (uint)i * sampleStep;
    Uniform4 u = hashed ? rng_hashed_uniform4(seed, iteration, sample, bounce, block)
                        : rng_uniform4(seed, iteration, sample, bounce, block);
    out[i] = (float4)(u.x, u.y, u.z, u.w);
}

/* The bounces whose blocks are stratified (core/rng.h), for the host. */
__kernel void sampler_stratified_bounces(__global uint* out) { out[0] = RNG_STRATIFIED_BOUNCES; }

/* The draws of block 2 of light path 4242 at bounce 0 (its emission
 * sample) along iterations first, first + 1, ...: stratified or hashed as
 * the program's algorithm has them (rng_light_uniform4). */
__kernel void sampler_light_draws(uint seed, uint first, int n, __global float4* out)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    Uniform4 u = rng_light_uniform4(seed, first + (uint)i, 4242u, 0u, 2u);
    out[i] = (float4)(u.x, u.y, u.z, u.w);
}
