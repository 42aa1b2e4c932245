/* accumulate: fold this iteration's samples of each pixel into the running
 * mean one at a time, mean_i = mean_{i-1} + (x - mean_{i-1}) / i, which
 * keeps the framebuffer in the range of the samples at any iteration count,
 * and clear the iteration's buffers. With samplesPerIteration K > 1
 * pixelRadiance, connectionRadiance and mergingRadiance hold K samples per
 * pixel (path_state.h: sample_pixel), folded in pass order: the same
 * arithmetic as K iterations of one. Light tracing's splats, one image for
 * the whole iteration (each pass's light paths weighted as one pass's), go
 * with pass 0, so that the mean over the K passes holds their sum once. A
 * sample is the sum of what the technique
 * families added: unidirectional (emission hits, next-event estimation,
 * background), vertex connection (connections, light-tracing splats) and
 * vertex merging; with `techniques` each family also gets a running mean of
 * its own (three float4 per pixel in familyMeans). A sample that is NaN or
 * Inf is dropped (counted as zero) and counted: the last guard of the NaN
 * policy (nan_policy.h), for finite contributions whose sum overflowed. */
#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"

INLINE vec3 take(__global float4* buffer, int pixel)
{
    vec3 x = load_vec3(buffer, pixel);
    store_vec3w(buffer, pixel, v3s(0.0f), 0.0f);
    return x;
}

/* mean += (x - mean) · inv, for element i of a float4 array of means */
INLINE void update_mean(__global float4* means, int i, vec3 x, float inv)
{
    vec3 mean = load_vec3(means, i);
    store_vec3w(means, i, v3_add(mean, v3_scale(v3_sub(x, mean), inv)), 0.0f);
}

__kernel void accumulate(RENDER_KERNEL_PARAMS)
{
    int pixel = get_global_id(0);
    if (pixel >= params.pixels)
        return;
    for (int k = 0; k < params.samplesPerIteration; ++k) {
        vec3 unidirectional = take(pixelRadiance, k * params.pixels + pixel);
        vec3 connection = v3s(0.0f), merging = v3s(0.0f);
#ifdef BIDIRECTIONAL
        connection = take(connectionRadiance, k * params.pixels + pixel);
        if (k == 0)
            connection = v3_add(connection, take(splatRadiance, pixel));
        merging = take(mergingRadiance, k * params.pixels + pixel);
#endif
        vec3 x = v3_add(v3_add(unidirectional, connection), merging);
        bool finite = v3_is_finite(x);
        if (!finite) {
            atomic_inc(&queueCounters[COUNTER_INDEX(COUNTER_NONFINITE)]);
            x = unidirectional = connection = merging = v3s(0.0f);
        }
        float inv = 1.0f / (float)(params.accumulated + k + 1);
        update_mean(framebuffer, pixel, x, inv);
        if (params.techniques) {
            update_mean(familyMeans, 3 * pixel, unidirectional, inv);
            update_mean(familyMeans, 3 * pixel + 1, connection, inv);
            update_mean(familyMeans, 3 * pixel + 2, merging, inv);
        }
    }
}
