/* shade_eyelight (`-a el`): radiance = |cos| between the primary ray and the
 * shading normal at the first hit (0 where the ray escapes). Exercises scene,
 * BVH, kernels and output before any light transport. */
#include "core/queues.h"
#include "geometry/surface.h"
#include "transport/path_state.h"

__kernel void shade_eyelight(RENDER_KERNEL_PARAMS)
{
    __local int scratch[8];
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_HITS, get_global_id(0));
    if (slot >= 0) {
        int tri = hitTriangle[slot];
        float3 n = geometric_normal(triVertices, tri);
#ifdef HAS_VERTEX_NORMALS
        n = shading_normal(triNormals, tri, hitBary[slot], n);
#endif
        float value = fabs(dot(normalize(rayDirections[slot].xyz), n));
        pixelRadiance[pathPixel[slot]] += (float4)(value, value, value, 0.0f);
    }
    queue_push4(queueItems, queueCounters, params.capacity,
                (int4)(params.nextFreeQueue, NO_COUNTER, NO_COUNTER, NO_COUNTER), (int4)(slot >= 0, 0, 0, 0), slot,
                scratch);
}
