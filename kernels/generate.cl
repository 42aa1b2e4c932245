/* generate: one camera path per slot for pixels [firstPixel, firstPixel +
 * capacity), each with a jittered primary ray (box filter), pushed to the ray
 * queue. */
#include "camera.h"
#include "path_state.h"
#include "queues.h"
#include "rng.h"

__kernel void generate(__constant const Camera* camera, uint seed, uint iteration, int firstPixel,
                       __global float4* rayOrigins, __global float4* rayDirections,
                       __global int* pathPixels, __global int* queueItems,
                       __global int* queueCounters)
{
    int slot = get_global_id(0);
    int pixel = firstPixel + slot;
    if (pixel >= camera->width * camera->height) {
        pathPixels[slot] = -1;
        return;
    }
    float4 u = rng_uniform4(seed, iteration, (uint)pixel, 0u, 0u);
    store_ray(rayOrigins, rayDirections, slot, camera_ray(camera, pixel, u.xy));
    pathPixels[slot] = pixel;
    queue_push(queueItems, queueCounters, QUEUE_RAYS, slot);
}
