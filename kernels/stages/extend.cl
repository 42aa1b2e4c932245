/* extend: closest hit for every ray in the ray queue, sorted into the hit
 * queue (to shade) or the escaped queue. */
#include "core/queues.h"
#include "geometry/bvh_traversal.h"
#include "transport/path_state.h"

__kernel void extend(RENDER_KERNEL_PARAMS)
{
    __local int scratch[QUEUE_SCRATCH_INTS];
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    prefetch_ray(queueItems, queueCounters, params.capacity, params.rayQueue, get_global_id(0), rayOrigins,
                 rayDirections);
    int slot = queue_item(queueItems, queueCounters, params.capacity, params.rayQueue, get_global_id(0));
    bool found = false;
    if (slot >= 0) {
        Hit hit;
        found = trace_ray(nodes, trianglePackets, load_ray(rayOrigins, rayDirections, slot), false, &hit, &b);
        hitTriangle[slot] = hit.triangle;
        hitT[slot] = found ? hit.t : INFINITY;
        store_vec2(hitBary, slot, v2(hit.b1, hit.b2));
    }
    queue_push4(queueItems, queueCounters, params.capacity, lanes(QUEUE_HITS, QUEUE_ESCAPED, NO_COUNTER, NO_COUNTER),
                lanes(slot >= 0 && found, slot >= 0 && !found, 0, 0), lanes(slot, slot, 0, 0), scratch, false);
}
