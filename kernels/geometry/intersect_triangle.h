/* Watertight ray/triangle intersection (Woop, Benthin, Wald, "Watertight
 * Ray/Triangle Intersection", JCGT 2(1), 2013), for the TRIANGLE_PACKET_WIDTH
 * triangles of one packet at once: every line below is one float4 operation
 * over the packet's triangles. The ray is sheared so it runs along +z from the
 * origin; the three 2-D edge functions then share their inputs between
 * neighbouring triangles, so a ray through a shared edge or vertex hits at
 * least one of them. Both faces are hit; nothing is culled. */
#ifndef WAVEVCM_INTERSECT_TRIANGLE_H
#define WAVEVCM_INTERSECT_TRIANGLE_H

#include "core/ray.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

/* No fused multiply-add contraction: the same ray and triangle then give the
 * same t in every kernel and on every device, so closest-hit, any-hit and
 * the brute-force reference agree bit for bit. */
#pragma OPENCL FP_CONTRACT OFF

#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#if TRIANGLE_PACKET_WIDTH != 4
#error "intersect_packet is written for packets of four triangles (float4)"
#endif

/* Per-ray constants of the shear transform (eq. in §3 of the paper). */
typedef struct ShearedRay {
    float ox, oy, oz; /* the origin, permuted like the axes */
    int kx, ky, kz;   /* permuted axes; kz is the largest |direction| component */
    float sx, sy, sz;
} ShearedRay;

INLINE ShearedRay shear_ray(Ray ray)
{
    ShearedRay s;
    vec3 a = v3_abs(ray.direction);
    /* Without branches: the axes are data, unpredictable for incoherent rays. */
    s.kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    s.kx = s.kz == 2 ? 0 : s.kz + 1;
    s.ky = s.kx == 2 ? 0 : s.kx + 1;
    float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    float dz = d[s.kz];
    int swap = dz < 0.0f; /* keep the winding: swap kx and ky */
    int kx = swap ? s.ky : s.kx, ky = swap ? s.kx : s.ky;
    s.kx = kx;
    s.ky = ky;
    s.sx = d[kx] / dz;
    s.sy = d[ky] / dz;
    s.sz = 1.0f / dz;
    s.ox = o[kx];
    s.oy = o[ky];
    s.oz = o[s.kz];
    return s;
}

/* any(m): whether a lane's sign bit is set. On x86 one movmskps, where
 * PoCL's any() extracts and ORs the lanes (14 instructions against 2; the
 * traversal is bound by instruction count, docs/performance.md, "Ray casting"). */
INLINE bool any_lane(int4 m)
{
#if defined(__SSE__)
    return __builtin_ia32_movmskps(as_float4(m)) != 0;
#else
    return (m.s0 | m.s1 | m.s2 | m.s3) < 0;
#endif
}

/* max(a, b) and min(a, b) of values that are never NaN (finite vertices):
 * one maxps/minps on x86, where fmax and fmin, which must return the other
 * operand for a NaN, take three instructions. */
INLINE float4 max_of(float4 a, float4 b) { return select(b, a, a > b); }
INLINE float4 min_of(float4 a, float4 b) { return select(b, a, a < b); }

INLINE float float4_lane(float4 v, int lane)
{
    return lane == 0 ? v.s0 : lane == 1 ? v.s1 : lane == 2 ? v.s2 : v.s3;
}

/* The nearest hit among the packet's triangles with 0 < t < tMax, lanes
 * whose bit (1 << lane) is set in `excluded` left out: returns its lane, or
 * -1, and sets *t, *b1, *b2 (barycentrics of v1 and v2). */
INLINE int intersect_packet(const ShearedRay* s, __global const TrianglePacket* p, float tMax, int excluded,
                            float* t, float* b1, float* b2)
{
    /* Vertices relative to the origin, sheared (§3, eqs. 2-3). */
    float4 Az = vload4(0, p->v[0][s->kz]) - s->oz;
    float4 Bz = vload4(0, p->v[1][s->kz]) - s->oz;
    float4 Cz = vload4(0, p->v[2][s->kz]) - s->oz;
    float4 Ax = (vload4(0, p->v[0][s->kx]) - s->ox) - s->sx * Az;
    float4 Ay = (vload4(0, p->v[0][s->ky]) - s->oy) - s->sy * Az;
    float4 Bx = (vload4(0, p->v[1][s->kx]) - s->ox) - s->sx * Bz;
    float4 By = (vload4(0, p->v[1][s->ky]) - s->oy) - s->sy * Bz;
    float4 Cx = (vload4(0, p->v[2][s->kx]) - s->ox) - s->sx * Cz;
    float4 Cy = (vload4(0, p->v[2][s->ky]) - s->oy) - s->sy * Cz;

    float4 U = Cx * By - Cy * Bx;
    float4 V = Ax * Cy - Ay * Cx;
    float4 W = Bx * Ay - By * Ax;
#ifdef cl_khr_fp64
    /* An edge function of exactly 0 may be a rounding artefact: redo that
     * triangle's three in double, as the paper prescribes, so the sign test
     * is exact. */
    int4 zero = U == 0.0f || V == 0.0f || W == 0.0f;
    if (any_lane(zero)) {
        double4 ax = convert_double4(Ax), ay = convert_double4(Ay), bx = convert_double4(Bx),
                by = convert_double4(By), cx = convert_double4(Cx), cy = convert_double4(Cy);
        U = select(U, convert_float4(cx * by - cy * bx), zero);
        V = select(V, convert_float4(ax * cy - ay * cx), zero);
        W = select(W, convert_float4(bx * ay - by * ax), zero);
    }
#endif
    float4 det = U + V + W;
    /* Inside: no edge function negative, or none positive (U, V, W are never
     * NaN for finite vertices). */
    int4 hit = (min_of(U, min_of(V, W)) >= 0.0f || max_of(U, max_of(V, W)) <= 0.0f) && det != 0.0f &&
               vload4(0, p->triangle) >= 0;
#ifdef HAS_ALPHA_TEST
    hit = hit && ((int4)(1, 2, 4, 8) & (int4)(excluded)) == (int4)(0); /* only alpha testing excludes lanes */
#endif
    if (!any_lane(hit))
        return -1;

    Az *= s->sz; Bz *= s->sz; Cz *= s->sz;
    float4 T = U * Az + V * Bz + W * Cz;
    /* Divide before comparing: the hit is reported iff the t we return lies
     * in (deltaT, tMax), so closest-hit and any-hit agree at every segment end. */
    float4 invDet = 1.0f / det;
    float4 tHit = T * invDet;
    /* Within (0, tMax) first: since deltaT >= 0 this rejects nothing the
     * test below keeps, and packets whose triangles' planes the ray meets
     * only behind it or past tMax (most, for a shadow ray) skip the bound. */
    hit = hit && tHit < tMax && tHit > 0.0f;
    if (!any_lane(hit))
        return -1;
    /* t must exceed its own rounding error (pbrt-v4, Triangle::Intersect,
     * after Woop et al. §4): a ray that starts on the triangle, e.g. on a
     * plane through the origin where the hit point's error bound and so the
     * ray offset are zero, must not hit it at t ≈ 0. */
    float4 maxZ = max_of(fabs(Az), max_of(fabs(Bz), fabs(Cz)));
    float4 maxX = max_of(fabs(Ax), max_of(fabs(Bx), fabs(Cx)));
    float4 maxY = max_of(fabs(Ay), max_of(fabs(By), fabs(Cy)));
    float4 deltaZ = GAMMA(3) * maxZ;
    float4 deltaX = GAMMA(5) * (maxX + maxZ), deltaY = GAMMA(5) * (maxY + maxZ);
    float4 deltaE = 2.0f * (GAMMA(2) * maxX * maxY + deltaY * maxX + deltaX * maxY);
    float4 maxE = max_of(fabs(U), max_of(fabs(V), fabs(W)));
    float4 deltaT = 3.0f * (GAMMA(3) * maxE * maxZ + deltaE * maxZ + deltaZ * maxE) * fabs(invDet);
    hit = hit && tHit > deltaT;

    /* The nearest lane; on a tie the first. */
    float4 tLane = select((float4)(INFINITY), tHit, hit);
    float nearest = fmin(fmin(tLane.s0, tLane.s1), fmin(tLane.s2, tLane.s3));
    if (!(nearest < tMax))
        return -1;
    int lane = tLane.s0 == nearest ? 0 : tLane.s1 == nearest ? 1 : tLane.s2 == nearest ? 2 : 3;
    *t = nearest;
    *b1 = float4_lane(V * invDet, lane);
    *b2 = float4_lane(W * invDet, lane);
    return lane;
}

#endif
