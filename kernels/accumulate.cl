/* accumulate: fold this iteration's sample of each pixel — what its camera
 * path gathered plus what light tracing splatted onto it — into the running
 * mean, mean_i = mean_{i-1} + (x - mean_{i-1}) / i, which keeps the
 * framebuffer in the range of the samples at any iteration count, and clear
 * both for the next iteration. A sample that is NaN or Inf is dropped
 * (counted as zero) and counted; it never reaches the image. */
#include "queue_ids.h"

__kernel void accumulate(__global float4* pixelRadiance, __global float4* splatRadiance, int pixels,
                         uint iteration, __global float4* framebuffer, __global int* queueCounters)
{
    int pixel = get_global_id(0);
    if (pixel >= pixels)
        return;
    float4 x = pixelRadiance[pixel] + splatRadiance[pixel];
    pixelRadiance[pixel] = (float4)(0.0f);
    splatRadiance[pixel] = (float4)(0.0f);
    if (!all(isfinite(x.xyz))) {
        atomic_inc(&queueCounters[COUNTER_INDEX(COUNTER_NONFINITE)]);
        x = (float4)(0.0f);
    }
    float4 mean = framebuffer[pixel];
    framebuffer[pixel] = mean + (x - mean) / (float)(iteration + 1);
}
