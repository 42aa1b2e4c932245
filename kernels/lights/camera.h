/* The camera described in shared_types.h, a pinhole or glTF's orthographic
 * one: primary rays, the density with which it samples directions, and the
 * projection of points onto the image (for light tracing). */
#ifndef WAVEVCM_CAMERA_H
#define WAVEVCM_CAMERA_H

#include "core/ray.h"
#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

INLINE Ray camera_ray(__constant const Camera* cam, int pixel, float jitterX, float jitterY)
{
    float x = (float)(pixel % cam->width) + jitterX;
    float y = (float)(pixel / cam->width) + jitterY;
    float sx = 2.0f * x / (float)cam->width - 1.0f;
    float sy = 1.0f - 2.0f * y / (float)cam->height;
    Ray r;
#ifdef ORTHOGRAPHIC_CAMERA
    r.origin = v3_add(load3c(cam->position), v3_add(v3_scale(load3c(cam->right), sx), v3_scale(load3c(cam->up), sy)));
    r.direction = load3c(cam->forward);
#else
    r.origin = load3c(cam->position);
    r.direction = v3_normalize(
        v3_add(v3_add(load3c(cam->forward), v3_scale(load3c(cam->right), sx)), v3_scale(load3c(cam->up), sy)));
#endif
    r.tMax = INFINITY;
    return r;
}

/* Density over solid angle of the camera's direction `d` (unit) when a point
 * is chosen uniformly over one pixel: the image plane sits where a pixel has
 * area 1, at distance H / (2 tan(fov/2)), and the density is
 * distance(image point)² / cos θ (SmallVCM's convention). */
INLINE float camera_pdf_w(__constant const Camera* cam, vec3 d)
{
    /* An orthographic camera's direction is a delta: infinite, so that
     * mis_camera_start gives light tracing's technique the weight 0. */
#ifdef ORTHOGRAPHIC_CAMERA
    return INFINITY;
#endif
    float cosAtCamera = v3_dot(d, load3c(cam->forward));
    float imagePlaneDistance = (float)cam->height / (2.0f * v3_length(load3c(cam->up)));
    float imagePointDistance = imagePlaneDistance / cosAtCamera;
    return cosAtCamera > 0.0f ? imagePointDistance * imagePointDistance / cosAtCamera : 0.0f;
}

/* The pixel a world point projects to, or -1 when it is behind the camera
 * or outside the image, or the camera is orthographic: a connection to it
 * would have to run exactly along its direction. */
INLINE int camera_pixel(__constant const Camera* cam, vec3 point)
{
#ifdef ORTHOGRAPHIC_CAMERA
    return -1;
#endif
    vec3 d = v3_sub(point, load3c(cam->position));
    float depth = v3_dot(d, load3c(cam->forward));
    if (!(depth > 0.0f))
        return -1;
    vec3 right = load3c(cam->right), up = load3c(cam->up);
    float sx = v3_dot(d, right) / (depth * v3_dot(right, right));
    float sy = v3_dot(d, up) / (depth * v3_dot(up, up));
    float x = 0.5f * (sx + 1.0f) * (float)cam->width, y = 0.5f * (1.0f - sy) * (float)cam->height;
    if (!(x >= 0.0f && x < (float)cam->width && y >= 0.0f && y < (float)cam->height))
        return -1;
    return (int)y * cam->width + (int)x;
}

#endif
