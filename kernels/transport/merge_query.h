/* A camera hit's merge query (vcm), found one kernel ahead. A query waits on
 * two cache misses, one after the other: its buckets' starts, then the
 * records they point to (hash_grid.h). connect_vertices, which runs on the
 * same hits just before merge, stores each hit's eight buckets, so that
 * merge can hint the queries of the entries ahead of its own in three steps,
 * each loading only lines the step before brought in. (ppm and bpm, which
 * have no connect_vertices, compute the buckets in merge and hint only the
 * query's own. A separate pass that stored them cost what merge gained:
 * docs/performance.md.) */
#ifndef WAVEVCM_MERGE_QUERY_H
#define WAVEVCM_MERGE_QUERY_H

#include "core/prefetch.h"
#include "core/queues.h"
#include "geometry/surface.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/bsdf.h"
#include "transport/hash_grid.h"

/* Hit-queue entries ahead of its own that merge hints: their stored buckets,
 * those buckets' starts, and each bucket's first record. */
#define MERGE_AHEAD_BUCKETS 6
#define MERGE_AHEAD_STARTS 4
#define MERGE_AHEAD_RECORDS 2

/* Stores the buckets of the query at the hit in `slot`, from the point merge's
 * camera vertex will have (surface_hit_point, as surface_hit computes it).
 * A material without non-delta lobes, where merge does not query, stores
 * bucket 0 eight times: the hints then read valid entries. */
INLINE void store_merge_query(const RenderBuffers* b, float mergeRadius, uint cellCount, int slot)
{
    int tri = b->hitTriangle[slot];
    int buckets[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    if (material_has_nondelta(&b->materials[b->triMaterials[tri]])) {
        vec3 pError;
        vec3 p = surface_hit_point(b->triVertices, tri, load_vec2(b->hitBary, slot), &pError);
        grid_query_buckets(to_float3(p), 2.0f * mergeRadius, cellCount, buckets);
    }
    __global int4* stored = (__global int4*)&b->queryBuckets[8 * slot];
    stored[0] = (int4)(buckets[0], buckets[1], buckets[2], buckets[3]);
    stored[1] = (int4)(buckets[4], buckets[5], buckets[6], buckets[7]);
}

/* merge's hints for the queries of the entries ahead of entry i. */
INLINE void prefetch_merge_queries(const RenderBuffers* b, int capacity, int i)
{
#ifdef HAS_PREFETCH
    int slot = queue_item(b->queueItems, b->queueCounters, capacity, QUEUE_HITS, i + MERGE_AHEAD_BUCKETS);
    if (slot >= 0)
        PREFETCH(&b->queryBuckets[8 * slot], 32);
    slot = queue_item(b->queueItems, b->queueCounters, capacity, QUEUE_HITS, i + MERGE_AHEAD_STARTS);
    if (slot >= 0)
        for (int k = 0; k < 8; ++k)
            PREFETCH(&b->bucketStarts[b->queryBuckets[8 * slot + k]], 4);
    slot = queue_item(b->queueItems, b->queueCounters, capacity, QUEUE_HITS, i + MERGE_AHEAD_RECORDS);
    if (slot >= 0)
        for (int k = 0; k < 8; ++k)
            PREFETCH(&b->bucketVertices[b->bucketStarts[b->queryBuckets[8 * slot + k]]], 16);
#endif
}

#endif
