/* The pinhole camera described in shared_types.h: primary rays, the density
 * with which it samples directions, and the projection of points onto the
 * image (for light tracing). */
#ifndef WAVEVCM_CAMERA_H
#define WAVEVCM_CAMERA_H

#include "core/ray.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

INLINE Ray camera_ray(__constant const Camera* cam, int pixel, float2 jitter)
{
    float x = (float)(pixel % cam->width) + jitter.x;
    float y = (float)(pixel / cam->width) + jitter.y;
    float sx = 2.0f * x / (float)cam->width - 1.0f;
    float sy = 1.0f - 2.0f * y / (float)cam->height;
    Ray r;
    r.origin = vload3(0, cam->position);
    r.direction = normalize(vload3(0, cam->forward) + sx * vload3(0, cam->right) + sy * vload3(0, cam->up));
    r.tMax = INFINITY;
    return r;
}

/* Density over solid angle of the camera's direction `d` (unit) when a point
 * is chosen uniformly over one pixel: the image plane sits where a pixel has
 * area 1, at distance H / (2 tan(fov/2)), and the density is
 * distance(image point)² / cos θ (SmallVCM's convention). */
INLINE float camera_pdf_w(__constant const Camera* cam, float3 d)
{
    float cosAtCamera = dot(d, vload3(0, cam->forward));
    if (cosAtCamera <= 0.0f)
        return 0.0f;
    float imagePlaneDistance = (float)cam->height / (2.0f * length(vload3(0, cam->up)));
    float imagePointDistance = imagePlaneDistance / cosAtCamera;
    return imagePointDistance * imagePointDistance / cosAtCamera;
}

/* The pixel a world point projects to, or -1 when it is behind the camera
 * or outside the image. */
INLINE int camera_pixel(__constant const Camera* cam, float3 point)
{
    float3 d = point - vload3(0, cam->position);
    float depth = dot(d, vload3(0, cam->forward));
    if (!(depth > 0.0f))
        return -1;
    float3 right = vload3(0, cam->right), up = vload3(0, cam->up);
    float sx = dot(d, right) / (depth * dot(right, right));
    float sy = dot(d, up) / (depth * dot(up, up));
    float x = 0.5f * (sx + 1.0f) * (float)cam->width, y = 0.5f * (1.0f - sy) * (float)cam->height;
    if (!(x >= 0.0f && x < (float)cam->width && y >= 0.0f && y < (float)cam->height))
        return -1;
    return (int)y * cam->width + (int)x;
}

#endif
