/* generate: give each free slot the next camera sample of the iteration (one
 * per pixel, pixel = sample index), with a jittered primary ray (box
 * filter), and push it to the ray queue. Slots left over once every sample is
 * handed out stay idle. */
#include "camera.h"
#include "path_state.h"
#include "queues.h"
#include "rng.h"

__kernel void generate(__constant const Camera* camera, uint seed, uint iteration, int capacity,
                       int freeQueue, int rayQueue, __global int* queueItems, __global int* queueCounters,
                       __global float4* rayOrigins, __global float4* rayDirections,
                       __global int* pathPixel, __global int* pathDepth, __global float4* pathThroughput,
                       __global float* pathPrevPdf)
{
    int slot = queue_item(queueItems, queueCounters, capacity, freeQueue, get_global_id(0));
    if (slot < 0)
        return;
    int sample = atomic_inc(&queueCounters[COUNTER_NEXT_SAMPLE]);
    if (sample >= camera->width * camera->height)
        return;
    float4 u = rng_uniform4(seed, iteration, (uint)sample, 0u, 0u);
    store_ray(rayOrigins, rayDirections, slot, camera_ray(camera, sample, u.xy));
    pathPixel[slot] = sample;
    pathDepth[slot] = 1; /* the camera segment */
    pathThroughput[slot] = (float4)(1.0f);
    pathPrevPdf[slot] = 0.0f; /* what the camera sees directly gets full weight */
    queue_push(queueItems, queueCounters, capacity, rayQueue, slot);
}
