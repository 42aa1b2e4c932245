/* extend: closest hit for every ray in the ray queue, sorted into the hit
 * queue (to shade) or the escaped queue. */
#include "core/queues.h"
#include "geometry/bvh_traversal.h"
#include "materials/volume.h"
#include "transport/path_state.h"

#ifdef HAS_VOLUME_ABSORPTION
/* A ray that reaches a surface from behind ran inside its solid: the path's
 * throughput keeps what absorption leaves (volume.h; w, pt's η², stays). */
INLINE void absorb_inside(const RenderBuffers* b, int slot, Ray ray, const Hit* hit)
{
    __global const Material* m = &b->materials[b->triMaterials[hit->triangle]];
    vec3 ng = triangle_normal(triangle_vertex(b->triVertices, hit->triangle, 0),
                              triangle_vertex(b->triVertices, hit->triangle, 1),
                              triangle_vertex(b->triVertices, hit->triangle, 2));
    if (!(v3_dot(ray.direction, ng) > 0.0f))
        return;
    float4 beta = b->pathThroughput[slot];
    vec3 kept = v3_mul(v3(beta.x, beta.y, beta.z), absorption(m, hit->t * v3_length(ray.direction)));
    b->pathThroughput[slot] = (float4)(kept.x, kept.y, kept.z, beta.w);
}
#endif

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
        Ray ray = load_ray(rayOrigins, rayDirections, slot);
        found = trace_ray(nodes, trianglePackets, ray, false, &hit, &b);
#ifdef HAS_VOLUME_ABSORPTION
        if (found)
            absorb_inside(&b, slot, ray, &hit);
#endif
        hitTriangle[slot] = hit.triangle;
        hitT[slot] = found ? hit.t : INFINITY;
        store_vec2(hitBary, slot, v2(hit.b1, hit.b2));
    }
    queue_push4(queueItems, queueCounters, params.capacity, lanes(QUEUE_HITS, QUEUE_ESCAPED, NO_COUNTER, NO_COUNTER),
                lanes(slot >= 0 && found, slot >= 0 && !found, 0, 0), lanes(slot, slot, 0, 0), scratch, false);
}
