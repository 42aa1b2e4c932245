/* Surface geometry at a hit: the point with its rounding-error bound, the
 * geometric normal from the triangle's winding, the shading normal
 * interpolated from vertex normals when the scene has them, and the local
 * shading frame facing the direction the hit is seen from. */
#ifndef WAVEVCM_SURFACE_H
#define WAVEVCM_SURFACE_H

#include "core/ray.h"
#include "core/sampling.h"
#include "interface/inline.h"

INLINE float3 geometric_normal(__global const float4* triVertices, int tri)
{
    float3 v0 = triVertices[3 * tri].xyz;
    return normalize(cross(triVertices[3 * tri + 1].xyz - v0, triVertices[3 * tri + 2].xyz - v0));
}

#ifdef HAS_VERTEX_NORMALS
/* Falls back to the geometric normal where the interpolated normal vanishes. */
INLINE float3 shading_normal(__global const float4* triNormals, int tri, float2 bary, float3 ng)
{
    float3 n = (1.0f - bary.x - bary.y) * triNormals[3 * tri].xyz +
               bary.x * triNormals[3 * tri + 1].xyz + bary.y * triNormals[3 * tri + 2].xyz;
    float len = length(n);
    return len > 1e-12f ? n / len : ng;
}
#endif

/* The point at barycentrics `bary` of triangle `tri`, with its error bound
 * (the p of surface_hit, for kernels that need only the point first). */
INLINE float3 surface_hit_point(__global const float4* triVertices, int tri, float2 bary, float3* error)
{
    return surface_point(triVertices[3 * tri].xyz, triVertices[3 * tri + 1].xyz, triVertices[3 * tri + 2].xyz,
                         bary.x, bary.y, error);
}

typedef struct SurfaceHit {
    float3 p, pError;
    float3 ngF, nsF;  /* geometric and shading normal, flipped to the side of w */
    Frame frame;      /* around nsF */
    bool frontSide;   /* w is on the side the geometric normal points to */
} SurfaceHit;

/* The hit on triangle `tri` at barycentrics `bary`, seen from direction w
 * (pointing away from the surface). A shading normal on the other side of
 * the surface from w than the geometric one is unusable; the geometric
 * normal replaces it. */
INLINE SurfaceHit surface_hit(__global const float4* triVertices, __global const float4* triNormals, int tri,
                              float2 bary, float3 w)
{
    SurfaceHit h;
    float3 v0 = triVertices[3 * tri].xyz, v1 = triVertices[3 * tri + 1].xyz, v2 = triVertices[3 * tri + 2].xyz;
    h.p = surface_hit_point(triVertices, tri, bary, &h.pError);
    float3 ng = normalize(cross(v1 - v0, v2 - v0));
    h.frontSide = dot(w, ng) > 0.0f;
    h.ngF = h.frontSide ? ng : -ng;
    h.nsF = h.ngF;
#ifdef HAS_VERTEX_NORMALS
    float3 ns = shading_normal(triNormals, tri, bary, ng);
    ns = h.frontSide ? ns : -ns;
    if (dot(ns, w) > 0.0f)
        h.nsF = ns;
#endif
    h.frame = frame_from_normal(h.nsF);
    return h;
}

/* Shading and geometric normal agree on the side of a direction; where they
 * do not, light would leak through the surface, so such directions carry
 * nothing. */
INLINE bool sides_agree(const SurfaceHit* h, float3 dirWorld, float3 dirLocal)
{
    return (dirLocal.z > 0.0f) == (dot(dirWorld, h->ngF) > 0.0f);
}

/* The factor that makes the BSDF with shading normals the adjoint of itself
 * for importance transport (Veach 1997, eq. 5.19):
 * |w_fixed·ns| |w_other·ng| / (|w_fixed·ng| |w_other·ns|), where w_fixed
 * points back along the light path and w_other towards the camera side. */
INLINE float adjoint_shading_correction(const SurfaceHit* h, float3 wFixed, float3 wOther)
{
    float denominator = fabs(dot(wFixed, h->ngF)) * fabs(dot(wOther, h->nsF));
    return denominator > 0.0f ? fabs(dot(wFixed, h->nsF)) * fabs(dot(wOther, h->ngF)) / denominator : 0.0f;
}

#endif
