/* Test-only kernels: a brute-force reference for the BVH traversal (the same
 * packet triangle test over every triangle, in BVH order) and rays spawned from surface points
 * with the production offset. */
#include "geometry/bvh_traversal.h"
#include "transport/path_state.h"

__kernel void brute_force_closest(__global const TrianglePacket* allTriangles, int packetCount,
                                  __global const float4* rayOrigins,
                                  __global const float4* rayDirections, int rayCount,
                                  __global float* hitT, __global int* hitTriangle)
{
    int i = get_global_id(0);
    if (i >= rayCount)
        return;
    Ray ray = load_ray(rayOrigins, rayDirections, i);
    ShearedRay sheared = shear_ray(ray);
    float tMax = ray.tMax;
    int found = -1;
    for (int p = 0; p < packetCount; ++p) {
        float t, b1, b2;
        int lane = intersect_packet(&sheared, &allTriangles[p], tMax, 0, &t, &b1, &b2);
        if (lane >= 0) {
            tMax = t;
            found = allTriangles[p].triangle[lane];
        }
    }
    hitT[i] = found >= 0 ? tMax : INFINITY;
    hitTriangle[i] = found;
}

/* From the point with barycentrics (b1, b2) on triangle `sources[i]`, offset
 * along the geometric normal to the side of directions[i], trace closest hit. */
__kernel void spawn_and_trace(__global const BvhNode* nodes, __global const TrianglePacket* packets,
                              __global const float4* triVertices,
                              __global const int* sources, __global const float2* barycentrics,
                              __global const float4* directions, int rayCount,
                              __global float* hitT, __global int* hitTriangle)
{
    int i = get_global_id(0);
    if (i >= rayCount)
        return;
    int tri = sources[i];
    vec3 v0 = load_vec3(triVertices, 3 * tri), v1 = load_vec3(triVertices, 3 * tri + 1),
         v2 = load_vec3(triVertices, 3 * tri + 2);
    vec2 b = load_vec2(barycentrics, i);
    vec3 error;
    vec3 p = surface_point(v0, v1, v2, b.x, b.y, &error);
    vec3 ng = v3_normalize(v3_cross(v3_sub(v1, v0), v3_sub(v2, v0)));
    Hit hit;
    trace_ray(nodes, packets, spawn_ray(p, error, ng, load_vec3(directions, i)), false, &hit, 0);
    hitT[i] = hit.triangle >= 0 ? hit.t : INFINITY;
    hitTriangle[i] = hit.triangle;
}

/* Any hit along each ray up to direction.w, with the production traversal. */
__kernel void any_hit(__global const BvhNode* nodes, __global const TrianglePacket* packets,
                      __global const float4* rayOrigins, __global const float4* rayDirections, int rayCount,
                      __global int* occluded)
{
    int i = get_global_id(0);
    if (i >= rayCount)
        return;
    Hit hit;
    occluded[i] = trace_ray(nodes, packets, load_ray(rayOrigins, rayDirections, i), true, &hit, 0);
}
