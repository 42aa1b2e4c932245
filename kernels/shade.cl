/* shade (`-a pt`): at every hit of a camera path, in order,
 *   1. emission seen here (front faces only), MIS-weighted against having
 *      sampled this light from the previous vertex;
 *   2. next-event estimation: sample a light, queue a shadow ray with its
 *      MIS-weighted contribution for `connect`;
 *   3. sample the BSDF to continue (Russian roulette after 3 segments), or end
 *      the path and free the slot.
 * MIS uses the power heuristic (Veach 1997, §9.2.4) between BSDF sampling and
 * light sampling; delta lights and delta lobes take weight 1.
 * Path length as in path_state.h: a vertex of depth d continues (and
 * samples a light) only if a path of d + 1 segments fits. */
#include "bsdf.h"
#include "lights.h"
#include "path_state.h"
#include "queues.h"
#include "rng.h"
#include "surface.h"

static inline float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

/* Shades the hit of path `slot`; sets *alive if the path continues (its next
 * ray stored) and *shadowRay if a shadow ray was stored for `connect`. */
static inline void shade_hit(const RenderBuffers* b, const LaunchParams* params, int slot, bool* aliveOut,
                             bool* shadowOut)
{
    int tri = b->hitTriangle[slot];
    float3 wo = -b->rayDirections[slot].xyz;
    SurfaceHit hit = surface_hit(b->triVertices, b->triNormals, tri, b->hitBary[slot], wo);
    int depth = hit_depth(b->pathDepth, slot);
    int pixel = b->pathPixel[slot];
    float3 beta = b->pathThroughput[slot].xyz;
    float3 L = (float3)(0.0f);

#ifdef HAS_EMISSIVE_TRIANGLES
    int light = b->triangleLight[tri];
    float cosLight = dot(wo, hit.ngF);
    if (light >= 0 && hit.frontSide) {
        float prevPdf = b->pathPrevPdf[slot];
        float w = 1.0f;
        if (prevPdf > 0.0f)
            w = power_heuristic(prevPdf,
                                triangle_light_pdf(b->lights[light].pmf, b->lights[light].area, b->hitT[slot], cosLight));
        L += w * beta * vload3(0, b->lights[light].emission);
    }
#endif

    float3 woL = to_local(&hit.frame, wo);
    Bsdf bsdf = make_bsdf(&b->materials[b->triMaterials[tri]], woL, hit.frontSide);
    bool alive = path_fits(depth + 1, params->maxPathLength) && !bsdf_is_black(&bsdf);

    if (alive && bsdf_has_nondelta(&bsdf)) {
        float4 u = rng_uniform4(params->seed, params->iteration, (uint)pixel, (uint)depth, 0u);
        LightSample ls;
        if (sample_light(b->lights, b->lightCdf, b->triVertices, b->scene, hit.p, u.xyz, &ls)) {
            float3 wiL = to_local(&hit.frame, ls.direction);
            if (sides_agree(&hit, ls.direction, wiL) && light_sample_resolved(hit.p, hit.pError, hit.ngF, &ls)) {
                float pdfBsdf, pdfRev;
                float3 f = bsdf_eval(&bsdf, woL, wiL, false, &pdfBsdf, &pdfRev);
                if (max_component(f) > 0.0f) {
                    float w = ls.delta ? 1.0f : power_heuristic(ls.pdf, pdfBsdf);
                    float3 contribution = beta * f * fabs(wiL.z) * ls.radiance * (w / ls.pdf);
                    store_ray(b->shadowOrigins, b->shadowDirections, slot,
                              shadow_ray_to_light(hit.p, hit.pError, hit.ngF, &ls));
                    b->shadowContribution[slot] = (float4)(contribution, 0.0f);
                    *shadowOut = true;
                }
            }
        }
    }

    if (alive) {
        float4 u = rng_uniform4(params->seed, params->iteration, (uint)pixel, (uint)depth, 1u);
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
            store_ray(b->rayOrigins, b->rayDirections, slot, spawn_ray(hit.p, hit.pError, hit.ngF, wi));
            b->pathThroughput[slot] = (float4)(beta, 0.0f);
            b->pathPrevPdf[slot] = bs.delta ? 0.0f : bs.pdf;
            b->pathDepth[slot] = depth;
        }
    }

    if (any(L != 0.0f))
        b->pixelRadiance[pixel] += (float4)(L, 0.0f);
    *aliveOut = alive;
}

__kernel void shade(RENDER_KERNEL_PARAMS)
{
    __local int scratch[2];
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_HITS, get_global_id(0));
    bool alive = false, shadowRay = false;
    if (slot >= 0)
        shade_hit(&b, &params, slot, &alive, &shadowRay);
    queue_push(queueItems, queueCounters, params.capacity, QUEUE_SHADOW, shadowRay, slot, scratch);
    queue_push(queueItems, queueCounters, params.capacity, params.nextRayQueue, alive, slot, scratch);
    queue_push(queueItems, queueCounters, params.capacity, params.nextFreeQueue, slot >= 0 && !alive, slot, scratch);
}
