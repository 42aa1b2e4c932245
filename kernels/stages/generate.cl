/* generate: start new paths in the first `generateCount` free slots and
 * append their first rays to the ray queue. The host knows how many samples
 * were handed out and how long the ray queue is, so no atomics are needed:
 * item i takes sample firstSample + i and ray-queue entry rayQueueLength + i.
 *   generate        camera paths, one per pixel (pixel = sample index), with a
 *                   jittered primary ray (box filter);
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

INLINE int take_free_slot(__global int* queueItems, __global int* queueCounters, const LaunchParams* p)
{
    int i = get_global_id(0);
    if (i == 0)
        queueCounters[COUNTER_INDEX(p->rayQueue)] = p->rayQueueLength + p->generateCount;
    if (i >= p->generateCount)
        return -1;
    int slot = queueItems[p->freeQueue * p->capacity + i];
    queueItems[p->rayQueue * p->capacity + p->rayQueueLength + i] = slot;
    return slot;
}

__kernel void generate(RENDER_KERNEL_PARAMS)
{
    int slot = take_free_slot(queueItems, queueCounters, &params);
    if (slot < 0)
        return;
    int sample = params.firstSample + (int)get_global_id(0);
    Uniform4 u = rng_uniform4(params.seed, params.iteration, (uint)sample, 0u, 0u);
    Ray ray = camera_ray(camera, sample, u.y, u.z);
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
    int slot = take_free_slot(queueItems, queueCounters, &params);
    if (slot < 0)
        return;
    int lightPath = params.firstSample + (int)get_global_id(0);
    Uniform4 u = rng_uniform4(params.seed, params.iteration, (uint)lightPath, 0u, 2u);
    Uniform4 v = rng_uniform4(params.seed, params.iteration, (uint)lightPath, 0u, 3u);
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
