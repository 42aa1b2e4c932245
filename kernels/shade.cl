/* shade (`-a pt`): at every hit of a camera path, in order,
 *   1. emission seen here (front faces only), MIS-weighted against having
 *      sampled this light from the previous vertex;
 *   2. next-event estimation: sample a light, queue a shadow ray with its
 *      MIS-weighted contribution for `connect`;
 *   3. sample the BSDF to continue (Russian roulette after 3 segments), or end
 *      the path and free the slot.
 * MIS uses the power heuristic (Veach 1997, §9.2.4) between BSDF sampling and
 * light sampling; delta lights and delta lobes take weight 1.
 * Path length counts segments, the camera segment included; a path of
 * `depth` segments ends here at `maxPathLength`. */
#include "bsdf.h"
#include "lights.h"
#include "path_state.h"
#include "queues.h"
#include "rng.h"
#include "surface.h"

inline float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

/* Shades the hit of path `slot`; sets *alive if the path continues (its next
 * ray stored) and *shadowRay if a shadow ray was stored for `connect`. */
inline void shade_hit(__global const float4* triVertices, __global const float4* triNormals,
                      __global const int* triMaterials, __global const Material* materials,
                      __global const Light* lights, __global const float* lightCdf,
                      __global const int* triangleLight, __constant const SceneInfo* scene, uint seed,
                      uint iteration, int maxPathLength, int slot, __global float4* rayOrigins,
                      __global float4* rayDirections, __global const float* hitT,
                      __global const int* hitTriangle, __global const float2* hitBary,
                      __global const int* pathPixel, __global int* pathDepth, __global float4* pathThroughput,
                      __global float* pathPrevPdf, __global float4* shadowOrigins,
                      __global float4* shadowDirections, __global float4* shadowContribution,
                      __global float4* pixelRadiance, bool* aliveOut, bool* shadowOut)
{
    int tri = hitTriangle[slot];
    float3 wo = -rayDirections[slot].xyz;
    SurfaceHit hit = surface_hit(triVertices, triNormals, tri, hitBary[slot], wo);
    int depth = pathDepth[slot];
    int pixel = pathPixel[slot];
    float3 beta = pathThroughput[slot].xyz;
    float3 L = (float3)(0.0f);

#ifdef HAS_EMISSIVE_TRIANGLES
    int light = triangleLight[tri];
    float cosLight = dot(wo, hit.ngF);
    if (light >= 0 && hit.frontSide) {
        float prevPdf = pathPrevPdf[slot];
        float w = 1.0f;
        if (prevPdf > 0.0f)
            w = power_heuristic(prevPdf, triangle_light_pdf(lights[light].pmf, lights[light].area, hitT[slot], cosLight));
        L += w * beta * vload3(0, lights[light].emission);
    }
#endif

    float3 woL = to_local(&hit.frame, wo);
    Bsdf bsdf = make_bsdf(&materials[triMaterials[tri]], woL, hit.frontSide);
    bool alive = depth < maxPathLength && !bsdf_is_black(&bsdf);

    if (alive && bsdf_has_nondelta(&bsdf)) {
        float4 u = rng_uniform4(seed, iteration, (uint)pixel, (uint)depth, 0u);
        LightSample ls;
        if (sample_light(lights, lightCdf, triVertices, scene, hit.p, u.xyz, &ls)) {
            float3 wiL = to_local(&hit.frame, ls.direction);
            if (sides_agree(&hit, ls.direction, wiL) && light_sample_resolved(hit.p, hit.pError, hit.ngF, &ls)) {
                float pdfBsdf, pdfRev;
                float3 f = bsdf_eval(&bsdf, woL, wiL, false, &pdfBsdf, &pdfRev);
                if (max_component(f) > 0.0f) {
                    float w = ls.delta ? 1.0f : power_heuristic(ls.pdf, pdfBsdf);
                    float3 contribution = beta * f * fabs(wiL.z) * ls.radiance * (w / ls.pdf);
                    store_ray(shadowOrigins, shadowDirections, slot, shadow_ray_to_light(hit.p, hit.pError, hit.ngF, &ls));
                    shadowContribution[slot] = (float4)(contribution, 0.0f);
                    *shadowOut = true;
                }
            }
        }
    }

    if (alive) {
        float4 u = rng_uniform4(seed, iteration, (uint)pixel, (uint)depth, 1u);
        BsdfSample bs;
        alive = bsdf_sample(&bsdf, woL, u.xyz, false, &bs);
        float3 wi = to_world(&hit.frame, bs.wi);
        alive = alive && sides_agree(&hit, wi, bs.wi);
        if (alive) {
            beta *= bs.weight;
            if (depth >= 3) { /* Russian roulette: survive with probability q, reweight by 1/q */
                float q = fmin(1.0f, max_component(beta));
                alive = u.w < q;
                beta /= q;
            }
            if (!all(isfinite(beta))) {
                L += (float3)(NAN); /* the sample is dropped and counted by accumulate */
                alive = false;
            }
            alive = alive && max_component(beta) > 0.0f;
        }
        if (alive) {
            store_ray(rayOrigins, rayDirections, slot, spawn_ray(hit.p, hit.pError, hit.ngF, wi));
            pathThroughput[slot] = (float4)(beta, 0.0f);
            pathPrevPdf[slot] = bs.delta ? 0.0f : bs.pdf;
            pathDepth[slot] = depth + 1;
        }
    }

    if (any(L != 0.0f))
        pixelRadiance[pixel] += (float4)(L, 0.0f);
    *aliveOut = alive;
}

__kernel void shade(int capacity, int nextRayQueue, int freeQueue, uint iteration, __global int* queueItems,
                    __global int* queueCounters, __global const float4* triVertices,
                    __global const float4* triNormals, __global const int* triMaterials,
                    __global const Material* materials, __global const Light* lights,
                    __global const float* lightCdf, __global const int* triangleLight,
                    __constant const SceneInfo* scene, uint seed, int maxPathLength,
                    __global float4* rayOrigins, __global float4* rayDirections, __global const float* hitT, __global const int* hitTriangle,
                    __global const float2* hitBary, __global const int* pathPixel,
                    __global int* pathDepth, __global float4* pathThroughput,
                    __global float* pathPrevPdf, __global float4* shadowOrigins,
                    __global float4* shadowDirections, __global float4* shadowContribution,
                    __global float4* pixelRadiance)
{
    __local int scratch[2];
    int slot = queue_item(queueItems, queueCounters, capacity, QUEUE_HITS, get_global_id(0));
    bool alive = false, shadowRay = false;
    if (slot >= 0)
        shade_hit(triVertices, triNormals, triMaterials, materials, lights, lightCdf, triangleLight, scene, seed,
                  iteration, maxPathLength, slot, rayOrigins, rayDirections, hitT, hitTriangle, hitBary, pathPixel,
                  pathDepth, pathThroughput, pathPrevPdf, shadowOrigins, shadowDirections, shadowContribution,
                  pixelRadiance, &alive, &shadowRay);
    queue_push(queueItems, queueCounters, capacity, QUEUE_SHADOW, shadowRay, slot, scratch);
    queue_push(queueItems, queueCounters, capacity, nextRayQueue, alive, slot, scratch);
    queue_push(queueItems, queueCounters, capacity, freeQueue, slot >= 0 && !alive, slot, scratch);
}
