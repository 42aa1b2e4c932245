/* shade (`-a pt`): at every hit of a camera path, in order,
 *   1. emission seen here (front faces, back faces too of two-sided emitters), MIS-weighted against having
 *      sampled this light from the previous vertex;
 *   2. next-event estimation: sample a light, queue a shadow ray with its
 *      MIS-weighted contribution for `connect`;
 *   3. sample the BSDF to continue (Russian roulette after 3 segments, on the
 *      throughput with refraction's 1/η² divided out) in the next round's
 *      slot (path_state.h), or end the path.
 * MIS uses the power heuristic (Veach 1997, §9.2.4) between BSDF sampling and
 * light sampling; delta lights and delta lobes take weight 1.
 * Path length as in path_state.h: a vertex of depth d continues (and
 * samples a light) only if a path of d + 1 segments fits. */
#include "core/nan_policy.h"
#include "core/queues.h"
#include "core/rng.h"
#include "core/simd.h"
#include "geometry/surface.h"
#include "interface/inline.h"
#include "lights/lights.h"
#include "materials/bsdf.h"
#include "materials/emission.h"
#include "materials/surface_bsdf.h"
#include "materials/volume.h"
#include "transport/continue_path.h"
#include "transport/path_state.h"

INLINE float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

/* Shades the hit of path `slot`; sets *alive if the path continues (its next
 * ray stored) and *shadowRay if a shadow ray was stored for `connect`;
 * counts what the NaN policy rejects in *rejected. */
INLINE void shade_hit(const RenderBuffers* b, const LaunchParams* params, int slot, bool* aliveOut,
                      bool* shadowOut, int* rejected)
{
    int depth = hit_depth(b->pathDepth, slot);
    int sample = b->pathPixel[slot], pixel = sample_pixel(params, sample);
    uint index = sample_index(params, sample);
    /* The random numbers first: their hashes are long chains of dependent
     * multiplies, which the core then runs while the loads of the hit's
     * triangle and material wait on the caches (drawn where they are used,
     * shade took 4-10 % longer on PoCL). */
    Uniform4 uLight = rng_uniform4(params->seed, index, (uint)pixel, (uint)depth, 0u);
    Uniform4 uScatter = rng_uniform4(params->seed, index, (uint)pixel, (uint)depth, 1u);
    int tri = b->hitTriangle[slot];
    vec3 wo = v3_neg(load_vec3(b->rayDirections, slot));
    vec2 bary = load_vec2(b->hitBary, slot);
    SurfaceHit hit = scene_surface_hit(b, tri, bary, wo);
    vec3 beta = load_vec3(b->pathThroughput, slot);
    float etaScale = load_w(b->pathThroughput, slot); /* η² of the refractions so far (generate starts it at 1) */
    vec3 L = v3s(0.0f);

#ifdef HAS_EMISSIVE_TRIANGLES
    int light = b->triangleLight[tri];
    float cosLight = v3_dot(wo, hit.ngF);
    if (light >= 0 && (hit.frontSide || b->lights[light].sides == 2)) {
        __global const Light* l = &b->lights[light];
        float prevPdf = b->pathPrevPdf[slot];
        float w = 1.0f;
        if (prevPdf > 0.0f)
            w = power_heuristic(prevPdf, triangle_light_pdf(l->pmf, l->area, b->hitT[slot], cosLight));
        L = v3_add(L, v3_scale(v3_mul(beta, triangle_emission(b, l, bary)), w));
    }
#endif

    vec3 woL = to_local(&hit.frame, wo);
    Bsdf bsdf = surface_bsdf(b, &hit, tri, bary, woL);
    bool alive = path_fits(depth + 1, params->maxPathLength) && !bsdf_is_black(&bsdf);

    if (alive && bsdf_has_nondelta(&bsdf)) {
        LightSample ls;
        if (sample_scene_light(b, hit.p, uLight, &ls)) {
            vec3 wiL = to_local(&hit.frame, ls.direction);
            if (sides_agree(&hit, ls.direction, wiL) && light_sample_resolved(hit.p, hit.pError, hit.ngF, &ls)) {
                float pdfBsdf, pdfRev;
                vec3 f = bsdf_eval(&bsdf, woL, wiL, false, &pdfBsdf, &pdfRev);
                float w = ls.delta ? 1.0f : power_heuristic(ls.pdf, pdfBsdf);
                vec3 contribution = v3_mul(v3_mul(beta, f), v3_scale(ls.radiance, fabs(wiL.z) * (w / ls.pdf)));
#ifdef HAS_VOLUME_ABSORPTION
                contribution = v3_mul(contribution, segment_absorption(&b->materials[b->triMaterials[tri]], &hit,
                                                                       ls.direction, ls.distance));
#endif
                if (max_component(f) > 0.0f && accept_finite(contribution, rejected)) {
                    store_ray(b->shadowOrigins, b->shadowDirections, slot,
                              shadow_ray_to_light(hit.p, hit.pError, hit.ngF, &ls));
                    store_vec3w(b->shadowContribution, slot, contribution, 0.0f);
                    *shadowOut = true;
                }
            }
        }
    }

    if (alive) {
        Scatter s;
        alive = scatter(&bsdf, &hit, wo, woL, uScatter, false, &s);
        if (alive) {
            beta = v3_mul(beta, s.weight);
            if (s.refracted)
                etaScale *= bsdf.eta * bsdf.eta;
            if (depth >= 3) {
                /* Russian roulette: survive with probability q, reweight by 1/q.
                 * q sees the throughput without refraction's 1/η² (pbrt-v4's
                 * etaScale): inside glass that scale says nothing about what
                 * the path is worth, and would end it η² times too often. */
                float q = fmin(1.0f, max_component(beta) * etaScale);
                alive = uScatter.w < q;
                beta = v3_div(beta, q);
            }
            int next = alive ? store_continuation(b, params, slot, &hit, s.wi, beta, etaScale, depth, rejected) : -1;
            alive = next >= 0;
            if (alive)
                b->pathPrevPdf[next] = s.delta ? 0.0f : s.pdfW;
        }
    }

    add_radiance(b->pixelRadiance, sample, L, rejected);
    *aliveOut = alive;
}

__kernel void shade(RENDER_KERNEL_PARAMS)
{
    __local int scratch[QUEUE_SCRATCH_INTS];
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int slot = shade_slot(&b, params.capacity, get_global_id(0), SIMD_CAMERA_SHADING);
    bool alive = false, shadowRay = false;
    int rejected = 0;
    if (slot >= 0)
        shade_hit(&b, &params, slot, &alive, &shadowRay, &rejected);
    queue_push4(queueItems, queueCounters, params.capacity,
                lanes(QUEUE_SHADOW, params.nextRayQueue, NO_COUNTER, NO_COUNTER),
                lanes(shadowRay, alive, 0, 0), lanes(slot, next_round_slot(&params), 0, 0), scratch,
                SIMD_CAMERA_SHADING);
    report_nonfinite(queueCounters, rejected);
}
