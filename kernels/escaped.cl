/* escaped: rays that left the scene see the background light (MIS-weighted
 * against having sampled it with next-event estimation); the path ends. */
#include "lights.h"
#include "queues.h"

__kernel void escaped(__global const Light* lights, __constant const SceneInfo* scene, int capacity,
                      int freeQueue, __global int* queueItems, __global int* queueCounters,
                      __global const int* pathPixel, __global const float4* pathThroughput,
                      __global const float* pathPrevPdf, __global float4* pixelRadiance)
{
    __local int scratch[2];
    int slot = queue_item(queueItems, queueCounters, capacity, QUEUE_ESCAPED, get_global_id(0));
#if defined(HAS_BACKGROUND) && !defined(EYE_LIGHT)
    if (slot >= 0 && scene->backgroundLight >= 0) {
        __global const Light* bg = &lights[scene->backgroundLight];
        float prevPdf = pathPrevPdf[slot];
        float lightPdf = background_light_pdf(bg->pmf);
        /* Power heuristic; prevPdf = 0 marks a delta or camera segment. */
        float w = prevPdf > 0.0f ? prevPdf * prevPdf / (prevPdf * prevPdf + lightPdf * lightPdf) : 1.0f;
        pixelRadiance[pathPixel[slot]] += (float4)(w * pathThroughput[slot].xyz * vload3(0, bg->emission), 0.0f);
    }
#endif
    queue_push(queueItems, queueCounters, capacity, freeQueue, slot >= 0, slot, scratch);
}
