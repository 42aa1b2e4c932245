/* Closest-hit and any-hit traversal of the flattened BVH: one routine, the
 * any-hit variant returns at the first intersection found. */
#ifndef WAVEVCM_BVH_TRAVERSAL_H
#define WAVEVCM_BVH_TRAVERSAL_H

#include "interface/inline.h"
#include "interface/shared_types.h"
#include "intersect_triangle.h"

/* The host builds trees at most this deep (host/bvh/Bvh.cpp), so the stack
 * cannot overflow. */
#define BVH_STACK_SIZE 64

typedef struct Hit {
    float t;
    int triangle; /* index into the BVH-ordered triangle arrays; -1 = miss */
    float b1, b2; /* barycentric weights of vertices 1 and 2 */
} Hit;

/* Slab test. invDir = 1/direction may hold ±∞ for axis-parallel rays; where
 * the origin then lies exactly on a slab plane, 0·∞ = NaN stands for "inside
 * the slab on this axis" and is replaced by -∞ (near) or +∞ (far), so rays
 * along box faces and through edges are not culled. The far distance is
 * enlarged by 1 + 2γ(3) (Ize, "Robust BVH Ray Traversal", JCGT 2013) so
 * rounding never culls a box the ray touches, which keeps the watertight
 * triangle test watertight through the tree. */
INLINE bool ray_hits_box(float3 origin, float3 invDir, float3 lo, float3 hi, float tMax)
{
    float3 t0 = (lo - origin) * invDir, t1 = (hi - origin) * invDir;
    t0 = select(t0, -invDir, isnan(t0));
    t1 = select(t1, invDir, isnan(t1));
    float3 tNear = fmin(t0, t1), tFar = fmax(t0, t1);
    float enter = fmax(fmax(tNear.x, tNear.y), fmax(tNear.z, 0.0f));
    float leave = fmin(fmin(tFar.x, tFar.y), fmin(tFar.z, tMax)) * 1.0000004f;
    return enter <= leave;
}

INLINE float3 load_float3(__global const float* p) { return (float3)(p[0], p[1], p[2]); }

/* Returns whether anything was hit before ray.tMax. With anyHit the first hit
 * found ends the search and *hit holds that hit, not the closest. */
INLINE bool trace_ray(__global const BvhNode* nodes, __global const float4* triVertices, Ray ray,
                      bool anyHit, Hit* hit)
{
    ShearedRay sheared = shear_ray(ray);
    float3 invDir = 1.0f / ray.direction;
    float tMax = ray.tMax;
    hit->triangle = -1;

    int stack[BVH_STACK_SIZE];
    int stackSize = 0;
    int nodeIndex = 0;
    for (;;) {
        __global const BvhNode* node = &nodes[nodeIndex];
        if (ray_hits_box(ray.origin, invDir, load_float3(node->lo), load_float3(node->hi), tMax)) {
            if (node->primCount > 0) {
                int end = node->offset + node->primCount;
                for (int tri = node->offset; tri < end; ++tri) {
                    float t, b1, b2;
                    if (intersect_triangle(&sheared, triVertices[3 * tri].xyz,
                                           triVertices[3 * tri + 1].xyz,
                                           triVertices[3 * tri + 2].xyz, tMax, &t, &b1, &b2)) {
                        tMax = t;
                        hit->t = t;
                        hit->triangle = tri;
                        hit->b1 = b1;
                        hit->b2 = b2;
                        if (anyHit)
                            return true;
                    }
                }
            } else {
                /* Visit the child on the ray's near side of the split first. */
                bool nearIsSecond = component(ray.direction, node->axis) < 0.0f;
                stack[stackSize++] = nearIsSecond ? nodeIndex + 1 : node->offset;
                nodeIndex = nearIsSecond ? node->offset : nodeIndex + 1;
                continue;
            }
        }
        if (stackSize == 0)
            break;
        nodeIndex = stack[--stackSize];
    }
    return hit->triangle >= 0;
}

#endif
