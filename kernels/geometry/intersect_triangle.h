/* Watertight ray/triangle intersection (Woop, Benthin, Wald, "Watertight
 * Ray/Triangle Intersection", JCGT 2(1), 2013), for PACKET_TEST_WIDTH
 * triangles of a packet at once: every line of intersect_lanes is one
 * vector operation over them. The ray is sheared so it runs along +z from
 * the origin; the three 2-D edge functions then share their inputs between
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

/* Lanes tested at once: a packet of eight in one test where the device has
 * 8-wide float vectors (on AVX CPUs one instruction tests eight triangles as
 * it would four: against packets of four, pt's iterations on the Cornell box
 * 1.07x), otherwise four (a GPU thread runs a vector's lanes one after
 * another, and keeps four lanes' values live, not eight). The host gives
 * devices without AVX trees of packets of four (host/render/SceneBuffers.h);
 * a tree of eights there is tested half by half. floatp and intp hold the
 * lanes. */
#if TRIANGLE_PACKET_WIDTH == 8 && defined(__AVX__)
#define PACKET_TEST_WIDTH 8
#define PACKET_LANE_BITS ((int8)(1, 2, 4, 8, 16, 32, 64, 128))
#else
#define PACKET_TEST_WIDTH 4
#define PACKET_LANE_BITS ((int4)(1, 2, 4, 8))
#endif
#define PACKET_PASTE(name, width) name##width
#define PACKET_NAME_(name, width) PACKET_PASTE(name, width)
#define PACKET_NAME(name) PACKET_NAME_(name, PACKET_TEST_WIDTH) /* float -> float8 */
typedef PACKET_NAME(float) floatp;
typedef PACKET_NAME(int) intp;
#define vloadp PACKET_NAME(vload)
#define vstorep PACKET_NAME(vstore)

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

/* Bit i set: lane i of m has its sign bit set (a comparison's true). On x86
 * one movmskps, where PoCL's any() extracts and ORs the lanes (14
 * instructions against 2; the traversal is bound by instruction count,
 * docs/performance.md, "Ray casting"). */
INLINE int lane_mask(intp m)
{
#if defined(__AVX__) && PACKET_TEST_WIDTH == 8
    return __builtin_ia32_movmskps256(as_float8(m));
#elif defined(__SSE__) && PACKET_TEST_WIDTH == 4
    return __builtin_ia32_movmskps(as_float4(m));
#else
    /* In registers: a private array indexed in a loop lands on a GPU's stack. */
    intp bits = (m >> 31) & PACKET_LANE_BITS;
#if PACKET_TEST_WIDTH == 8
    int4 b = bits.lo | bits.hi;
#else
    int4 b = bits;
#endif
    return b.s0 | b.s1 | b.s2 | b.s3;
#endif
}

/* Whether any lane of m has its sign bit set. */
INLINE bool any_lane(intp m)
{
#if defined(__SSE__)
    return lane_mask(m) != 0; /* one movmskps */
#else
    /* The lanes ORed, no shifts or masks: for sm_90, extend with every
     * scene feature took 150 registers so, 165 through lane_mask. */
#if PACKET_TEST_WIDTH == 8
    int4 b = m.lo | m.hi;
#else
    int4 b = m;
#endif
    return (b.s0 | b.s1 | b.s2 | b.s3) < 0;
#endif
}

/* The index of the lowest set bit of m != 0. */
INLINE int lowest_bit(int m) { return 31 - clz(m & -m); }

/* max(a, b) and min(a, b) of values that are never NaN (finite vertices):
 * one maxps/minps on x86, where fmax and fmin, which must return the other
 * operand for a NaN, take three instructions. */
INLINE floatp max_of(floatp a, floatp b) { return select(b, a, a > b); }
INLINE floatp min_of(floatp a, floatp b) { return select(b, a, a < b); }

INLINE float packet_lane(floatp v, int lane)
{
#if PACKET_TEST_WIDTH == 8
    /* AVX only: one store and one indexed load. */
    float lanes[PACKET_TEST_WIDTH];
    vstorep(v, 0, lanes);
    return lanes[lane];
#else
    /* Selects, which a GPU keeps in registers. */
    return lane == 0 ? v.s0 : lane == 1 ? v.s1 : lane == 2 ? v.s2 : v.s3;
#endif
}

/* The smallest lane of v. */
INLINE float packet_min(floatp v)
{
#if PACKET_TEST_WIDTH == 8
    float4 m = fmin(v.lo, v.hi);
#else
    float4 m = v;
#endif
    return fmin(fmin(m.s0, m.s1), fmin(m.s2, m.s3));
}

#ifdef cl_khr_fp64
/* a·b − c·d per lane, in double (a product of two floats is exact there),
 * rounded to float. */
INLINE float4 difference_of_products4(float4 a, float4 b, float4 c, float4 d)
{
    return convert_float4(convert_double4(a) * convert_double4(b) - convert_double4(c) * convert_double4(d));
}

INLINE floatp difference_of_products(floatp a, floatp b, floatp c, floatp d)
{
#if PACKET_TEST_WIDTH == 8
    /* By halves: without AVX-512 a double8 is passed to and returned from
     * PoCL's conversion functions on the stack (clang warns that it changes
     * the ABI, which every cold build on an AVX2 CPU printed). */
    return (float8)(difference_of_products4(a.lo, b.lo, c.lo, d.lo), difference_of_products4(a.hi, b.hi, c.hi, d.hi));
#else
    return difference_of_products4(a, b, c, d);
#endif
}
#endif

/* The nearest hit among the triangles of lanes [PACKET_TEST_WIDTH · part,
 * PACKET_TEST_WIDTH · (part + 1)) of the packet with 0 < t < tMax, lanes
 * whose bit (1 << lane, counted from the part's first) is set in `excluded`
 * left out: returns its lane in the part, or -1, and sets *t, *b1, *b2
 * (barycentrics of v1 and v2). */
INLINE int intersect_lanes(const ShearedRay* s, __global const TrianglePacket* p, int part, float tMax,
                           int excluded, float* t, float* b1, float* b2)
{
    /* Vertices relative to the origin, sheared (§3, eqs. 2-3). */
    floatp Az = vloadp(part, p->v[0][s->kz]) - s->oz;
    floatp Bz = vloadp(part, p->v[1][s->kz]) - s->oz;
    floatp Cz = vloadp(part, p->v[2][s->kz]) - s->oz;
    floatp Ax = (vloadp(part, p->v[0][s->kx]) - s->ox) - s->sx * Az;
    floatp Ay = (vloadp(part, p->v[0][s->ky]) - s->oy) - s->sy * Az;
    floatp Bx = (vloadp(part, p->v[1][s->kx]) - s->ox) - s->sx * Bz;
    floatp By = (vloadp(part, p->v[1][s->ky]) - s->oy) - s->sy * Bz;
    floatp Cx = (vloadp(part, p->v[2][s->kx]) - s->ox) - s->sx * Cz;
    floatp Cy = (vloadp(part, p->v[2][s->ky]) - s->oy) - s->sy * Cz;

    floatp U = Cx * By - Cy * Bx;
    floatp V = Ax * Cy - Ay * Cx;
    floatp W = Bx * Ay - By * Ax;
#ifdef cl_khr_fp64
    /* An edge function of exactly 0 may be a rounding artefact: redo that
     * triangle's three in double, as the paper prescribes, so the sign test
     * is exact. */
    intp zero = U == 0.0f || V == 0.0f || W == 0.0f;
    if (any_lane(zero)) {
        U = select(U, difference_of_products(Cx, By, Cy, Bx), zero);
        V = select(V, difference_of_products(Ax, Cy, Ay, Cx), zero);
        W = select(W, difference_of_products(Bx, Ay, By, Ax), zero);
    }
#endif
    floatp det = U + V + W;
    /* Inside: no edge function negative, or none positive (U, V, W are never
     * NaN for finite vertices). */
    intp hit = (min_of(U, min_of(V, W)) >= 0.0f || max_of(U, max_of(V, W)) <= 0.0f) && det != 0.0f &&
               vloadp(part, p->triangle) >= 0;
#ifdef HAS_ALPHA_TEST
    hit = hit && (PACKET_LANE_BITS & (intp)(excluded)) == (intp)(0); /* only alpha testing excludes lanes */
#endif
    if (!any_lane(hit))
        return -1;

    Az *= s->sz; Bz *= s->sz; Cz *= s->sz;
    floatp T = U * Az + V * Bz + W * Cz;
    /* Divide before comparing: the hit is reported iff the t we return lies
     * in (deltaT, tMax), so closest-hit and any-hit agree at every segment end. */
    floatp invDet = 1.0f / det;
    floatp tHit = T * invDet;
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
    floatp maxZ = max_of(fabs(Az), max_of(fabs(Bz), fabs(Cz)));
    floatp maxX = max_of(fabs(Ax), max_of(fabs(Bx), fabs(Cx)));
    floatp maxY = max_of(fabs(Ay), max_of(fabs(By), fabs(Cy)));
    floatp deltaZ = GAMMA(3) * maxZ;
    floatp deltaX = GAMMA(5) * (maxX + maxZ), deltaY = GAMMA(5) * (maxY + maxZ);
    floatp deltaE = 2.0f * (GAMMA(2) * maxX * maxY + deltaY * maxX + deltaX * maxY);
    floatp maxE = max_of(fabs(U), max_of(fabs(V), fabs(W)));
    floatp deltaT = 3.0f * (GAMMA(3) * maxE * maxZ + deltaE * maxZ + deltaZ * maxE) * fabs(invDet);
    hit = hit && tHit > deltaT;

    /* The nearest lane; on a tie the first. */
    floatp tLane = select((floatp)(INFINITY), tHit, hit);
    float nearest = packet_min(tLane);
    if (!(nearest < tMax))
        return -1;
    int lane = lowest_bit(lane_mask(tLane == nearest));
    *t = nearest;
    *b1 = packet_lane(V * invDet, lane);
    *b2 = packet_lane(W * invDet, lane);
    return lane;
}

/* The nearest hit among the packet's triangles with 0 < t < tMax, lanes
 * whose bit (1 << lane) is set in `excluded` left out: returns its lane, or
 * -1, and sets *t, *b1, *b2 (barycentrics of v1 and v2); on a tie the first
 * lane. */
INLINE int intersect_packet(const ShearedRay* s, __global const TrianglePacket* p, float tMax, int excluded,
                            float* t, float* b1, float* b2)
{
#if PACKET_TEST_WIDTH == TRIANGLE_PACKET_WIDTH
    return intersect_lanes(s, p, 0, tMax, excluded, t, b1, b2);
#else
    /* Half by half, in a loop that is not unrolled: unrolled, the GPU
     * compiler scheduled both halves' loads together (extend for sm_90: 231
     * registers, against 162 as a loop). Only nearer hits replace the first
     * half's; a second half of padding alone ends the packet. */
    int lane = -1;
#pragma nounroll
    for (int part = 0; part < TRIANGLE_PACKET_WIDTH / PACKET_TEST_WIDTH; ++part) {
        if (p->triangle[part * PACKET_TEST_WIDTH] < 0)
            break;
        int found = intersect_lanes(s, p, part, lane >= 0 ? *t : tMax, excluded >> (part * PACKET_TEST_WIDTH),
                                    t, b1, b2);
        if (found >= 0)
            lane = part * PACKET_TEST_WIDTH + found;
    }
    return lane;
#endif
}

#endif
