/* shade_eyelight (`-a el`): radiance = |cos| between the primary ray and the
 * shading normal at the first hit, 0 where the ray escapes. Exercises scene,
 * BVH, kernels and output before any light transport exists. */
#include "path_state.h"
#include "queue_ids.h"
#include "surface.h"

__kernel void shade_eyelight(__global const float4* triVertices, __global const float4* triNormals,
                             __global const int* queueItems, __global const int* queueCounters,
                             __global const float4* rayDirections, __global const int* hitTriangle,
                             __global const float2* hitBary, __global float4* sampleRadiance)
{
    int i = get_global_id(0);
    if (i >= queueCounters[QUEUE_RAYS])
        return;
    int slot = queueItems[i];
    int tri = hitTriangle[slot];
    float value = 0.0f;
    if (tri >= 0) {
        float3 n = geometric_normal(triVertices, tri);
#ifdef HAS_VERTEX_NORMALS
        n = shading_normal(triNormals, tri, hitBary[slot], n);
#endif
        value = fabs(dot(normalize(rayDirections[slot].xyz), n));
    }
    sampleRadiance[slot] = (float4)(value, value, value, 0.0f);
}
