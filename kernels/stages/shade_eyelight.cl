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
        vec3 n = geometric_normal(triVertices, tri);
#ifdef HAS_VERTEX_NORMALS
        n = shading_normal(triNormals, tri, load_vec2(hitBary, slot), n);
#endif
        float value = fabs(v3_dot(v3_normalize(load_vec3(rayDirections, slot)), n));
        add_vec3(pixelRadiance, pathPixel[slot], v3s(value));
    }
    queue_push4(queueItems, queueCounters, params.capacity,
                lanes(params.nextFreeQueue, NO_COUNTER, NO_COUNTER, NO_COUNTER), lanes(slot >= 0, 0, 0, 0), slot,
                scratch);
}
