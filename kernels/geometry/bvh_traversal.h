/* Closest-hit and any-hit traversal of the wide BVH (BvhNode in
 * interface/shared_types.h): one routine, the any-hit variant returns at the
 * first intersection found. A node visit tests all BVH_WIDTH child boxes with
 * one vector operation per slab plane and visits the children it hits near to
 * far; a leaf tests its triangles a packet at a time (intersect_triangle.h). */
#ifndef WAVEVCM_BVH_TRAVERSAL_H
#define WAVEVCM_BVH_TRAVERSAL_H

#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "interface/shared_types.h"
#include "intersect_triangle.h"
#include "materials/alpha.h"

#if BVH_WIDTH == 8
typedef float8 floatw;
#define vloadw vload8
#define vstorew vstore8
#elif BVH_WIDTH == 4
typedef float4 floatw;
#define vloadw vload4
#define vstorew vstore4
#else
#error "BVH_WIDTH must be 4 or 8"
#endif

typedef struct Hit {
    float t;
    int triangle; /* index into the BVH-ordered triangle arrays; -1 = miss */
    float b1, b2; /* barycentric weights of vertices 1 and 2 */
} Hit;

/* Per-ray constants of the slab test. near[a] is the offset, in floats into
 * BvhNode.bounds, of the child boxes' plane the ray enters through on axis a
 * (lower bound if the direction is positive), far[a] of the one it leaves
 * through. A plane's distance is (origin - plane) · (-1/direction), the
 * same number as (plane - origin) / direction, but with the plane second in
 * the subtraction x86 reads it from memory in the same instruction (six
 * instructions fewer per node visit). */
typedef struct BoxRay {
    float3 origin, negInvDir;
    int near[3], far[3];
} BoxRay;

INLINE BoxRay box_ray(Ray ray)
{
    BoxRay r;
    r.origin = to_float3(ray.origin);
    float3 invDir = 1.0f / to_float3(ray.direction);
    r.negInvDir = -invDir;
    /* 3 · BVH_WIDTH where the direction is negative: the upper planes. */
    int3 flip = (as_int3(invDir) >> 31) & (3 * BVH_WIDTH);
    int3 near = (int3)(0, 1, 2) * BVH_WIDTH + flip, far = (int3)(3, 4, 5) * BVH_WIDTH - flip;
    r.near[0] = near.x; r.near[1] = near.y; r.near[2] = near.z;
    r.far[0] = far.x; r.far[1] = far.y; r.far[2] = far.z;
    return r;
}

/* max(a, b) and min(a, b) for b never NaN, a NaN giving b: fmax and fmin
 * there, but one instruction on x86 (maxps/minps return their second operand
 * when either is NaN) where fmax/fmin take three. */
INLINE floatw max_skipping_nan(floatw a, floatw b) { return select(b, a, a > b); }
INLINE floatw min_skipping_nan(floatw a, floatw b) { return select(b, a, a < b); }

/* Slab test of every child box: *enter and *leave get each child's entry
 * and exit distances; a child is hit where enter <= leave. negInvDir may hold
 * ±∞ for axis-parallel rays; where the origin then lies exactly on a slab
 * plane, 0·∞ = NaN stands for "inside the slab on this axis", which the
 * maximum and minimum skip (each takes the plane's value, maybe NaN, first
 * and the result so far, never NaN, second), so rays along box faces and
 * through edges are not culled. The exit distance is enlarged by 1 + 2γ(3)
 * (Ize, "Robust BVH Ray Traversal", JCGT 2013) so rounding never culls a box
 * the ray touches, which keeps the watertight triangle test watertight
 * through the tree. An empty slot (lo = +∞, hi = -∞) enters at +∞ and
 * leaves at -∞. */
INLINE void intersect_child_boxes(__global const BvhNode* node, const BoxRay* r, float tMax, floatw* enter,
                                  floatw* leave)
{
    __global const float* bounds = &node->bounds[0][0];
    floatw nx = (r->origin.x - vloadw(0, bounds + r->near[0])) * r->negInvDir.x;
    floatw ny = (r->origin.y - vloadw(0, bounds + r->near[1])) * r->negInvDir.y;
    floatw nz = (r->origin.z - vloadw(0, bounds + r->near[2])) * r->negInvDir.z;
    floatw fx = (r->origin.x - vloadw(0, bounds + r->far[0])) * r->negInvDir.x;
    floatw fy = (r->origin.y - vloadw(0, bounds + r->far[1])) * r->negInvDir.y;
    floatw fz = (r->origin.z - vloadw(0, bounds + r->far[2])) * r->negInvDir.z;
    *enter = max_skipping_nan(nz, max_skipping_nan(ny, max_skipping_nan(nx, (floatw)(0.0f))));
    *leave = min_skipping_nan(fz, min_skipping_nan(fy, min_skipping_nan(fx, (floatw)(tMax)))) * 1.0000004f;
}

/* Bit c set: child c is hit (enter <= leave). One movmskps on x86. */
INLINE int child_hit_mask(floatw enter, floatw leave)
{
#if defined(__AVX__) && BVH_WIDTH == 8
    return __builtin_ia32_movmskps256(as_float8(enter <= leave));
#elif defined(__SSE__) && BVH_WIDTH == 4
    return __builtin_ia32_movmskps(as_float4(enter <= leave));
#else
    float e[BVH_WIDTH], l[BVH_WIDTH];
    vstorew(enter, 0, e);
    vstorew(leave, 0, l);
    int m = 0;
    for (int c = 0; c < BVH_WIDTH; ++c)
        m |= (e[c] <= l[c]) << c;
    return m;
#endif
}

/* A stack entry is skipped when popped if the ray, shortened since it was
 * pushed, now ends before the box: the same test as enter <= leave above. */
INLINE bool box_still_ahead(float enter, float tMax) { return enter <= tMax * 1.0000004f; }

/* Returns whether anything was hit before ray.tMax. With anyHit the first hit
 * found ends the search and *hit holds that hit, not the closest. `scene`
 * (0 for none) gives the materials whose alpha decides where a ray stops
 * (materials/alpha.h), in scenes with alpha-tested materials. */
INLINE bool trace_ray(__global const BvhNode* nodes, __global const TrianglePacket* packets, Ray ray,
                      bool anyHit, Hit* hit, const RenderBuffers* scene)
{
    ShearedRay sheared = shear_ray(ray);
    BoxRay boxRay = box_ray(ray);
    float tMax = ray.tMax;
    /* Every field set, here and in the leaf loop's t, b1, b2: PoCL keeps a
     * value that may be read unset in a per-work-item array in memory,
     * loaded and stored again for every ray. */
    hit->triangle = -1;
    hit->t = INFINITY;
    hit->b1 = hit->b2 = 0.0f;

    /* Entries: a node index (>= 0) or a leaf (< 0, as in BvhNode.child),
     * with the distance at which the ray enters its box. */
    int stackItem[BVH_STACK_SIZE];
    float stackEnter[BVH_STACK_SIZE];
    int stackSize = 0;
    int item = 0;
    for (;;) {
        if (item >= 0) {
            /* Interior node: the nearest child hit is visited next, kept in
             * registers (popping it back from the stack put a store and a
             * load on the path to the next node: 0-10 % slower); the others
             * are pushed by insertion into the top of the stack, farthest
             * deepest. The order is that of pushing them all and popping.
             * The children hit come from one mask, lowest index first: no
             * instruction for the children missed. */
            __global const BvhNode* node = &nodes[item];
            floatw enterw, leavew;
            intersect_child_boxes(node, &boxRay, tMax, &enterw, &leavew);
            float enter[BVH_WIDTH];
            vstorew(enterw, 0, enter);
            int hitMask = child_hit_mask(enterw, leavew);
            if (hitMask != 0) {
                int c = lowest_bit(hitMask);
                hitMask &= hitMask - 1;
                int nearItem = node->child[c];
                /* Any hit: leaves, the cheapest candidates, before interior
                 * nodes (the ray is never shortened, so no entry is culled). */
                float nearKey = anyHit && nearItem < 0 ? -1.0f : enter[c];
                int base = stackSize;
                while (hitMask != 0) {
                    c = lowest_bit(hitMask);
                    hitMask &= hitMask - 1;
                    int child = node->child[c];
                    float key = anyHit && child < 0 ? -1.0f : enter[c];
                    /* Nearer: the previous nearest goes to the stack (on a tie
                     * too: the later child first, as popping would). */
                    if (key <= nearKey) {
                        int t = nearItem; nearItem = child; child = t;
                        float tk = nearKey; nearKey = key; key = tk;
                    }
                    int j = stackSize++;
                    for (; j > base && stackEnter[j - 1] < key; --j) {
                        stackItem[j] = stackItem[j - 1];
                        stackEnter[j] = stackEnter[j - 1];
                    }
                    stackItem[j] = child;
                    stackEnter[j] = key;
                }
                item = nearItem;
                continue;
            }
        } else {
            /* Leaf: its packets, in order. */
            int first = (~item) >> 3, end = first + ((~item) & 7) + 1;
            for (int p = first; p < end; ++p) {
                float t = 0.0f, b1 = 0.0f, b2 = 0.0f;
                int lane = intersect_packet(&sheared, &packets[p], tMax, 0, &t, &b1, &b2);
#ifdef HAS_ALPHA_TEST
                /* A hit the surface's alpha lets through: the packet's next nearest. */
                for (int excluded = 0; lane >= 0 && scene &&
                                       !alpha_stops_ray(scene, packets[p].triangle[lane], b1, b2, ray);) {
                    excluded |= 1 << lane;
                    lane = intersect_packet(&sheared, &packets[p], tMax, excluded, &t, &b1, &b2);
                }
#endif
                if (lane >= 0) {
                    tMax = t;
                    hit->t = t;
                    hit->triangle = packets[p].triangle[lane];
                    hit->b1 = b1;
                    hit->b2 = b2;
                    if (anyHit)
                        return true;
                }
            }
        }
        /* Next: the top of the stack, skipping boxes now beyond the hit. */
        do {
            if (stackSize == 0)
                return hit->triangle >= 0;
            --stackSize;
        } while (!box_still_ahead(stackEnter[stackSize], tMax));
        item = stackItem[stackSize];
    }
}

#endif
