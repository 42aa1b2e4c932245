/* shade (`-a pt`): at every hit of a camera path, in order,
 *   1. emission seen here (front faces only), MIS-weighted against having
 *      sampled this light from the previous vertex;
 *   2. next-event estimation: sample a light, queue a shadow ray with its
 *      MIS-weighted contribution for `connect`;
 *   3. sample the BSDF to continue (Russian roulette after 3 segments, on the
 *      throughput with refraction's 1/η² divided out), or end the path and
 *      free the slot.
 * MIS uses the power heuristic (Veach 1997, §9.2.4) between BSDF sampling and
 * light sampling; delta lights and delta lobes take weight 1.
 * Path length as in path_state.h: a vertex of depth d continues (and
 * samples a light) only if a path of d + 1 segments fits. */
#include "core/queues.h"
#include "core/rng.h"
#include "geometry/surface.h"
#include "interface/inline.h"
#include "lights/lights.h"
#include "materials/bsdf.h"
#include "transport/continue_path.h"
#include "transport/path_state.h"

INLINE float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

/* Shades the hit of path `slot`; sets *alive if the path continues (its next
 * ray stored) and *shadowRay if a shadow ray was stored for `connect`. */
INLINE void shade_hit(const RenderBuffers* b, const LaunchParams* params, int slot, bool* aliveOut,
                             bool* shadowOut)
{
    int tri = b->hitTriangle[slot];
    float3 wo = -b->rayDirections[slot].xyz;
    SurfaceHit hit = surface_hit(b->triVertices, b->triNormals, tri, b->hitBary[slot], wo);
    int depth = hit_depth(b->pathDepth, slot);
    int pixel = b->pathPixel[slot];
    float4 throughput = b->pathThroughput[slot];
    float3 beta = throughput.xyz;
    float etaScale = throughput.w; /* η² of the refractions so far (generate starts it at 1) */
    float3 L = (float3)(0.0f);

#ifdef HAS_EMISSIVE_TRIANGLES
    int light = b->triangleLight[tri];
    float cosLight = dot(wo, hit.ngF);
    if (light >= 0 && hit.frontSide) {
        __global const Light* l = &b->lights[light];
        float prevPdf = b->pathPrevPdf[slot];
        float w = 1.0f;
        if (prevPdf > 0.0f)
            w = power_heuristic(prevPdf, triangle_light_pdf(l->pmf, l->area, b->hitT[slot], cosLight));
        L += w * beta * vload3(0, l->emission);
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
                float w = ls.delta ? 1.0f : power_heuristic(ls.pdf, pdfBsdf);
                float3 contribution = beta * f * fabs(wiL.z) * ls.radiance * (w / ls.pdf);
                if (max_component(f) > 0.0f && accept_finite(contribution, b->queueCounters)) {
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
        Scatter s;
        alive = scatter(&bsdf, &hit, wo, woL, u.xyz, false, false, &s);
        if (alive) {
            beta *= s.weight;
            if (s.refracted)
                etaScale *= bsdf.eta * bsdf.eta;
            if (depth >= 3) {
                /* Russian roulette: survive with probability q, reweight by 1/q.
                 * q sees the throughput without refraction's 1/η² (pbrt-v4's
                 * etaScale): inside glass that scale says nothing about what
                 * the path is worth, and would end it η² times too often. */
                float q = fmin(1.0f, max_component(beta) * etaScale);
                alive = u.w < q;
                beta /= q;
            }
            alive = alive && store_continuation(b, slot, &hit, s.wi, beta, etaScale, depth);
            if (alive)
                b->pathPrevPdf[slot] = s.delta ? 0.0f : s.pdfW;
        }
    }

    add_radiance(b->pixelRadiance, pixel, L, b->queueCounters);
    *aliveOut = alive;
}

__kernel void shade(RENDER_KERNEL_PARAMS)
{
    __local int scratch[8];
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    prefetch_hit_state(&b, params.capacity, QUEUE_HITS, get_global_id(0));
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_HITS, get_global_id(0));
    bool alive = false, shadowRay = false;
    if (slot >= 0)
        shade_hit(&b, &params, slot, &alive, &shadowRay);
    queue_push4(queueItems, queueCounters, params.capacity,
                (int4)(QUEUE_SHADOW, params.nextRayQueue, params.nextFreeQueue, NO_COUNTER),
                (int4)(shadowRay, alive, slot >= 0 && !alive, 0), slot, scratch);
}
