/* connect_vertices (`-a bpt`): vertex connection. Every camera hit with a
 * non-delta BSDF connects to each stored vertex of the light sub-path with
 * its own index (one light path per camera path), MIS-weighted against all
 * other techniques (Georgiev's report, eqs. 40-41 and 37), and adds what is
 * visible to its pixel. It runs before `shade`, which then moves the path on.
 * One work-item walks its whole light path and traces each shadow ray
 * itself: the number of connections varies per path. */
#include "core/nan_policy.h"
#include "core/prefetch.h"
#include "core/queues.h"
#include "geometry/bvh_traversal.h"
#include "geometry/surface.h"
#include "lights/lights.h"
#include "materials/surface_bsdf.h"
#include "transport/camera_vertex.h"
#include "transport/mis.h"
#include "transport/path_state.h"

/* The last stored vertex of the light path that queue entry i connects to,
 * -1 for none or past the queue's end. */
INLINE int light_path_ahead(const RenderBuffers* b, const LaunchParams* params, int i)
{
    int slot = queue_item(b->queueItems, b->queueCounters, params->capacity, QUEUE_HITS, i);
    return slot < 0 ? -1 : b->lightPathHead[b->pathPixel[slot] - params->firstLightPath];
}

/* Hints for the connections ahead: the last light vertex of entry i + D's
 * light path, and the triangle of entry i + D/2's, which that hint brought. */
INLINE void prefetch_light_paths(const RenderBuffers* b, const LaunchParams* params, int i)
{
#ifdef HAS_PREFETCH
    int v = light_path_ahead(b, params, i + PREFETCH_DISTANCE);
    if (v >= 0)
        PREFETCH(&b->lightVertices[v], sizeof(LightVertex));
    v = light_path_ahead(b, params, i + PREFETCH_DISTANCE / 2);
    if (v >= 0)
        prefetch_triangle(b, b->lightVertices[v].triangle);
#endif
}

__kernel void connect_vertices(RENDER_KERNEL_PARAMS)
{
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    prefetch_hit_state(&b, params.capacity, QUEUE_HITS, get_global_id(0));
    prefetch_pixel(&b, params.capacity, QUEUE_HITS, get_global_id(0), connectionRadiance);
    prefetch_light_paths(&b, &params, get_global_id(0));
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_HITS, get_global_id(0));
    if (slot < 0)
        return;
    int depth = hit_depth(pathDepth, slot);
    if (!path_fits(depth + 1 + 1, params.maxPathLength)) /* even the first light vertex makes it too long */
        return;
    if (!material_has_nondelta(&materials[triMaterials[hitTriangle[slot]]]))
        return;
    int pixel = pathPixel[slot];
    int last = lightPathHead[pixel - params.firstLightPath];
    if (last < 0)
        return; /* the light path stored no vertex */
    PREFETCH(&lightVertices[last], sizeof(LightVertex));
    CameraVertex cv = camera_vertex(&b, slot);
    if (!bsdf_has_nondelta(&cv.bsdf))
        return;
    vec3 beta = load_vec3(pathThroughput, slot);
    int rejected = 0;

    vec3 L = v3s(0.0f);
    for (int v = last; v >= 0; v = lightVertices[v].prev) {
        __global const LightVertex* lv = &lightVertices[v];
        if (lv->prev >= 0) /* needed after this connection: load it meanwhile */
            PREFETCH(&lightVertices[lv->prev], sizeof(LightVertex));
        if (!path_fits(depth + lv->pathLength + 1, params.maxPathLength))
            continue; /* vertices go from the deepest back: shallower ones may still fit */
        vec3 toLight = load3(lv->toLight);
        vec2 lightBary = v2(lv->b1, lv->b2);
        SurfaceHit lightHit = scene_surface_hit(&b, lv->triangle, lightBary, toLight);
        if (!connection_resolved(cv.hit.p, cv.hit.pError, cv.hit.ngF, lightHit.p, lightHit.pError, lightHit.ngF))
            continue;
        vec3 d = v3_sub(lightHit.p, cv.hit.p);
        float dist2 = v3_dot(d, d);
        if (!(dist2 > 0.0f))
            continue;
        float dist = sqrt(dist2);
        d = v3_div(d, dist);
        vec3 dL = to_local(&cv.hit.frame, d);
        vec3 backL = to_local(&lightHit.frame, v3_neg(d));
        if (!sides_agree(&cv.hit, d, dL) || !sides_agree(&lightHit, v3_neg(d), backL))
            continue;
        float cameraFwd, cameraRev, lightFwd, lightRev;
        vec3 fCamera = bsdf_eval(&cv.bsdf, cv.woL, dL, false, &cameraFwd, &cameraRev);
        vec3 toLightL = to_local(&lightHit.frame, toLight);
        Bsdf lightBsdf = surface_bsdf(&b, lv->triangle, lightBary, toLightL, lightHit.frontSide);
        vec3 fLight = v3_scale(bsdf_eval(&lightBsdf, toLightL, backL, true, &lightFwd, &lightRev),
                               adjoint_shading_correction(&lightHit, toLight, v3_neg(d)));
        if (!(max_component(fCamera) > 0.0f && max_component(fLight) > 0.0f))
            continue;
        float contLight = continuation_probability(&lightBsdf);
        cameraFwd *= cv.continuation;
        cameraRev *= cv.continuation;
        lightFwd *= contLight;
        lightRev *= contLight;
        /* The throughput's cosines are the shading normals' (the BSDFs'
         * |ns·ω|, the light side adjoint-corrected); the densities' are the
         * surfaces' own (mis_cos). */
        float geometry = fabs(dL.z) * fabs(backL.z) / dist2;
        PathMis lightMis = {lv->dVCM, lv->dVC, lv->dVM};
        float w = mis_weight_connection(lightMis, cv.mis, cameraFwd * mis_cos(lightHit.ngF, d) / dist2,
                                        lightFwd * mis_cos(cv.hit.ngF, d) / dist2, lightRev, cameraRev,
                                        params.vmWeightFactor);
        vec3 c = v3_mul(v3_mul(v3_mul(v3_scale(beta, w * geometry), fCamera), fLight), load3(lv->throughput));
        if (!accept_finite(c, &rejected))
            continue;
        Hit occluder;
        Ray shadow = ray_between(cv.hit.p, cv.hit.pError, cv.hit.ngF, lightHit.p, lightHit.pError, lightHit.ngF);
        if (!trace_ray(nodes, trianglePackets, shadow, true, &occluder, &b))
            L = v3_add(L, c);
    }
    add_radiance(connectionRadiance, pixel, L, &rejected);
    report_nonfinite(queueCounters, rejected);
}
