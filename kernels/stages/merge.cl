/* merge (`-a ppm`, `-a bpm`, `-a vcm`): vertex merging. Every camera hit
 * with a non-delta BSDF gathers the light vertices within radius r (a range
 * query in the hash grid) as a path sampling technique (Georgiev et al. 2012):
 * each merge adds f · throughput_light / (π r² N_light), weighted against all
 * other techniques with dVCM and dVM (eqs. 37-39; ppm: weight 1). It runs
 * before `shade`, which then moves the path on. No cosine at the camera
 * vertex: the light vertices' density on the surface already carries it
 * (with a shading normal, the ratio of its cosine to the geometric one).
 * Each candidate is one cache line (MergeVertex), its bucket's candidates
 * one after another. Under vcm the query's buckets come from
 * connect_vertices (transport/merge_query.h). */
#include "core/nan_policy.h"
#include "core/prefetch.h"
#include "core/queues.h"
#include "core/simd.h"
#include "geometry/surface.h"
#include "transport/camera_vertex.h"
#include "transport/hash_grid.h"
#include "transport/merge_query.h"
#include "transport/mis.h"
#include "transport/path_state.h"

__kernel void merge(RENDER_KERNEL_PARAMS)
{
    RenderBuffers b = RENDER_BUFFERS_VALUE;
    prefetch_hit_state(&b, params.capacity, QUEUE_HITS, get_global_id(0));
    prefetch_pixel(&b, params.capacity, QUEUE_HITS, get_global_id(0), mergingRadiance);
#ifdef VERTEX_CONNECTION
    prefetch_merge_queries(&b, params.capacity, get_global_id(0));
#endif
    int slot = queue_item(queueItems, queueCounters, params.capacity, QUEUE_HITS, get_global_id(0));
    if (slot < 0)
        return;
    int tri = hitTriangle[slot];
    if (!material_has_nondelta(&materials[triMaterials[tri]]))
        return;
    CameraVertex cv = camera_vertex(&b, slot);
    if (!bsdf_has_nondelta(&cv.bsdf))
        return;
    float radius2 = params.mergeRadius * params.mergeRadius;
    int buckets[8];
#ifdef VERTEX_CONNECTION /* vcm: stored by connect_vertices */
    SCALAR_LOOP
    for (int k = 0; k < 8; ++k)
        buckets[k] = queryBuckets[8 * slot + k];
#else
    grid_query_buckets(to_float3(cv.hit.p), 2.0f * params.mergeRadius, params.cellCount, buckets);
    /* Hints for the scan below: the buckets' starts, then each bucket's first
     * record. Both lie anywhere in the grid; hinted together, their cache
     * misses overlap instead of each bucket waiting for the one before. */
    for (int k = 0; k < 8; ++k)
        PREFETCH(&bucketStarts[buckets[k]], 4); /* its end, the next int, shares the line 15 times in 16 */
    for (int k = 0; k < 8; ++k)
        PREFETCH(&bucketVertices[bucketStarts[buckets[k]]], 16);
#endif
    int depth = hit_depth(pathDepth, slot);

    vec3 sum = v3s(0.0f);
    SCALAR_LOOP
    for (int k = 0; k < 8; ++k) {
        int end = bucketStarts[buckets[k] + 1];
        SCALAR_LOOP
        for (int j = bucketStarts[buckets[k]]; j < end; ++j) {
            __global const MergeVertex* lv = &bucketVertices[j];
            vec3 d = v3_sub(load3(lv->position), cv.hit.p);
            if (v3_dot(d, d) > radius2)
                continue;
            if (!path_fits(depth + lv->pathLength, params.maxPathLength))
                continue;
            /* The light arrives along the light vertex's incoming direction. */
            vec3 toLight = load3(lv->toLight);
            vec3 toLightL = to_local(&cv.hit.frame, toLight);
            if (!sides_agree(&cv.hit, toLight, toLightL))
                continue;
            /* The light vertices' density per area carries the geometric
             * cosine |ng·ωi|; the camera vertex integrates f |ns·ωi| dωi. */
            float cosGeometric = fabs(v3_dot(toLight, cv.hit.ngF));
            if (!(cosGeometric > 0.0f))
                continue;
            float shadingFactor = fabs(toLightL.z) / cosGeometric;
            float pdfFwd, pdfRev;
            vec3 f = bsdf_eval(&cv.bsdf, cv.woL, toLightL, false, &pdfFwd, &pdfRev);
            if (!(max_component(f) > 0.0f))
                continue;
            float w = 1.0f;
#ifndef PPM
            PathMis lightMis = {lv->dVCM, 0.0f, lv->dVM}; /* eq. 38 has no dVC term */
            w = mis_weight_merge(lightMis, cv.mis, pdfFwd * cv.continuation, pdfRev * lv->continuation,
                                 params.vcWeightFactor);
#endif
            sum = v3_add(sum, v3_mul(v3_scale(f, w * shadingFactor), load3(lv->throughput)));
        }
    }
    int rejected = 0;
    add_radiance(mergingRadiance, pathPixel[slot],
                 v3_scale(v3_mul(load_vec3(pathThroughput, slot), sum), params.vmNormalization), &rejected);
    report_nonfinite(queueCounters, rejected);
}
