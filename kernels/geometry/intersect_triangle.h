/* Watertight ray/triangle intersection (Woop, Benthin, Wald, "Watertight
 * Ray/Triangle Intersection", JCGT 2(1), 2013). The ray is sheared so it runs
 * along +z from the origin; the three 2-D edge functions then share their
 * inputs between neighbouring triangles, so a ray through a shared edge or
 * vertex hits at least one of them. Both faces are hit; nothing is culled. */
#ifndef WAVEVCM_INTERSECT_TRIANGLE_H
#define WAVEVCM_INTERSECT_TRIANGLE_H

#include "core/ray.h"
#include "interface/inline.h"

/* No fused multiply-add contraction: the same ray and triangle then give the
 * same t in every kernel and on every device, so closest-hit, any-hit and
 * the brute-force reference agree bit for bit. */
#pragma OPENCL FP_CONTRACT OFF

#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

/* Per-ray constants of the shear transform (eq. in §3 of the paper). */
typedef struct ShearedRay {
    float3 origin;
    int kx, ky, kz;  /* permuted axes; kz is the largest |direction| component */
    float sx, sy, sz;
} ShearedRay;

INLINE float component(float3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

INLINE ShearedRay shear_ray(Ray ray)
{
    ShearedRay s;
    float3 a = fabs(ray.direction);
    s.kz = (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    s.kx = s.kz == 2 ? 0 : s.kz + 1;
    s.ky = s.kx == 2 ? 0 : s.kx + 1;
    float dz = component(ray.direction, s.kz);
    if (dz < 0.0f) { /* keep the winding: swap kx and ky */
        int t = s.kx; s.kx = s.ky; s.ky = t;
    }
    s.sx = component(ray.direction, s.kx) / dz;
    s.sy = component(ray.direction, s.ky) / dz;
    s.sz = 1.0f / dz;
    s.origin = ray.origin;
    return s;
}

/* Returns true and sets *t, *b1, *b2 (barycentrics of v1 and v2) if the ray
 * hits the triangle with 0 < t < tMax. */
INLINE bool intersect_triangle(const ShearedRay* s, float3 v0, float3 v1, float3 v2, float tMax,
                               float* t, float* b1, float* b2)
{
    float3 A = v0 - s->origin, B = v1 - s->origin, C = v2 - s->origin;
    float Az = component(A, s->kz), Bz = component(B, s->kz), Cz = component(C, s->kz);
    float Ax = component(A, s->kx) - s->sx * Az, Ay = component(A, s->ky) - s->sy * Az;
    float Bx = component(B, s->kx) - s->sx * Bz, By = component(B, s->ky) - s->sy * Bz;
    float Cx = component(C, s->kx) - s->sx * Cz, Cy = component(C, s->ky) - s->sy * Cz;

    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
#ifdef cl_khr_fp64
    /* An edge function of exactly 0 may be a rounding artefact: redo all three
     * in double, as the paper prescribes, so the sign test is exact. */
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        U = (float)((double)Cx * (double)By - (double)Cy * (double)Bx);
        V = (float)((double)Ax * (double)Cy - (double)Ay * (double)Cx);
        W = (float)((double)Bx * (double)Ay - (double)By * (double)Ax);
    }
#endif
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f))
        return false;
    float det = U + V + W;
    if (det == 0.0f)
        return false;

    Az *= s->sz; Bz *= s->sz; Cz *= s->sz;
    float T = U * Az + V * Bz + W * Cz;
    /* Divide before comparing: the hit is reported iff the t we return lies
     * in (deltaT, tMax), so closest-hit and any-hit agree at every segment end. */
    float invDet = 1.0f / det;
    float tHit = T * invDet;
    if (!(tHit < tMax))
        return false;
    /* t must exceed its own rounding error (pbrt-v4, Triangle::Intersect,
     * after Woop et al. §4): a ray that starts on the triangle, e.g. on a
     * plane through the origin where the hit point's error bound and so the
     * ray offset are zero, must not hit it at t ≈ 0. */
    float maxZ = fmax(fabs(Az), fmax(fabs(Bz), fabs(Cz)));
    float maxX = fmax(fabs(Ax), fmax(fabs(Bx), fabs(Cx)));
    float maxY = fmax(fabs(Ay), fmax(fabs(By), fabs(Cy)));
    float deltaZ = GAMMA(3) * maxZ;
    float deltaX = GAMMA(5) * (maxX + maxZ), deltaY = GAMMA(5) * (maxY + maxZ);
    float deltaE = 2.0f * (GAMMA(2) * maxX * maxY + deltaY * maxX + deltaX * maxY);
    float maxE = fmax(fabs(U), fmax(fabs(V), fabs(W)));
    float deltaT = 3.0f * (GAMMA(3) * maxE * maxZ + deltaE * maxZ + deltaZ * maxE) * fabs(invDet);
    if (!(tHit > deltaT))
        return false;
    *t = tHit;
    *b1 = V * invDet;
    *b2 = W * invDet;
    return true;
}

#endif
