/* shade_eyelight (`-a el`): radiance = |cos| between the primary ray and the
 * shading normal at the first hit (0 where the ray escapes). Exercises scene,
 * BVH, kernels and output before any light transport. */
#include "path_state.h"
#include "queues.h"
#include "surface.h"

__kernel void shade_eyelight(int capacity, int nextRayQueue, int freeQueue, uint iteration,
                             __global int* queueItems, __global int* queueCounters,
                             __global const float4* triVertices, __global const float4* triNormals,
                             __global const float4* rayDirections,
                             __global const int* hitTriangle, __global const float2* hitBary,
                             __global const int* pathPixel, __global float4* pixelRadiance)
{
    __local int scratch[2];
    int slot = queue_item(queueItems, queueCounters, capacity, QUEUE_HITS, get_global_id(0));
    if (slot >= 0) {
        int tri = hitTriangle[slot];
        float3 n = geometric_normal(triVertices, tri);
#ifdef HAS_VERTEX_NORMALS
        n = shading_normal(triNormals, tri, hitBary[slot], n);
#endif
        float value = fabs(dot(normalize(rayDirections[slot].xyz), n));
        pixelRadiance[pathPixel[slot]] += (float4)(value, value, value, 0.0f);
    }
    queue_push(queueItems, queueCounters, capacity, freeQueue, slot >= 0, slot, scratch);
}
