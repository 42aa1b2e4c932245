/* shade_light (every algorithm with light paths: lt, bpt, ppm, bpm, vcm): at
 * order (SmallVCM's light pass, vertexcm.hxx),
 *   1. convert the MIS quantities of the last segment to area measure;
 *   2. at a vertex with a non-delta BSDF: store it in the light-vertex buffer
 *      for vertex connection and merging (as StoredLightVertex: a whole
 *      LightVertex for connection, merging's record for ppm and bpm; not
 *      lt), and connect it to the camera (t = 1; not ppm and bpm):
 *      queue a shadow ray whose contribution `connect_splat` adds to the
 *      pixel the vertex projects to;
 *   3. sample the adjoint BSDF to continue, with Russian roulette by the
 *      material's continuation probability, or end the path.
 * Light paths carry importance: BSDFs are evaluated in their adjoint form,
 * with Veach's shading-normal correction. Path length as in path_state.h:
 * a vertex of depth d connects to the camera if d + 1 segments fit, and is
 * only worth continuing from if a path through the next vertex (d + 2
 * segments, the camera connection included) fits. */
#include "core/nan_policy.h"
#include "core/queues.h"
#include "core/rng.h"
#include "core/simd.h"
#include "geometry/surface.h"
#include "interface/inline.h"
#include "lights/camera.h"
#include "lights/lights.h"
#include "materials/bsdf.h"
#include "materials/surface_bsdf.h"
#include "materials/volume.h"
#include "transport/continue_path.h"
#include "transport/mis.h"
#include "transport/path_state.h"

/* int, not bool, flags: rusticl (Mesa 22.3) loses bool members of a struct
 * returned from a function. */
typedef struct LightHitResult {
    int alive, shadowRay, storeVertex;
    StoredLightVertex vertex; /* to store after the group's reservation */
} LightHitResult;

/* Stores vertex v of the light path whose list `slot` holds (its last vertex
 * and their number) at place `at` of the light vertex buffer; for vertex
 * connection, linked after the path's last one.
 * The counter keeps counting past the buffer's end, so the host sees how
 * many vertices were wanted and can retry with room for them; past it
 * nothing is stored. */
INLINE void append_light_vertex(const RenderBuffers* b, const LaunchParams* params, int slot, int at,
                                StoredLightVertex* v)
{
    if (at >= params->vertexCapacity)
        return;
#ifdef VERTEX_CONNECTION
    v->prev = b->pathLastVertex[slot];
    int flags = b->pathFlags[slot] + PATH_STORED_ONE;
    b->pathFlags[slot] = flags;
    v->number = flags / PATH_STORED_ONE;
    b->pathLastVertex[slot] = at;
    b->lightPathHead[b->pathPixel[slot] - params->firstLightPath] = at;
#endif
    ((__global StoredLightVertex*)b->lightVertices)[at] = *v;
}

INLINE LightHitResult shade_light_hit(const RenderBuffers* b, const LaunchParams* params, int slot, int* rejected)
{
    LightHitResult r;
    r.alive = r.shadowRay = r.storeVertex = 0;
    vec3 beta = load_vec3(b->pathThroughput, slot);
    if (!(max_component(beta) > 0.0f))
        return r; /* a failed emission sample */
    int depth = hit_depth(b->pathDepth, slot);
    int lightPath = b->pathPixel[slot];
    /* The random numbers first, as in shade.cl. */
    Uniform4 u = rng_light_uniform4(params->seed, sample_index(params, lightPath),
                                    (uint)sample_pixel(params, lightPath), (uint)depth, 3u);
    int tri = b->hitTriangle[slot];
    vec2 bary = load_vec2(b->hitBary, slot);
    vec3 wLight = v3_neg(load_vec3(b->rayDirections, slot)); /* back along the light path */
    SurfaceHit hit = scene_surface_hit(b, tri, bary, wLight);
    vec3 wLightL = to_local(&hit.frame, wLight);
    PathMis mis = load_mis(b->pathMis, slot);
    mis_at_hit(&mis, b->hitT[slot], mis_cos(hit.ngF, wLight), depth > 1 || (b->pathFlags[slot] & PATH_FINITE_LIGHT));
    Bsdf bsdf = surface_bsdf(b, &hit, tri, bary, wLightL);
    if (bsdf_is_black(&bsdf))
        return r;
    float cont = continuation_probability(&bsdf);

    if (bsdf_has_nondelta(&bsdf)) {
        /* Techniques the program lacks are compiled out, not skipped at run
         * time: where PoCL runs this kernel in SIMD it executes both sides
         * of every branch for all lanes (ppm and bpm: 1.22-1.29× as fast
         * without the camera connection's code). */
#ifndef LIGHT_TRACING /* lt keeps no vertices */
        {
            StoredLightVertex v;
#ifdef VERTEX_CONNECTION
            v.surface = surface_record(&hit);
            v.dVC = mis.dVC;
            v.triangle = tri;
            v.b1 = bary.x;
            v.b2 = bary.y;
#else
            store3(v.position, hit.p);
            v.pad[0] = v.pad[1] = v.pad[2] = 0.0f;
#endif
            store3(v.throughput, beta);
            store3(v.toLight, wLight);
            v.dVCM = mis.dVCM;
            v.dVM = mis.dVM;
            v.pathLength = depth;
            v.continuation = cont;
            if (pushes_per_item(SIMD_LIGHT_SHADING)) {
                /* Its place now, as group_allocate4 would give it (an atomic
                 * per item): stored here, it is not kept live through the rest. */
                append_light_vertex(b, params, slot,
                                    atomic_inc(&b->queueCounters[COUNTER_INDEX(COUNTER_LIGHT_VERTICES)]), &v);
            } else {
                r.storeVertex = 1;
                r.vertex = v;
            }
        }
#endif
#ifndef VERTEX_MERGING_ONLY /* ppm and bpm make no connections, to the camera neither */
        if (lightPath >= params->firstSplatPath && path_fits(depth + 1, params->maxPathLength)) {
            vec3 cameraPosition = load3c(b->camera->position);
            vec3 toCamera = v3_sub(cameraPosition, hit.p);
            float dist2 = v3_dot(toCamera, toCamera);
            toCamera = v3_scale(toCamera, rsqrt(dist2));
            vec3 toCameraL = to_local(&hit.frame, toCamera);
            int pixel = camera_pixel(b->camera, hit.p);
            if (pixel >= 0 && sides_agree(&hit, toCamera, toCameraL)) {
                float pdfFwd, pdfRev;
                vec3 f = v3_scale(bsdf_eval(&bsdf, wLightL, toCameraL, true, &pdfFwd, &pdfRev),
                                  adjoint_shading_correction(&hit, wLight, toCamera));
                /* The camera's importance arriving here, per unit area (with
                 * the shading cosine of the adjoint BSDF's |ns·ω|), and, for
                 * the weight, its density of sampling this point (mis_cos). */
                float cameraPdfW = camera_pdf_w(b->camera, v3_neg(toCamera));
                float importance = cameraPdfW * fabs(toCameraL.z) / dist2;
                float w = 1.0f; /* lt: the only technique for these paths */
#ifndef LIGHT_TRACING
                w = mis_weight_light_to_camera(mis, cameraPdfW * mis_cos(hit.ngF, toCamera) / dist2,
                                               params->lightTracePaths, pdfRev * cont, params->vmWeightFactor);
#endif
                vec3 contribution = v3_scale(v3_mul(beta, f), w * (importance / params->lightTracePaths));
#ifdef HAS_VOLUME_ABSORPTION
                contribution = v3_mul(contribution, segment_absorption(&b->materials[b->triMaterials[tri]], &hit,
                                                                       toCamera, sqrt(dist2)));
#endif
                if (accept_finite(contribution, rejected) && max_component(contribution) > 0.0f) {
                    store_ray(b->shadowOrigins, b->shadowDirections, slot,
                              ray_between(hit.p, hit.pError, hit.ngF, cameraPosition, v3s(0.0f), v3_neg(toCamera)));
                    store_vec3w(b->shadowContribution, slot, contribution, 0.0f);
                    b->shadowPixel[slot] = pixel;
                    r.shadowRay = 1;
                }
            }
        }
#endif
    }

    if (!path_fits(depth + 2, params->maxPathLength))
        return r; /* the next vertex could not even connect to the camera */
    Scatter s;
    if (!continue_bidirectional(&bsdf, &hit, wLight, wLightL, u, true, cont, params, &mis, &beta, &s))
        return r;
    int next = store_continuation(b, params, slot, &hit, s.wi, beta, 0.0f, depth, rejected);
    if (next < 0)
        return r;
    /* What the light path keeps: its flags (among them its count of stored
     * vertices, by which queued connections reserve their entries) and, for
     * connections, the last vertex of its list. */
    b->pathFlags[next] = b->pathFlags[slot];
#ifdef VERTEX_CONNECTION
    b->pathLastVertex[next] = b->pathLastVertex[slot];
#endif
    store_mis(b->pathMis, next, mis);
    r.alive = 1;
    return r;
}

__kernel void shade_light(RENDER_KERNEL_PARAMS)
{
    __local int scratch[QUEUE_SCRATCH_INTS];
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    int slot = shade_slot(&b, params.capacity, get_global_id(0), SIMD_LIGHT_SHADING);
    LightHitResult r;
    r.alive = r.shadowRay = r.storeVertex = 0;
    int rejected = 0;
    if (slot >= 0)
        r = shade_light_hit(&b, &params, slot, &rejected);
    /* One reservation for the two queues and the light vertices. */
    int next = next_round_slot(&params);
    Lanes queues = lanes(QUEUE_SHADOW, params.nextRayQueue, COUNTER_LIGHT_VERTICES, NO_COUNTER);
    Lanes wants = lanes(r.shadowRay, r.alive, r.storeVertex, 0);
    Lanes at = group_allocate4(queueCounters, queues, wants, scratch, SIMD_LIGHT_SHADING);
    if (at.x >= 0)
        queueItems[queues.x * params.capacity + at.x] = slot;
    if (at.y >= 0)
        queueItems[queues.y * params.capacity + at.y] = next;
    if (at.z >= 0) /* the path's list now goes on from its next slot, where it continues */
        append_light_vertex(&b, &params, r.alive ? next : slot, at.z, &r.vertex);
    report_nonfinite(queueCounters, rejected);
}
