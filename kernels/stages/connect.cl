/* connect: trace every shadow ray in the shadow queue (any hit, up to
 * direction.w) and, if nothing is in the way, add its contribution:
 *   connect        to its camera path's sample (pixelRadiance has an entry per
 *                  camera sample of the iteration), so no two items of a
 *                  launch write the same entry;
 *   connect_splat  to the pixel a light path vertex projects to (light
 *                  tracing): many may hit one pixel, so the adds are atomic.
 *                  The sum then depends on timing only by float rounding;
 *   trace_connections the vertex connections that connect_vertices queued in
 *                  the round before (its CONNECTION_QUEUE), to the camera
 *                  path's sample: a sample's connections are traced by as
 *                  many work-items, so these adds are atomic too. */
#include "core/queues.h"
#include "geometry/bvh_traversal.h"
#include "interface/inline.h"
#include "transport/path_state.h"

/* Hints for the adds ahead: the pixel index (pixelOf[slot]) and the
 * contribution of entry i + D, then, through that index, the pixel of entry
 * i + D/2 itself. The pixels lie anywhere in the image, and each add waited
 * for its pixel's cache line (connect_splat: half of its time, in the
 * compare-and-swap loop). */
INLINE void prefetch_shadow_pixels(const RenderBuffers* b, int capacity, int i, __global const int* pixelOf,
                                   __global const float4* image)
{
#ifdef HAS_PREFETCH
    int slot = queue_item(b->queueItems, b->queueCounters, capacity, QUEUE_SHADOW, i + PREFETCH_DISTANCE);
    if (slot >= 0) {
        PREFETCH(&pixelOf[slot], 4);
        PREFETCH(&b->shadowContribution[slot], 16);
    }
    slot = queue_item(b->queueItems, b->queueCounters, capacity, QUEUE_SHADOW, i + PREFETCH_DISTANCE / 2);
    if (slot >= 0)
        PREFETCH(&image[pixelOf[slot]], 16);
#endif
}

/* The slot of shadow-queue entry i if nothing is in its ray's way, else -1
 * (also past the queue's end); first the hints for the entries ahead, whose
 * contributions go to image[pixelOf[slot]]. */
INLINE int unoccluded_shadow_slot(const RenderBuffers* b, int capacity, int i, __global const int* pixelOf,
                                  __global const float4* image)
{
    prefetch_ray(b->queueItems, b->queueCounters, capacity, QUEUE_SHADOW, i, b->shadowOrigins, b->shadowDirections);
    prefetch_shadow_pixels(b, capacity, i, pixelOf, image);
    int slot = queue_item(b->queueItems, b->queueCounters, capacity, QUEUE_SHADOW, i);
    if (slot < 0)
        return -1;
    Hit hit;
    bool occluded = trace_ray(b->nodes, b->trianglePackets, load_ray(b->shadowOrigins, b->shadowDirections, slot),
                              true, &hit, b);
    return occluded ? -1 : slot;
}

__kernel void connect(RENDER_KERNEL_PARAMS)
{
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int slot = unoccluded_shadow_slot(&b, params.capacity, get_global_id(0), pathPixel, pixelRadiance);
    if (slot >= 0)
        add_vec3(pixelRadiance, pathPixel[slot], load_vec3(shadowContribution, slot));
}

/* *p += v as a compare-and-swap loop: OpenCL 1.2 has no float atomics. */
INLINE void atomic_add_float(volatile __global float* p, float v)
{
    union {
        uint u;
        float f;
    } expected, desired;
    do {
        expected.f = *p;
        desired.f = expected.f + v;
    } while (atomic_cmpxchg((volatile __global uint*)p, expected.u, desired.u) != expected.u);
}

/* image[pixel].xyz += c, atomically per component. */
INLINE void atomic_add_vec3(__global float4* image, int pixel, vec3 c)
{
    volatile __global float* p = (volatile __global float*)(image + pixel);
    atomic_add_float(p, c.x);
    atomic_add_float(p + 1, c.y);
    atomic_add_float(p + 2, c.z);
}

__kernel void connect_splat(RENDER_KERNEL_PARAMS)
{
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int slot = unoccluded_shadow_slot(&b, params.capacity, get_global_id(0), shadowPixel, splatRadiance);
    if (slot >= 0)
        atomic_add_vec3(splatRadiance, shadowPixel[slot], load_vec3(shadowContribution, slot));
}

__kernel void trace_connections(RENDER_KERNEL_PARAMS)
{
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int i = get_global_id(0);
    if (i >= min(queueCounters[COUNTER_INDEX(COUNTER_CONNECTIONS)], params.connectionCapacity))
        return;
    int sample = *connection_sample(connectionContribution, i);
    if (sample < 0)
        return;
    Hit hit;
    if (trace_ray(nodes, trianglePackets, load_ray(connectionOrigins, connectionDirections, i), true, &hit, &b))
        return;
    atomic_add_vec3(connectionRadiance, sample, load_vec3(connectionContribution, i));
}
