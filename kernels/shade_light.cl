/* shade_light (`-a lt`, `-a bpt`): at every hit of a light sub-path, in
 * order (SmallVCM's light pass, vertexcm.hxx),
 *   1. convert the MIS quantities of the last segment to area measure;
 *   2. at a vertex with a non-delta BSDF: store it in the light-vertex buffer
 *      for vertex connection (bpt), and connect it to the camera (t = 1):
 *      queue a shadow ray whose contribution `connect_splat` adds to the
 *      pixel the vertex projects to;
 *   3. sample the adjoint BSDF to continue, with Russian roulette by the
 *      material's continuation probability, or end the path.
 * Light paths carry importance: BSDFs are evaluated in their adjoint form,
 * with Veach's shading-normal correction. Path length counts segments; a
 * vertex `depth` segments from the light is only worth continuing from if a
 * full path through the next vertex (at least one more segment to the
 * camera) still fits in maxPathLength. */
#include "bsdf.h"
#include "camera.h"
#include "lights.h"
#include "mis.h"
#include "path_state.h"
#include "queues.h"
#include "rng.h"
#include "surface.h"

/* int, not bool, flags: rusticl (Mesa 22.3) loses bool members of a struct
 * returned from a function. */
typedef struct LightHitResult {
    int alive, shadowRay, storeVertex;
    LightVertex vertex;
} LightHitResult;

inline LightHitResult shade_light_hit(
    int slot, uint iteration, __global const float4* triVertices, __global const float4* triNormals,
    __global const int* triMaterials, __global const Material* materials, __constant const Camera* camera,
    uint seed, int maxPathLength, float lightTracePaths, int connectToCamera, int storeVertices,
    float vmWeightFactor, float vcWeightFactor, __global float4* rayOrigins, __global float4* rayDirections,
    __global const float* hitT, __global const int* hitTriangle, __global const float2* hitBary,
    __global const int* pathPixel, __global int* pathDepth, __global float4* pathThroughput,
    __global float4* pathMis, __global const int* pathFlags, __global float4* shadowOrigins,
    __global float4* shadowDirections, __global float4* shadowContribution, __global int* shadowPixel,
    __global int* queueCounters)
{
    LightHitResult r;
    r.alive = r.shadowRay = r.storeVertex = 0;
    float3 beta = pathThroughput[slot].xyz;
    if (!(max_component(beta) > 0.0f))
        return r; /* a failed emission sample */
    int tri = hitTriangle[slot];
    float2 bary = hitBary[slot];
    float3 wLight = -rayDirections[slot].xyz; /* back along the light path */
    SurfaceHit hit = surface_hit(triVertices, triNormals, tri, bary, wLight);
    float3 wLightL = to_local(&hit.frame, wLight);
    int depth = pathDepth[slot] + 1;
    int lightPath = pathPixel[slot];
    PathMis mis = load_mis(pathMis, slot);
    mis_at_hit(&mis, hitT[slot], fabs(wLightL.z), depth > 1 || (pathFlags[slot] & PATH_FINITE_LIGHT));
    Bsdf bsdf = make_bsdf(&materials[triMaterials[tri]], wLightL, hit.frontSide);
    if (bsdf_is_black(&bsdf))
        return r;
    float cont = continuation_probability(&bsdf);

    if (bsdf_has_nondelta(&bsdf)) {
        if (storeVertices) {
            r.storeVertex = 1;
            LightVertex* v = &r.vertex;
            vstore3(hit.p, 0, v->position);
            vstore3(beta, 0, v->throughput);
            vstore3(wLight, 0, v->toLight);
            v->dVCM = mis.dVCM;
            v->dVC = mis.dVC;
            v->dVM = mis.dVM;
            v->pathLength = depth;
            v->triangle = tri;
            v->b1 = bary.x;
            v->b2 = bary.y;
            v->continuation = cont;
        }
        if (connectToCamera && depth + 1 <= maxPathLength) {
            float3 cameraPosition = vload3(0, camera->position);
            float3 toCamera = cameraPosition - hit.p;
            float dist2 = dot(toCamera, toCamera);
            toCamera *= rsqrt(dist2);
            float3 toCameraL = to_local(&hit.frame, toCamera);
            int pixel = camera_pixel(camera, hit.p);
            if (pixel >= 0 && sides_agree(&hit, toCamera, toCameraL)) {
                float pdfFwd, pdfRev;
                float3 f = bsdf_eval(&bsdf, wLightL, toCameraL, true, &pdfFwd, &pdfRev) *
                           adjoint_shading_correction(&hit, wLight, toCamera);
                /* Density of the camera sampling this point, per unit area. */
                float cameraPdfA = camera_pdf_w(camera, -toCamera) * fabs(toCameraL.z) / dist2;
                float w = 1.0f; /* lt: the only technique for these paths */
#ifndef LIGHT_TRACING
                w = mis_weight_light_to_camera(mis, cameraPdfA, lightTracePaths, pdfRev * cont, vmWeightFactor);
#endif
                float3 contribution = w * beta * f * (cameraPdfA / lightTracePaths);
                if (max_component(contribution) > 0.0f) {
                    store_ray(shadowOrigins, shadowDirections, slot,
                              ray_between(hit.p, hit.pError, hit.ngF, cameraPosition, (float3)(0.0f), -toCamera));
                    shadowContribution[slot] = (float4)(contribution, 0.0f);
                    shadowPixel[slot] = pixel;
                    r.shadowRay = 1;
                }
            }
        }
    }

    if (depth + 2 > maxPathLength)
        return r;
    float4 u = rng_uniform4(seed, iteration, (uint)lightPath, (uint)depth, 3u);
    BsdfSample bs;
    if (!bsdf_sample(&bsdf, wLightL, u.xyz, true, &bs))
        return r;
    float3 wOut = to_world(&hit.frame, bs.wi);
    if (!sides_agree(&hit, wOut, bs.wi) || u.w >= cont)
        return r;
    float pdfW = bs.pdf * cont, revPdfW = pdfW;
    if (!bs.delta) {
        float fwd, rev;
        bsdf_eval(&bsdf, wLightL, bs.wi, true, &fwd, &rev);
        revPdfW = rev * cont;
    }
    mis_after_scatter(&mis, bs.delta, fabs(bs.wi.z), pdfW, revPdfW, vmWeightFactor, vcWeightFactor);
    beta *= bs.weight * (adjoint_shading_correction(&hit, wLight, wOut) / cont);
    if (!all(isfinite(beta))) {
        atomic_inc(&queueCounters[COUNTER_INDEX(COUNTER_NONFINITE)]);
        return r;
    }
    store_ray(rayOrigins, rayDirections, slot, spawn_ray(hit.p, hit.pError, hit.ngF, wOut));
    pathThroughput[slot] = (float4)(beta, 0.0f);
    store_mis(pathMis, slot, mis);
    pathDepth[slot] = depth;
    r.alive = max_component(beta) > 0.0f ? 1 : 0;
    return r;
}

__kernel void shade_light(int capacity, int nextRayQueue, int freeQueue, uint iteration,
                          __global int* queueItems, __global int* queueCounters,
                          __global const float4* triVertices, __global const float4* triNormals,
                          __global const int* triMaterials, __global const Material* materials,
                          __constant const Camera* camera, uint seed, int maxPathLength, float lightTracePaths,
                          int connectToCamera, int storeVertices, float vmWeightFactor, float vcWeightFactor,
                          __global float4* rayOrigins, __global float4* rayDirections, __global const float* hitT,
                          __global const int* hitTriangle, __global const float2* hitBary,
                          __global const int* pathPixel, __global int* pathDepth,
                          __global float4* pathThroughput, __global float4* pathMis,
                          __global const int* pathFlags, __global int* pathLastVertex,
                          __global float4* shadowOrigins, __global float4* shadowDirections,
                          __global float4* shadowContribution, __global int* shadowPixel,
                          __global LightVertex* lightVertices, int vertexCapacity, int firstLightPath,
                          __global int* lightPathHead)
{
    __local int scratch[2];
    int slot = queue_item(queueItems, queueCounters, capacity, QUEUE_HITS, get_global_id(0));
    LightHitResult r;
    r.alive = r.shadowRay = r.storeVertex = 0;
    if (slot >= 0)
        r = shade_light_hit(slot, iteration, triVertices, triNormals, triMaterials, materials, camera, seed,
                            maxPathLength, lightTracePaths, connectToCamera, storeVertices, vmWeightFactor,
                            vcWeightFactor, rayOrigins, rayDirections, hitT, hitTriangle, hitBary, pathPixel,
                            pathDepth, pathThroughput, pathMis, pathFlags, shadowOrigins, shadowDirections,
                            shadowContribution, shadowPixel, queueCounters);
    /* The counter keeps counting past the buffer's end, so the host sees how
     * many vertices were wanted and can retry with room for them. */
    int index = group_allocate(queueCounters, COUNTER_LIGHT_VERTICES, r.storeVertex, scratch);
    if (r.storeVertex && index < vertexCapacity) {
        r.vertex.prev = pathLastVertex[slot];
        lightVertices[index] = r.vertex;
        pathLastVertex[slot] = index;
        lightPathHead[pathPixel[slot] - firstLightPath] = index;
    }
    queue_push(queueItems, queueCounters, capacity, QUEUE_SHADOW, r.shadowRay, slot, scratch);
    queue_push(queueItems, queueCounters, capacity, nextRayQueue, r.alive, slot, scratch);
    queue_push(queueItems, queueCounters, capacity, freeQueue, slot >= 0 && !r.alive, slot, scratch);
}
