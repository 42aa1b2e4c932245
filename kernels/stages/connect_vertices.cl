/* connect_vertices (`-a bpt`, `-a vcm`): vertex connection. Every camera hit
 * with a non-delta BSDF connects to each stored vertex of the light sub-path
 * with its own index (one light path per camera sample), MIS-weighted against
 * all other techniques (Georgiev's report, eqs. 40-41 and 37), and adds what
 * is visible to its sample. It runs before `shade`, which then moves the path
 * on. One work-item walks its light path and evaluates each connection;
 * whether the two vertices see each other is found one of two ways
 * (Renderer.h, VertexConnections):
 *   inline            the work-item traces each shadow ray itself and adds
 *                     the visible sum to its sample;
 *   CONNECTION_QUEUE  it appends an entry per (camera vertex, light vertex)
 *                     pair to the connection queue: the shadow ray and its
 *                     contribution. trace_connections (connect.cl) traces
 *                     them at the start of the next round, a work-item per
 *                     ray, so that a GPU's threads do equal work instead of
 *                     one traversal per vertex of paths of unequal length.
 *                     A round queues at most one entry per stored light
 *                     vertex (a camera path connects to its own light path
 *                     only): the queue is as long as the light vertex buffer. */
#include "core/nan_policy.h"
#include "core/prefetch.h"
#include "core/queues.h"
#include "geometry/bvh_traversal.h"
#include "geometry/surface.h"
#include "lights/lights.h"
#include "materials/surface_bsdf.h"
#include "materials/volume.h"
#include "transport/camera_vertex.h"
#include "transport/merge_query.h"
#include "transport/mis.h"
#include "transport/path_state.h"

/* The connection of camera vertex cv (throughput beta) to light vertex lv:
 * false if it contributes nothing, else its contribution *c if nothing is in
 * the way of *shadow. */
INLINE bool connect_to_light_vertex(const RenderBuffers* b, const LaunchParams* params, const CameraVertex* cv,
                                    vec3 beta, __global const LightVertex* lv, vec3* c, Ray* shadow, int* rejected)
{
    vec3 toLight = load3(lv->toLight);
    vec2 lightBary = v2(lv->b1, lv->b2);
    SurfaceHit lightHit = recorded_surface_hit(&lv->surface);
    if (!connection_resolved(cv->hit.p, cv->hit.pError, cv->hit.ngF, lightHit.p, lightHit.pError, lightHit.ngF))
        return false;
    vec3 d = v3_sub(lightHit.p, cv->hit.p);
    float dist2 = v3_dot(d, d);
    if (!(dist2 > 0.0f))
        return false;
    float dist = sqrt(dist2);
    d = v3_div(d, dist);
    vec3 dL = to_local(&cv->hit.frame, d);
    vec3 backL = to_local(&lightHit.frame, v3_neg(d));
    if (!sides_agree(&cv->hit, d, dL) || !sides_agree(&lightHit, v3_neg(d), backL))
        return false;
    float cameraFwd, cameraRev, lightFwd, lightRev;
    vec3 fCamera = bsdf_eval(&cv->bsdf, cv->woL, dL, false, &cameraFwd, &cameraRev);
    vec3 toLightL = to_local(&lightHit.frame, toLight);
    Bsdf lightBsdf = surface_bsdf(b, &lightHit, lv->triangle, lightBary, toLightL);
    vec3 fLight = v3_scale(bsdf_eval(&lightBsdf, toLightL, backL, true, &lightFwd, &lightRev),
                           adjoint_shading_correction(&lightHit, toLight, v3_neg(d)));
    if (!(max_component(fCamera) > 0.0f && max_component(fLight) > 0.0f))
        return false;
    float contLight = lv->continuation;
    cameraFwd *= cv->continuation;
    cameraRev *= cv->continuation;
    lightFwd *= contLight;
    lightRev *= contLight;
    /* The throughput's cosines are the shading normals' (the BSDFs'
     * |ns·ω|, the light side adjoint-corrected); the densities' are the
     * surfaces' own (mis_cos). */
    float geometry = fabs(dL.z) * fabs(backL.z) / dist2;
    PathMis lightMis = {lv->dVCM, lv->dVC, lv->dVM};
    float w = mis_weight_connection(lightMis, cv->mis, cameraFwd * mis_cos(lightHit.ngF, d) / dist2,
                                    lightFwd * mis_cos(cv->hit.ngF, d) / dist2, lightRev, cameraRev,
                                    params->vmWeightFactor);
    *c = v3_mul(v3_mul(v3_mul(v3_scale(beta, w * geometry), fCamera), fLight), load3(lv->throughput));
#ifdef HAS_VOLUME_ABSORPTION
    /* From the light vertex back to the camera vertex: inside its solid? */
    *c = v3_mul(*c, segment_absorption(&b->materials[b->triMaterials[lv->triangle]], &lightHit, v3_neg(d), dist));
#endif
    if (!accept_finite(*c, rejected))
        return false;
    *shadow = ray_between(cv->hit.p, cv->hit.pError, cv->hit.ngF, lightHit.p, lightHit.pError, lightHit.ngF);
    return true;
}

/* The first light vertex that entry i + D of the hit queue connects to (its
 * light path's last), whose line came in just before its use when hinted
 * only by its own work-item: 19 % of the kernel's samples waited there. The
 * entry's pathPixel came with prefetch_hit_state's hint D entries ago; its
 * lightPathHead entry with the hint here D/2 entries ago (unhinted, its load
 * had 1.3 % of the kernel's samples, 0.16 % hinted). */
INLINE void prefetch_light_path(const RenderBuffers* b, const LaunchParams* params, int i)
{
#ifdef HAS_PREFETCH
    int slot = queue_item(b->queueItems, b->queueCounters, params->capacity, QUEUE_HITS,
                          i + PREFETCH_DISTANCE + PREFETCH_DISTANCE / 2);
    if (slot >= 0)
        PREFETCH(&b->lightPathHead[b->pathPixel[slot] - params->firstLightPath], 4);
    slot = queue_item(b->queueItems, b->queueCounters, params->capacity, QUEUE_HITS, i + PREFETCH_DISTANCE);
    if (slot < 0)
        return;
    int last = b->lightPathHead[b->pathPixel[slot] - params->firstLightPath];
    if (last >= 0)
        PREFETCH(&b->lightVertices[last], sizeof(LightVertex));
#endif
}

/* Connection queue entry i: a shadow ray and what it adds to camera sample
 * `sample` if nothing is in its way; sample -1: an entry without a ray. */
INLINE void queue_connection(const RenderBuffers* b, int i, int sample, vec3 c, Ray shadow)
{
    if (sample >= 0)
        store_ray(b->connectionOrigins, b->connectionDirections, i, shadow);
    store_vec3w(b->connectionContribution, i, c, 0.0f);
    *connection_sample(b->connectionContribution, i) = sample;
}

/* Connects the camera hit in `slot` (of `depth`) to the light path ending at
 * vertex `last`: into the connection queue from entry `first` on if `queued`
 * (returns the entries used), else traced here and added to its sample. */
INLINE int connect_camera_hit(const RenderBuffers* b, const LaunchParams* params, int slot, int depth, int last,
                              bool queued, int first, int* rejected)
{
    CameraVertex cv = camera_vertex(b, slot);
    if (!bsdf_has_nondelta(&cv.bsdf))
        return 0;
    int sample = b->pathPixel[slot];
    vec3 beta = load_vec3(b->pathThroughput, slot);
    vec3 L = v3s(0.0f);
    int entries = 0;
    for (int v = last; v >= 0; v = b->lightVertices[v].prev) {
        __global const LightVertex* lv = &b->lightVertices[v];
        if (lv->prev >= 0) /* needed after this connection: load it meanwhile */
            PREFETCH(&b->lightVertices[lv->prev], sizeof(LightVertex));
        if (!path_fits(depth + lv->pathLength + 1, params->maxPathLength))
            continue; /* vertices go from the deepest back: shallower ones may still fit */
        vec3 c = v3s(0.0f);
        Ray shadow;
        bool contributes = connect_to_light_vertex(b, params, &cv, beta, lv, &c, &shadow, rejected);
        Hit occluder;
        if (queued)
            queue_connection(b, first + entries++, contributes ? sample : -1, c, shadow);
        else if (contributes && !trace_ray(b->nodes, b->trianglePackets, shadow, true, &occluder, b))
            L = v3_add(L, c);
    }
    add_radiance(b->connectionRadiance, sample, L, rejected);
    return entries;
}

__kernel void connect_vertices(RENDER_KERNEL_PARAMS)
{
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    prefetch_hit_state(&b, params.capacity, QUEUE_HITS, get_global_id(0));
    prefetch_pixel(&b, params.capacity, QUEUE_HITS, get_global_id(0), connectionRadiance);
    prefetch_light_path(&b, &params, get_global_id(0));
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_HITS, get_global_id(0));
    int depth = 0, last = -1; /* last: the light path's last stored vertex, -1: nothing to connect to */
    if (slot >= 0) {
        depth = hit_depth(pathDepth, slot);
        /* Even the first light vertex would make the path too long, or the
         * material has nothing to connect through. */
        if (path_fits(depth + 1 + 1, params.maxPathLength) &&
            material_has_nondelta(&materials[triMaterials[hitTriangle[slot]]]))
            last = lightPathHead[pathPixel[slot] - params.firstLightPath];
    }
#ifdef VERTEX_CONNECTION
    if (slot >= 0 && params.mergeRadius > 0.0f) /* vcm */
        store_merge_query(&b, params.mergeRadius, params.cellCount, slot);
#endif
    int rejected = 0;
#ifdef CONNECTION_QUEUE
    /* An entry for each light vertex that fits: at most the path's stored
     * vertices, and those of length up to maxPathLength - depth - 1 (their
     * path lengths differ). The counter keeps counting past the queue's end,
     * which the host reports as an error. */
    __local int scratch[QUEUE_SCRATCH_INTS];
    int n = last >= 0 ? min(lightVertices[last].number, params.maxPathLength - depth - 1) : 0;
    int first = group_allocate_n(queueCounters, COUNTER_CONNECTIONS, n, scratch, false);
    if (n > 0 && first + n <= params.connectionCapacity) {
        int used = connect_camera_hit(&b, &params, slot, depth, last, true, first, &rejected);
        for (int i = first + used; i < first + n; ++i) /* reserved, not used */
            *connection_sample(connectionContribution, i) = -1;
    }
#else
    if (last >= 0)
        connect_camera_hit(&b, &params, slot, depth, last, false, 0, &rejected);
#endif
    report_nonfinite(queueCounters, rejected);
}
