/* Rays, surface points with error bounds, and the self-intersection-free
 * origin offset. */
#ifndef WAVEVCM_RAY_H
#define WAVEVCM_RAY_H

#include "core/vec3.h"
#include "interface/inline.h"

typedef struct Ray {
    vec3 origin;
    vec3 direction; /* not necessarily unit length; t is in units of it */
    float tMax;
} Ray;

/* γ(n) = nε / (1 - nε), ε = 2^-24: the bound on the relative error of n
 * chained float operations (Higham; pbrt-v4 §6.8). */
#define GAMMA(n) ((float)(n) * 0x1.0p-24f / (1.0f - (float)(n) * 0x1.0p-24f))

/* A point on a triangle from barycentrics, p = b0·v0 + b1·v1 + b2·v2, and a
 * conservative bound on its absolute error per axis,
 * γ(7)·(|b0·v0| + |b1·v1| + |b2·v2|) (pbrt-v4, Triangle::InteractionFromIntersection),
 * which covers the rounding of the barycentrics from the watertight test. */
INLINE vec3 surface_point(vec3 v0, vec3 v1, vec3 v2, float b1, float b2, vec3* error)
{
    float b0 = 1.0f - b1 - b2;
    vec3 a = v3_scale(v0, b0), b = v3_scale(v1, b1), c = v3_scale(v2, b2);
    *error = v3_scale(v3_add(v3_add(v3_abs(a), v3_abs(b)), v3_abs(c)), GAMMA(7));
    return v3_add(v3_add(a, b), c);
}

INLINE float next_float_up(float v)
{
    v = v == -0.0f ? 0.0f : v;
    int bits = as_int(v);
    float up = as_float(v >= 0.0f ? bits + 1 : bits - 1);
    return isinf(v) && v > 0.0f ? v : up;
}

INLINE float next_float_down(float v)
{
    v = v == 0.0f ? -0.0f : v;
    int bits = as_int(v);
    float down = as_float(v > 0.0f ? bits - 1 : bits + 1);
    return isinf(v) && v < 0.0f ? v : down;
}

/* p moved by `offset` (per axis), then rounded away from p. */
INLINE float offset_component(float p, float offset)
{
    float po = p + offset;
    return offset > 0.0f ? next_float_up(po) : (offset < 0.0f ? next_float_down(po) : po);
}

/* Move p off the surface along the geometric normal n, to the side of w, by
 * the projection of the error box onto n, then round away from p: the origin
 * is then provably on w's side of the true surface, at any scene scale and
 * position (pbrt-v4 OffsetRayOrigin). */
INLINE vec3 offset_ray_origin(vec3 p, vec3 error, vec3 n, vec3 w)
{
    float d = v3_dot(v3_abs(n), error);
    vec3 offset = v3_scale(n, v3_dot(w, n) < 0.0f ? -d : d);
    return v3(offset_component(p.x, offset.x), offset_component(p.y, offset.y), offset_component(p.z, offset.z));
}

/* A ray leaving surface point p (error bound `error`, geometric normal ng)
 * in direction d. */
INLINE Ray spawn_ray(vec3 p, vec3 error, vec3 ng, vec3 d)
{
    Ray r;
    r.origin = offset_ray_origin(p, error, ng, d);
    r.direction = d;
    r.tMax = INFINITY;
    return r;
}

#endif
