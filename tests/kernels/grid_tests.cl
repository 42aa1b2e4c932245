/* Test-only kernel: a range query through the hash grid, as merge.cl does
 * it, returning how many vertices lie within r of each query point and the
 * sum of their indices (so a wrong or duplicated vertex shows). */
#include "interface/shared_types.h"
#include "transport/hash_grid.h"

__kernel void grid_query(__global const LightVertex* vertices, __global const int* bucketStarts,
                         __global const MergeVertex* bucketVertices, uint buckets, float radius,
                         __global const float4* queries, int queryCount, __global int* found,
                         __global long* indexSums)
{
    int q = get_global_id(0);
    if (q >= queryCount)
        return;
    float3 x = queries[q].xyz;
    int b[8];
    grid_query_buckets(x, 2.0f * radius, buckets, b);
    int n = 0;
    long sum = 0;
    for (int k = 0; k < 8; ++k) {
        for (int j = bucketStarts[b[k]]; j < bucketStarts[b[k] + 1]; ++j) {
            int v = bucketVertices[j].pathLength; /* the test gives each vertex its index there */
            float3 d = vload3(0, bucketVertices[j].position) - x;
            if (dot(d, d) <= radius * radius) {
                ++n;
                sum += v;
            }
        }
    }
    found[q] = n;
    indexSums[q] = sum;
}
