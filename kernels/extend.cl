/* extend: closest hit for every ray in the ray queue. */
#include "bvh_traversal.h"
#include "path_state.h"
#include "queue_ids.h"

__kernel void extend(__global const BvhNode* nodes, __global const float4* triVertices,
                     __global const int* queueItems, __global const int* queueCounters,
                     __global const float4* rayOrigins, __global const float4* rayDirections,
                     __global float* hitT, __global int* hitTriangle, __global float2* hitBary)
{
    int i = get_global_id(0);
    if (i >= queueCounters[QUEUE_RAYS])
        return;
    int slot = queueItems[i];
    Hit hit;
    trace_ray(nodes, triVertices, load_ray(rayOrigins, rayDirections, slot), false, &hit);
    hitTriangle[slot] = hit.triangle;
    hitT[slot] = hit.triangle >= 0 ? hit.t : INFINITY;
    hitBary[slot] = (float2)(hit.b1, hit.b2);
}
