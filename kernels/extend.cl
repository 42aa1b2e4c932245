/* extend: closest hit for every ray in the ray queue, sorted into the hit
 * queue (to shade) or the escaped queue. */
#include "bvh_traversal.h"
#include "path_state.h"
#include "queues.h"

__kernel void extend(RENDER_KERNEL_PARAMS)
{
    __local int scratch[2];
    int slot = queue_item(queueItems, queueCounters, params.capacity, params.rayQueue, get_global_id(0));
    bool found = false;
    if (slot >= 0) {
        Hit hit;
        found = trace_ray(nodes, triVertices, load_ray(rayOrigins, rayDirections, slot), false, &hit);
        hitTriangle[slot] = hit.triangle;
        hitT[slot] = found ? hit.t : INFINITY;
        hitBary[slot] = (float2)(hit.b1, hit.b2);
    }
    queue_push(queueItems, queueCounters, params.capacity, QUEUE_HITS, slot >= 0 && found, slot, scratch);
    queue_push(queueItems, queueCounters, params.capacity, QUEUE_ESCAPED, slot >= 0 && !found, slot, scratch);
}
