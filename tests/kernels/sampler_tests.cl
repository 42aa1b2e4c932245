/* Test-only kernel for core/rng.h: the draws rng_uniform4 gives work-item i,
 * which is iteration first + i·iterationStep of sample firstSample +
 * i·sampleStep (one of the steps 0). */
#include "core/rng.h"

__kernel void sampler_draws(uint seed, uint first, uint iterationStep, uint firstSample, uint sampleStep,
                            uint bounce, uint block, int n, __global float4* out)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    Uniform4 u = rng_uniform4(seed, first + (uint)i * iterationStep, firstSample + (uint)i * sampleStep, bounce, block);
    out[i] = (float4)(u.x, u.y, u.z, u.w);
}

/* The bounces whose blocks are stratified (core/rng.h), for the host. */
__kernel void sampler_stratified_bounces(__global uint* out) { out[0] = RNG_STRATIFIED_BOUNCES; }
