/* Rays, surface points with error bounds, and the self-intersection-free
 * origin offset. */
#ifndef WAVEVCM_RAY_H
#define WAVEVCM_RAY_H

#include "interface/inline.h"

typedef struct Ray {
    float3 origin;
    float3 direction; /* not necessarily unit length; t is in units of it */
    float tMax;
} Ray;

/* γ(n) = nε / (1 - nε), ε = 2^-24: the bound on the relative error of n
 * chained float operations (Higham; pbrt-v4 §6.8). */
#define GAMMA(n) ((float)(n) * 0x1.0p-24f / (1.0f - (float)(n) * 0x1.0p-24f))

/* A point on a triangle from barycentrics, p = b0·v0 + b1·v1 + b2·v2, and a
 * conservative bound on its absolute error per axis,
 * γ(7)·(|b0·v0| + |b1·v1| + |b2·v2|) (pbrt-v4, Triangle::InteractionFromIntersection),
 * which covers the rounding of the barycentrics from the watertight test. */
INLINE float3 surface_point(float3 v0, float3 v1, float3 v2, float b1, float b2, float3* error)
{
    float b0 = 1.0f - b1 - b2;
    *error = GAMMA(7) * (fabs(b0 * v0) + fabs(b1 * v1) + fabs(b2 * v2));
    return b0 * v0 + b1 * v1 + b2 * v2;
}

INLINE float next_float_up(float v)
{
    if (isinf(v) && v > 0.0f) return v;
    if (v == -0.0f) v = 0.0f;
    int bits = as_int(v);
    return as_float(v >= 0.0f ? bits + 1 : bits - 1);
}

INLINE float next_float_down(float v)
{
    if (isinf(v) && v < 0.0f) return v;
    if (v == 0.0f) v = -0.0f;
    int bits = as_int(v);
    return as_float(v > 0.0f ? bits - 1 : bits + 1);
}

/* Move p off the surface along the geometric normal n, to the side of w, by
 * the projection of the error box onto n, then round away from p: the origin
 * is then provably on w's side of the true surface, at any scene scale and
 * position (pbrt-v4 OffsetRayOrigin). */
INLINE float3 offset_ray_origin(float3 p, float3 error, float3 n, float3 w)
{
    float d = dot(fabs(n), error);
    float3 offset = d * n;
    if (dot(w, n) < 0.0f)
        offset = -offset;
    float3 po = p + offset;
    po.x = offset.x > 0.0f ? next_float_up(po.x) : (offset.x < 0.0f ? next_float_down(po.x) : po.x);
    po.y = offset.y > 0.0f ? next_float_up(po.y) : (offset.y < 0.0f ? next_float_down(po.y) : po.y);
    po.z = offset.z > 0.0f ? next_float_up(po.z) : (offset.z < 0.0f ? next_float_down(po.z) : po.z);
    return po;
}

/* A ray leaving surface point p (error bound `error`, geometric normal ng)
 * in direction d. */
INLINE Ray spawn_ray(float3 p, float3 error, float3 ng, float3 d)
{
    Ray r;
    r.origin = offset_ray_origin(p, error, ng, d);
    r.direction = d;
    r.tMax = INFINITY;
    return r;
}

#endif
