/* connect: trace every shadow ray in the shadow queue (any hit, up to
 * direction.w) and add its contribution to the pixel if nothing is in the way.
 * Each pixel has one camera path per iteration, so no two items of a launch
 * write the same pixel. */
#include "bvh_traversal.h"
#include "path_state.h"
#include "queues.h"

__kernel void connect(__global const BvhNode* nodes, __global const float4* triVertices, int capacity,
                      __global const int* queueItems, __global const int* queueCounters,
                      __global const float4* shadowOrigins, __global const float4* shadowDirections,
                      __global const float4* shadowContribution, __global const int* pathPixel,
                      __global float4* pixelRadiance)
{
    int slot = queue_item(queueItems, queueCounters, capacity, QUEUE_SHADOW, get_global_id(0));
    if (slot < 0)
        return;
    Hit hit;
    if (!trace_ray(nodes, triVertices, load_ray(shadowOrigins, shadowDirections, slot), true, &hit))
        pixelRadiance[pathPixel[slot]] += shadowContribution[slot];
}
