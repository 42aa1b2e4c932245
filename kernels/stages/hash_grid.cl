/* Building the hash grid (hash_grid.h) over the stored light vertices
 * (StoredLightVertex), on the device: count per bucket, exclusive prefix
 * sum, scatter.
 * The prefix sum works in chunks: each work-item scans its own chunk
 * serially (scan_chunks), one work-item scans the chunk totals (scan_totals),
 * and every chunk adds its offset (scan_add) — no barriers, which CPU
 * devices run slowly, and few enough chunks for the serial middle step.
 * The scatter writes each vertex as merging reads it (MergeVertex). */
#include "core/prefetch.h"
#include "interface/shared_types.h"
#include "transport/hash_grid.h"

#define GRID_PREFETCH_DISTANCE 8

INLINE __global const float* stored_position(__global const StoredLightVertex* v)
{
#ifdef VERTEX_CONNECTION
    return v->surface.position;
#else
    return v->position;
#endif
}

/* The bucket of vertex i. */
INLINE int vertex_bucket(__global const StoredLightVertex* vertices, int i, float cellSize, uint cellCount)
{
    return (int)grid_bucket(grid_cell(vload3(0, stored_position(&vertices[i])), cellSize), cellCount);
}

/* Counts each bucket's vertices and keeps, per vertex, its bucket and its
 * place among the bucket's vertices (the count's atomic increment returns
 * it), so the scatter needs neither the hash nor an atomic. */
__kernel void grid_count(__global const StoredLightVertex* vertices, int count, float cellSize, uint cellCount,
                         __global int* bucketCounts, __global int2* vertexPlaces)
{
    int i = get_global_id(0);
#ifdef HAS_PREFETCH
    /* The bucket of the vertex GRID_PREFETCH_DISTANCE ahead: buckets lie
     * anywhere in the table, and each atomic add waits for its cache line.
     * That vertex's position was hinted as many vertices before (without
     * it, 47 % of the kernel's samples waited on its load: the hardware
     * prefetcher does not keep up with LightVertex's 128-byte stride). */
    int ahead = i + GRID_PREFETCH_DISTANCE;
    if (ahead + GRID_PREFETCH_DISTANCE < count)
        PREFETCH(stored_position(&vertices[ahead + GRID_PREFETCH_DISTANCE]), 12);
    if (ahead < count)
        PREFETCH(&bucketCounts[vertex_bucket(vertices, ahead, cellSize, cellCount)], 4);
#endif
    if (i >= count)
        return;
    int b = vertex_bucket(vertices, i, cellSize, cellCount);
    vertexPlaces[i] = (int2)(b, atomic_inc(&bucketCounts[b]));
}

/* In place: values[i] becomes the sum of the values before it in its chunk;
 * chunkTotals[c] the sum of chunk c. */
__kernel void scan_chunks(__global int* values, int count, int chunk, __global int* chunkTotals, int chunks)
{
    int c = get_global_id(0);
    if (c >= chunks)
        return;
    int sum = 0;
    int end = min(count, (c + 1) * chunk);
    for (int i = c * chunk; i < end; ++i) {
        int v = values[i];
        values[i] = sum;
        sum += v;
    }
    chunkTotals[c] = sum;
}

/* One work-item: exclusive prefix sum of the chunk totals; the grand total
 * goes to chunkTotals[chunks]. */
__kernel void scan_totals(__global int* chunkTotals, int chunks)
{
    if (get_global_id(0) != 0)
        return;
    int sum = 0;
    for (int c = 0; c < chunks; ++c) {
        int v = chunkTotals[c];
        chunkTotals[c] = sum;
        sum += v;
    }
    chunkTotals[chunks] = sum;
}

__kernel void scan_add(__global int* values, int count, int chunk, __global const int* chunkTotals)
{
    int i = get_global_id(0);
    if (i < count)
        values[i] += chunkTotals[i / chunk];
    else if (i == count) /* the end of the last bucket */
        values[count] = chunkTotals[(count + chunk - 1) / chunk];
}

/* Each vertex's record (MergeVertex) to its place: bucket start + its place
 * in the bucket. The records land anywhere in the array; on CPU devices they
 * are written with streaming stores, whole cache lines that need not be
 * read first. With merging only the stored vertex is that record already
 * (grid_count 1.3x, grid_scatter 1.5x as fast as from a LightVertex). */
__kernel void grid_scatter(__global const StoredLightVertex* vertices, int count, __global const int2* vertexPlaces,
                           __global const int* bucketStarts, __global MergeVertex* bucketVertices)
{
    int i = get_global_id(0);
#ifdef HAS_PREFETCH
    if (i + GRID_PREFETCH_DISTANCE < count) {
        PREFETCH(&bucketStarts[vertexPlaces[i + GRID_PREFETCH_DISTANCE].x], 4);
        PREFETCH(&vertices[i + GRID_PREFETCH_DISTANCE], sizeof(StoredLightVertex));
    }
#endif
    if (i >= count)
        return;
    __global const StoredLightVertex* v = &vertices[i];
    int2 place = vertexPlaces[i];
    __global float4* m = (__global float4*)&bucketVertices[bucketStarts[place.x] + place.y];
#ifdef VERTEX_CONNECTION
    STREAM_STORE((float4)(vload3(0, v->surface.position), as_float(v->pathLength)), m);
    STREAM_STORE((float4)(vload3(0, v->toLight), v->dVCM), m + 1);
    STREAM_STORE((float4)(vload3(0, v->throughput), v->dVM), m + 2);
    STREAM_STORE((float4)(v->continuation, 0.0f, 0.0f, 0.0f), m + 3);
#else
    __global const float4* record = (__global const float4*)v;
    for (int k = 0; k < 4; ++k)
        STREAM_STORE(record[k], m + k);
#endif
}
