/* Path state in structure-of-arrays form: one array per field, indexed by
 * path slot. Rays pack tMax into direction.w. */
#ifndef WAVEVCM_PATH_STATE_H
#define WAVEVCM_PATH_STATE_H

#include "ray.h"

/* Bits of pathFlags. */
#define PATH_FINITE_LIGHT 1 /* a light path from a light with a position */
#define PATH_SPECULAR 2     /* a camera path with only delta scattering so far */

inline Ray load_ray(__global const float4* origins, __global const float4* directions, int slot)
{
    float4 o = origins[slot], d = directions[slot];
    Ray r;
    r.origin = o.xyz;
    r.direction = d.xyz;
    r.tMax = d.w;
    return r;
}

inline void store_ray(__global float4* origins, __global float4* directions, int slot, Ray r)
{
    origins[slot] = (float4)(r.origin, 0.0f);
    directions[slot] = (float4)(r.direction, r.tMax);
}

#endif
