/* Building the hash grid (hash_grid.h) over the stored light vertices, on
 * the device: count per bucket, exclusive prefix sum, scatter.
 * The prefix sum works in chunks: each work-item scans its own chunk
 * serially (scan_chunks), one work-item scans the chunk totals (scan_totals),
 * and every chunk adds its offset (scan_add) — no barriers, which CPU
 * devices run slowly, and few enough chunks for the serial middle step.
 * The scatter writes each vertex as merging reads it (MergeVertex). */
#include "core/prefetch.h"
#include "interface/shared_types.h"
#include "transport/hash_grid.h"

/* The bucket of vertex i, or -1 past the end. */
INLINE int vertex_bucket(__global const LightVertex* vertices, int count, int i, float cellSize, uint cellCount)
{
    return i < count ? (int)grid_bucket(grid_cell(vload3(0, vertices[i].position), cellSize), cellCount) : -1;
}

/* For hints (CPU devices, core/prefetch.h): the bucket of the vertex
 * GRID_PREFETCH_DISTANCE after i, -1 past the end or where hints are
 * nothing. Buckets lie anywhere in the table, and each vertex's atomic add
 * waited for its bucket's cache line. */
#define GRID_PREFETCH_DISTANCE 8
INLINE int bucket_ahead(__global const LightVertex* vertices, int count, int i, float cellSize, uint cellCount)
{
#ifdef HAS_PREFETCH
    return vertex_bucket(vertices, count, i + GRID_PREFETCH_DISTANCE, cellSize, cellCount);
#else
    return -1;
#endif
}

__kernel void grid_count(__global const LightVertex* vertices, int count, float cellSize, uint cellCount,
                         __global int* bucketCounts)
{
    int i = get_global_id(0);
    int ahead = bucket_ahead(vertices, count, i, cellSize, cellCount);
    if (ahead >= 0)
        PREFETCH(&bucketCounts[ahead], 4);
    if (i >= count)
        return;
    atomic_inc(&bucketCounts[vertex_bucket(vertices, count, i, cellSize, cellCount)]);
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

__kernel void grid_scatter(__global const LightVertex* vertices, int count, float cellSize, uint cellCount,
                           __global const int* bucketStarts, __global int* bucketFill,
                           __global MergeVertex* bucketVertices)
{
    int i = get_global_id(0);
    int ahead = bucket_ahead(vertices, count, i, cellSize, cellCount);
    if (ahead >= 0) {
        PREFETCH(&bucketStarts[ahead], 4);
        PREFETCH(&bucketFill[ahead], 4);
    }
    if (i >= count)
        return;
    __global const LightVertex* v = &vertices[i];
    float3 p = vload3(0, v->position);
    uint b = grid_bucket(grid_cell(p, cellSize), cellCount);
    __global MergeVertex* m = &bucketVertices[bucketStarts[b] + atomic_inc(&bucketFill[b])];
    vstore3(p, 0, m->position);
    m->pathLength = v->pathLength;
    vstore3(vload3(0, v->toLight), 0, m->toLight);
    m->dVCM = v->dVCM;
    vstore3(vload3(0, v->throughput), 0, m->throughput);
    m->dVM = v->dVM;
    m->continuation = v->continuation;
}
