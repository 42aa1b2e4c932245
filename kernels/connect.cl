/* connect: any-hit visibility for every shadow ray in the queue; a ray's
 * segment ends at direction.w. */
#include "bvh_traversal.h"
#include "path_state.h"
#include "queue_ids.h"

__kernel void connect(__global const BvhNode* nodes, __global const float4* triVertices,
                      __global const int* queueItems, __global const int* queueCounters,
                      int queue, __global const float4* rayOrigins,
                      __global const float4* rayDirections, __global int* occluded)
{
    int i = get_global_id(0);
    if (i >= queueCounters[queue])
        return;
    int slot = queueItems[i];
    Hit hit;
    occluded[slot] = trace_ray(nodes, triVertices, load_ray(rayOrigins, rayDirections, slot), true, &hit);
}
