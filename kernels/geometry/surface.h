/* Surface geometry at a hit: the point with its rounding-error bound, the
 * geometric normal from the triangle's winding, the shading normal
 * interpolated from vertex normals when the scene has them, and the local
 * shading frame facing the direction the hit is seen from. */
#ifndef WAVEVCM_SURFACE_H
#define WAVEVCM_SURFACE_H

#include "core/ray.h"
#include "core/sampling.h"
#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

/* Vertex k (0-2) of triangle `tri`; `normals` work the same way. */
INLINE vec3 triangle_vertex(__global const float4* triVertices, int tri, int k)
{
    return load_vec3(triVertices, 3 * tri + k);
}

INLINE vec3 triangle_normal(vec3 v0, vec3 v1, vec3 v2) { return v3_normalize(v3_cross(v3_sub(v1, v0), v3_sub(v2, v0))); }

#ifdef HAS_VERTEX_NORMALS
/* Falls back to the geometric normal where the interpolated normal vanishes. */
INLINE vec3 shading_normal(__global const float4* triNormals, int tri, vec2 bary, vec3 ng)
{
    vec3 n = v3_add(v3_add(v3_scale(triangle_vertex(triNormals, tri, 0), 1.0f - bary.x - bary.y),
                           v3_scale(triangle_vertex(triNormals, tri, 1), bary.x)),
                    v3_scale(triangle_vertex(triNormals, tri, 2), bary.y));
    float len = v3_length(n);
    return len > 1e-12f ? v3_div(n, len) : ng;
}
#endif

/* The point at barycentrics `bary` of triangle `tri`, with its error bound
 * (the p of surface_hit, for kernels that need only the point first). */
INLINE vec3 surface_hit_point(__global const float4* triVertices, int tri, vec2 bary, vec3* error)
{
    return surface_point(triangle_vertex(triVertices, tri, 0), triangle_vertex(triVertices, tri, 1),
                         triangle_vertex(triVertices, tri, 2), bary.x, bary.y, error);
}

typedef struct SurfaceHit {
    vec3 p, pError;
    vec3 ngF, nsF;    /* geometric and shading normal, flipped to the side of w */
    Frame frame;      /* around nsF */
    bool frontSide;   /* w is on the side the geometric normal points to */
} SurfaceHit;

/* Makes ns (a unit normal on the side the file's normals face) h's shading
 * normal, turned to w's side as the geometric one is, and sets the frame
 * around it. A shading normal on the other side of the surface from w than
 * the geometric one is unusable: h keeps the normal it has. */
INLINE void set_shading_normal(SurfaceHit* h, vec3 ns, vec3 w)
{
    ns = h->frontSide ? ns : v3_neg(ns);
    h->nsF = v3_dot(ns, w) > 0.0f ? ns : h->nsF;
    h->frame = frame_from_normal(h->nsF);
}

/* The hit on triangle `tri` at barycentrics `bary`, seen from direction w
 * (pointing away from the surface), shaded with the interpolated vertex
 * normal where the scene has them (the geometric normal otherwise). */
INLINE SurfaceHit surface_hit(__global const float4* triVertices, __global const float4* triNormals, int tri,
                              vec2 bary, vec3 w)
{
    SurfaceHit h;
    vec3 v0 = triangle_vertex(triVertices, tri, 0), v1 = triangle_vertex(triVertices, tri, 1),
         v2 = triangle_vertex(triVertices, tri, 2);
    h.p = surface_point(v0, v1, v2, bary.x, bary.y, &h.pError);
    vec3 ng = triangle_normal(v0, v1, v2);
    h.frontSide = v3_dot(w, ng) > 0.0f;
    h.ngF = h.frontSide ? ng : v3_neg(ng);
    h.nsF = h.ngF;
#ifdef HAS_VERTEX_NORMALS
    set_shading_normal(&h, shading_normal(triNormals, tri, bary, ng), w);
#else
    h.frame = frame_from_normal(h.nsF);
#endif
    return h;
}

/* A SurfaceHit as stored for later kernels (SurfaceRecord, in light
 * vertices), and back: the frame follows from the shading normal as
 * set_shading_normal makes it. */
INLINE SurfaceRecord surface_record(const SurfaceHit* h)
{
    SurfaceRecord r;
    store3(r.position, h->p);
    store3(r.positionError, h->pError);
    store3(r.geometricNormal, h->ngF);
    store3(r.shadingNormal, h->nsF);
    r.frontSide = h->frontSide ? 1 : 0;
    r.pad0 = r.pad1 = r.pad2 = 0.0f;
    return r;
}

INLINE SurfaceHit recorded_surface_hit(__global const SurfaceRecord* r)
{
    SurfaceHit h;
    h.p = load3(r->position);
    h.pError = load3(r->positionError);
    h.ngF = load3(r->geometricNormal);
    h.nsF = load3(r->shadingNormal);
    h.frame = frame_from_normal(h.nsF);
    h.frontSide = r->frontSide != 0;
    return h;
}

/* Shading and geometric normal agree on the side of a direction; where they
 * do not, light would leak through the surface, so such directions carry
 * nothing. */
INLINE bool sides_agree(const SurfaceHit* h, vec3 dirWorld, vec3 dirLocal)
{
    return (dirLocal.z > 0.0f) == (v3_dot(dirWorld, h->ngF) > 0.0f);
}

/* The factor that makes the BSDF with shading normals the adjoint of itself
 * for importance transport (Veach 1997, eq. 5.19):
 * |w_fixed·ns| |w_other·ng| / (|w_fixed·ng| |w_other·ns|), where w_fixed
 * points back along the light path and w_other towards the camera side. */
INLINE float adjoint_shading_correction(const SurfaceHit* h, vec3 wFixed, vec3 wOther)
{
    float denominator = fabs(v3_dot(wFixed, h->ngF)) * fabs(v3_dot(wOther, h->nsF));
    return denominator > 0.0f ? fabs(v3_dot(wFixed, h->nsF)) * fabs(v3_dot(wOther, h->ngF)) / denominator : 0.0f;
}

#endif
