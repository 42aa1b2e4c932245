/* generate: start new paths in the round's region after the places of the
 * last round's hits (path_state.h), as many as plan_round decided, and
 * append their first rays to the ray queue after the continuing ones: item i
 * takes sample firstSample + ROUND_FIRST + i and ray-queue entry
 * ROUND_RAYS + i, with no atomics.
 *   plan_round      one work-item, first in every round (below);
 *   generate        camera paths, samplesPerIteration per pixel (sample_pixel,
 *                   path_state.h), with a jittered primary ray (box filter);
 *   generate_light  light paths (light path index = sample index) from a light
 *                   chosen by power, by emission sampling. */
#include "core/queues.h"
#include "core/rng.h"
#include "interface/inline.h"
#include "lights/camera.h"
#include "lights/lights.h"
#include "materials/emission.h"
#include "transport/mis.h"
#include "transport/path_state.h"

/* The round's plan: as many new paths as there are samples left in the
 * phase and slots in the round's region after the places of the last round's
 * hits, where its continuing paths lie (path_state.h); the rays the round
 * traces counted (with the previous round's shadow rays); the queues the
 * round fills emptied. Being on the device, it lets the host enqueue a round
 * before the previous one has run (Renderer::runPhase): every kernel is
 * launched over an upper bound of its queue and skips the items past its
 * actual size. */
__kernel void plan_round(RENDER_KERNEL_PARAMS)
{
    if (get_global_id(0) != 0)
        return;
    __global int* c = queueCounters;
    int rays = c[COUNTER_INDEX(params.rayQueue)];
    int issued = c[COUNTER_INDEX(COUNTER_ISSUED)];
    int firstNewSlot = c[COUNTER_INDEX(QUEUE_HITS)];
    int fresh = min(params.capacity - firstNewSlot, params.samples - issued);
    c[COUNTER_INDEX(COUNTER_ROUND_FIRST)] = issued;
    c[COUNTER_INDEX(COUNTER_ROUND_NEW)] = fresh;
    c[COUNTER_INDEX(COUNTER_ROUND_RAYS)] = rays;
    c[COUNTER_INDEX(COUNTER_ROUND_NEW_SLOT)] = firstNewSlot;
    c[COUNTER_INDEX(COUNTER_ISSUED)] = issued + fresh;
    c[COUNTER_INDEX(params.rayQueue)] = rays + fresh;
    *(__global ulong*)&c[COUNTER_INDEX(COUNTER_RAYS_TRACED)] += (ulong)(rays + fresh + c[COUNTER_INDEX(QUEUE_SHADOW)]);
    c[COUNTER_INDEX(QUEUE_HITS)] = 0;
    c[COUNTER_INDEX(QUEUE_ESCAPED)] = 0;
    c[COUNTER_INDEX(QUEUE_SHADOW)] = 0;
    c[COUNTER_INDEX(COUNTER_CONNECTIONS)] = 0; /* traced before this plan (Renderer::round) */
    c[COUNTER_INDEX(params.nextRayQueue)] = 0;
}

/* The slot of new path i of the round (and its sample), or -1 past them: in
 * the round's region, after the places of the last round's hits. */
INLINE int new_path_slot(__global int* queueItems, __global const int* queueCounters, const LaunchParams* p,
                         int* sample)
{
    int i = get_global_id(0);
    if (i >= queueCounters[COUNTER_INDEX(COUNTER_ROUND_NEW)])
        return -1;
    int slot = region_first_slot(p->rayQueue, p->capacity) + queueCounters[COUNTER_INDEX(COUNTER_ROUND_NEW_SLOT)] + i;
    queueItems[p->rayQueue * p->capacity + queueCounters[COUNTER_INDEX(COUNTER_ROUND_RAYS)] + i] = slot;
    *sample = p->firstSample + queueCounters[COUNTER_INDEX(COUNTER_ROUND_FIRST)] + i;
    return slot;
}

__kernel void generate(RENDER_KERNEL_PARAMS)
{
    int sample;
    int slot = new_path_slot(queueItems, queueCounters, &params, &sample);
    if (slot < 0)
        return;
    int pixel = sample_pixel(&params, sample);
    Uniform4 u = rng_uniform4(params.seed, sample_index(&params, sample), (uint)pixel, 0u, 0u);
    Ray ray = camera_ray(camera, pixel, u.y, u.z);
    store_ray(rayOrigins, rayDirections, slot, ray);
    pathPixel[slot] = sample;
    pathDepth[slot] = 0;
    store_vec3w(pathThroughput, slot, v3s(1.0f), 1.0f);
    pathPrevPdf[slot] = 0.0f; /* what the camera sees directly gets full weight */
#ifdef BIDIRECTIONAL
    store_mis(pathMis, slot, mis_camera_start(params.lightTracePaths, camera_pdf_w(camera, ray.direction)));
    pathFlags[slot] = PATH_SPECULAR;
#endif
}

__kernel void generate_light(RENDER_KERNEL_PARAMS)
{
    int lightPath;
    int slot = new_path_slot(queueItems, queueCounters, &params, &lightPath);
    if (slot < 0)
        return;
    uint index = sample_index(&params, lightPath), pixel = (uint)sample_pixel(&params, lightPath);
    Uniform4 u = rng_light_uniform4(params.seed, index, pixel, 0u, 2u);
    Uniform4 v = rng_light_uniform4(params.seed, index, pixel, 0u, 3u);
    EmissionSample e;
    Ray ray;
    vec3 beta = v3s(0.0f); /* a failed sample travels with nothing to carry and stores nothing */
    PathMis mis = {0.0f, 0.0f, 0.0f};
    bool finite = false;
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    if (sample_scene_emission(&b, u, v, &e)) {
        finite = e.finite;
        float emissionPdfW = e.pdfPosition * e.pdfDirection;
        beta = v3_scale(e.radiance, e.cosAtLight / emissionPdfW);
        mis = mis_light_start(e.directPdf, emissionPdfW, e.cosAtLight, e.finite, e.deltaPosition || e.deltaDirection,
                              params.vcWeightFactor);
        ray.origin = e.light >= 0 && lights[e.light].type == LIGHT_TRIANGLE
                         ? offset_ray_origin(e.position, e.positionError, e.normal, e.direction)
                         : e.position;
        ray.direction = e.direction;
    } else {
        ray.origin = load3c(scene->center);
        ray.direction = v3(0.0f, 0.0f, 1.0f);
    }
    ray.tMax = INFINITY;
    store_ray(rayOrigins, rayDirections, slot, ray);
    pathPixel[slot] = lightPath;
    pathDepth[slot] = 0;
    store_vec3w(pathThroughput, slot, beta, 0.0f);
    store_mis(pathMis, slot, mis);
    pathFlags[slot] = finite ? PATH_FINITE_LIGHT : 0;
    pathLastVertex[slot] = -1;
    lightPathHead[lightPath - params.firstLightPath] = -1;
}
