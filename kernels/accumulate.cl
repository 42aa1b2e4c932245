/* accumulate: fold this iteration's sample of each path slot into the running
 * per-pixel mean, mean_i = mean_{i-1} + (x - mean_{i-1}) / i, which keeps the
 * framebuffer in the range of the samples at any iteration count. A sample
 * that is NaN or Inf is dropped and counted; it never reaches the image. */
#include "queue_ids.h"

__kernel void accumulate(__global const int* pathPixels, __global const float4* sampleRadiance,
                         uint iteration, __global float4* framebuffer,
                         __global int* queueCounters)
{
    int slot = get_global_id(0);
    int pixel = pathPixels[slot];
    if (pixel < 0)
        return;
    float4 x = sampleRadiance[slot];
    if (!all(isfinite(x))) {
        atomic_inc(&queueCounters[COUNTER_NONFINITE]);
        x = (float4)(0.0f);
    }
    float4 mean = framebuffer[pixel];
    framebuffer[pixel] = mean + (x - mean) / (float)(iteration + 1);
}
