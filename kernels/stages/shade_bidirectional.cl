/* shade_bidirectional: camera sub-paths of lt, bpt, ppm, bpm and vcm
 * (SmallVCM's camera pass, vertexcm.hxx). At every hit, in order,
 *   1. convert the MIS quantities of the last segment to area measure;
 *   2. emission seen here (front faces, and back faces of two-sided emitters), weighted against every other
 *      technique that samples this path (eqs. 42-43); with merging but no
 *      connections (ppm, bpm) only purely specular paths take it, with
 *      weight 1, as merging covers the rest;
 *   lt ends here: its camera paths only see what is directly visible;
 *   3. next-event estimation with its weight (eqs. 44-45), queued for
 *      `connect` (not in ppm and bpm); vertex connections and merges were
 *      added by `connect_vertices` and `merge` before this;
 *   4. sample the BSDF to continue, with Russian roulette by the material's
 *      continuation probability (part of every pdf in the weights); ppm ends
 *      the path at its first non-delta vertex, where it merged. */
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
#include "transport/mis.h"
#include "transport/path_state.h"

/* int, not bool, flags: rusticl (Mesa 22.3) loses bool members of a struct
 * returned from a function. */
typedef struct CameraHitResult {
    int alive, shadowRay;
} CameraHitResult;

INLINE CameraHitResult shade_camera_hit(const RenderBuffers* b, const LaunchParams* params, int slot, int* rejected)
{
    CameraHitResult r = {0, 0};
    int depth = hit_depth(b->pathDepth, slot);
    int sample = b->pathPixel[slot], pixel = sample_pixel(params, sample);
    uint index = sample_index(params, sample);
    /* The random numbers first, as in shade.cl; under ppm, which continues a
     * camera path only through delta lobes, the scatter block only for those
     * hits (shade_bidirectional 1.4 -> 2.0 M items/s on the caustics scene). */
#ifdef VERTEX_CONNECTION
    Uniform4 uLight = rng_uniform4(params->seed, index, (uint)pixel, (uint)depth, 0u);
#endif
#if !defined(LIGHT_TRACING) && !defined(PPM)
    Uniform4 uScatter = rng_uniform4(params->seed, index, (uint)pixel, (uint)depth, 1u);
#endif
    int tri = b->hitTriangle[slot];
    vec3 wo = v3_neg(load_vec3(b->rayDirections, slot));
    vec2 bary = load_vec2(b->hitBary, slot);
    SurfaceHit hit = scene_surface_hit(b, tri, bary, wo);
    vec3 woL = to_local(&hit.frame, wo);
    vec3 beta = load_vec3(b->pathThroughput, slot);
    PathMis mis = load_mis(b->pathMis, slot);
    mis_at_hit(&mis, b->hitT[slot], mis_cos(hit.ngF, wo), true);
    vec3 L = v3s(0.0f);

#ifdef HAS_EMISSIVE_TRIANGLES
    int light = b->triangleLight[tri];
    bool specularPath = (b->pathFlags[slot] & PATH_SPECULAR) != 0;
    if (light >= 0 && (hit.frontSide || b->lights[light].sides == 2)) {
        float w = 1.0f; /* seen directly: no other technique */
#ifdef VERTEX_MERGING_ONLY
        w = specularPath ? 1.0f : 0.0f;
#else
        if (depth > 1) {
            float directPdfA, emissionPdfW;
            triangle_hit_pdfs(&b->lights[light], v3_dot(wo, hit.ngF), &directPdfA, &emissionPdfW);
            w = mis_weight_emission_hit(mis, directPdfA, emissionPdfW);
        }
#endif
        L = v3_add(L, v3_scale(v3_mul(beta, triangle_emission(b, &b->lights[light], bary)), w));
    }
#endif

#ifndef LIGHT_TRACING
    Bsdf bsdf = surface_bsdf(b, &hit, tri, bary, woL);
    bool alive = path_fits(depth + 1, params->maxPathLength) && !bsdf_is_black(&bsdf);
    float cont = continuation_probability(&bsdf);
#ifdef PPM
    alive = alive && !bsdf_has_nondelta(&bsdf);
#endif

#ifdef VERTEX_CONNECTION
    if (alive && b->scene->lightCount > 0 && bsdf_has_nondelta(&bsdf)) {
        LightSample ls;
        if (sample_scene_light(b, hit.p, uLight, &ls)) {
            vec3 wiL = to_local(&hit.frame, ls.direction);
            if (sides_agree(&hit, ls.direction, wiL) && light_sample_resolved(hit.p, hit.pError, hit.ngF, &ls)) {
                float pdfFwd, pdfRev;
                vec3 f = bsdf_eval(&bsdf, woL, wiL, false, &pdfFwd, &pdfRev);
                float cosToLight = fabs(wiL.z);
                float bsdfDirPdfW = ls.delta ? 0.0f : pdfFwd * cont;
                float bsdfRevPdfW = pdfRev * cont;
                float w = mis_weight_nee(mis, bsdfDirPdfW, bsdfRevPdfW, ls.directPdfW, ls.emissionPdfW,
                                         mis_cos(hit.ngF, ls.direction), ls.cosAtLight, params->vmWeightFactor);
                vec3 contribution = v3_mul(v3_mul(beta, f), v3_scale(ls.radiance, w * cosToLight / ls.pdf));
#ifdef HAS_VOLUME_ABSORPTION
                contribution = v3_mul(contribution, segment_absorption(&b->materials[b->triMaterials[tri]], &hit,
                                                                       ls.direction, ls.distance));
#endif
                if (max_component(f) > 0.0f && accept_finite(contribution, rejected)) {
                    store_ray(b->shadowOrigins, b->shadowDirections, slot,
                              shadow_ray_to_light(hit.p, hit.pError, hit.ngF, &ls));
                    store_vec3w(b->shadowContribution, slot, contribution, 0.0f);
                    r.shadowRay = 1;
                }
            }
        }
    }
#endif

    if (alive) {
#ifdef PPM
        Uniform4 uScatter = rng_uniform4(params->seed, index, (uint)pixel, (uint)depth, 1u);
#endif
        Scatter s;
        int next = continue_bidirectional(&bsdf, &hit, wo, woL, uScatter, false, cont, params, &mis, &beta, &s)
                       ? store_continuation(b, params, slot, &hit, s.wi, beta, 0.0f, depth, rejected)
                       : -1;
        alive = next >= 0;
        if (alive) {
            store_mis(b->pathMis, next, mis);
            b->pathFlags[next] = s.delta ? b->pathFlags[slot] : 0; /* PATH_SPECULAR until a non-delta scatter */
        }
    }
    r.alive = alive ? 1 : 0;
#endif
    add_radiance(b->pixelRadiance, sample, L, rejected);
    return r;
}

__kernel void shade_bidirectional(RENDER_KERNEL_PARAMS)
{
    __local int scratch[QUEUE_SCRATCH_INTS];
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int slot = shade_slot(&b, params.capacity, get_global_id(0), SIMD_CAMERA_SHADING);
    CameraHitResult r = {0, 0};
    int rejected = 0;
    if (slot >= 0)
        r = shade_camera_hit(&b, &params, slot, &rejected);
    queue_push4(queueItems, queueCounters, params.capacity,
                lanes(QUEUE_SHADOW, params.nextRayQueue, NO_COUNTER, NO_COUNTER),
                lanes(r.shadowRay, r.alive, 0, 0), lanes(slot, next_round_slot(&params), 0, 0), scratch,
                SIMD_CAMERA_SHADING);
    report_nonfinite(queueCounters, rejected);
}
