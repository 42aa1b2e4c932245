/* Primary rays of the pinhole camera described in shared_types.h. */
#ifndef WAVEVCM_CAMERA_H
#define WAVEVCM_CAMERA_H

#include "shared_types.h"
#include "ray.h"

inline Ray camera_ray(__constant const Camera* cam, int pixel, float2 jitter)
{
    float x = (float)(pixel % cam->width) + jitter.x;
    float y = (float)(pixel / cam->width) + jitter.y;
    float sx = 2.0f * x / (float)cam->width - 1.0f;
    float sy = 1.0f - 2.0f * y / (float)cam->height;
    float3 forward = (float3)(cam->forward[0], cam->forward[1], cam->forward[2]);
    float3 right = (float3)(cam->right[0], cam->right[1], cam->right[2]);
    float3 up = (float3)(cam->up[0], cam->up[1], cam->up[2]);
    Ray r;
    r.origin = (float3)(cam->position[0], cam->position[1], cam->position[2]);
    r.direction = normalize(forward + sx * right + sy * up);
    r.tMax = INFINITY;
    return r;
}

#endif
