/* accumulate: fold this iteration's sample of each pixel into the running
 * mean, mean_i = mean_{i-1} + (x - mean_{i-1}) / i, which keeps the
 * framebuffer in the range of the samples at any iteration count, and clear
 * the iteration's buffers. The sample is the sum of what the technique
 * families added: unidirectional (emission hits, next-event estimation,
 * background), vertex connection (connections, light-tracing splats) and
 * vertex merging; with `techniques` each family also gets a running mean of
 * its own (three float4 per pixel in familyMeans). A sample that is NaN or
 * Inf is dropped (counted as zero) and counted: the last guard of the NaN
 * policy (nan_policy.h), for finite contributions whose sum overflowed. */
#include "interface/inline.h"
#include "interface/kernel_interface.h"

INLINE float4 take(__global float4* buffer, int pixel)
{
    float4 x = buffer[pixel];
    buffer[pixel] = (float4)(0.0f);
    return x;
}

__kernel void accumulate(RENDER_KERNEL_PARAMS)
{
    int pixel = get_global_id(0);
    if (pixel >= params.pixels)
        return;
    float4 family[3] = {take(pixelRadiance, pixel), take(connectionRadiance, pixel) + take(splatRadiance, pixel),
                        take(mergingRadiance, pixel)};
    float4 x = family[0] + family[1] + family[2];
    if (!all(isfinite(x.xyz))) {
        atomic_inc(&queueCounters[COUNTER_INDEX(COUNTER_NONFINITE)]);
        x = family[0] = family[1] = family[2] = (float4)(0.0f);
    }
    float inv = 1.0f / (float)(params.iteration + 1);
    float4 mean = framebuffer[pixel];
    framebuffer[pixel] = mean + (x - mean) * inv;
    if (params.techniques)
        for (int f = 0; f < 3; ++f) {
            float4 m = familyMeans[3 * pixel + f];
            familyMeans[3 * pixel + f] = m + (family[f] - m) * inv;
        }
}
