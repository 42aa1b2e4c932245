/* generate: give the first `count` free slots the next camera samples of the
 * iteration (one per pixel, pixel = sample index), each with a jittered
 * primary ray (box filter), appended to the ray queue. The host knows how
 * many samples were handed out and how long the ray queue is, so no atomics
 * are needed: item i takes sample firstSample + i and ray-queue entry
 * rayQueueLength + i. */
#include "camera.h"
#include "path_state.h"
#include "queues.h"
#include "rng.h"

__kernel void generate(__constant const Camera* camera, uint seed, uint iteration, int capacity,
                       int freeQueue, int rayQueue, int count, int firstSample, int rayQueueLength,
                       __global int* queueItems, __global int* queueCounters,
                       __global float4* rayOrigins, __global float4* rayDirections,
                       __global int* pathPixel, __global int* pathDepth, __global float4* pathThroughput,
                       __global float* pathPrevPdf)
{
    int i = get_global_id(0);
    if (i == 0)
        queueCounters[COUNTER_INDEX(rayQueue)] = rayQueueLength + count;
    if (i >= count)
        return;
    int slot = queueItems[freeQueue * capacity + i];
    int sample = firstSample + i;
    float4 u = rng_uniform4(seed, iteration, (uint)sample, 0u, 0u);
    store_ray(rayOrigins, rayDirections, slot, camera_ray(camera, sample, u.xy));
    pathPixel[slot] = sample;
    pathDepth[slot] = 1; /* the camera segment */
    pathThroughput[slot] = (float4)(1.0f);
    pathPrevPdf[slot] = 0.0f; /* what the camera sees directly gets full weight */
    queueItems[rayQueue * capacity + rayQueueLength + i] = slot;
}
