/* The hash grid over light vertices (SmallVCM's hashgrid.hxx, on the
 * device): cells of size 2r hashed into `cellCount` buckets; bucket b holds
 * the vertices bucketVertices[bucketStarts[b], bucketStarts[b+1]), each a
 * 64-byte MergeVertex. A query sphere of radius r around x lies within the
 * 2×2×2 cells nearest x. */
#ifndef WAVEVCM_HASH_GRID_H
#define WAVEVCM_HASH_GRID_H

#include "interface/inline.h"

INLINE int3 grid_cell(float3 p, float cellSize)
{
    float3 c = floor(p / cellSize);
    return (int3)((int)c.x, (int)c.y, (int)c.z);
}

/* Cells are hashed in blocks of 2×2×2, whose eight cells take eight
 * consecutive buckets: the bucket starts and the records of the 2×2×2 cells
 * a query visits then lie in the query's 1-8 blocks (3.4 on average) instead
 * of in eight places anywhere in the grid. A block's hash is Teschner et
 * al.'s spatial hash (SmallVCM's), folded to the table's 2^k / 8 blocks by a
 * multiplicative (Fibonacci) hash, whose top bits mix all of the hash's bits
 * where `% cellCount` costs an integer division. */
INLINE uint grid_bucket(int3 cell, uint cellCount)
{
    int3 block = cell >> 1; /* arithmetic shift: floor(cell / 2) */
    uint h = ((uint)block.x * 73856093u) ^ ((uint)block.y * 19349663u) ^ ((uint)block.z * 83492791u);
    uint inBlock = (uint)(cell.x & 1) | (uint)(cell.y & 1) << 1 | (uint)(cell.z & 1) << 2;
    return (h * 2654435769u) >> (clz(cellCount) + 4) << 3 | inBlock;
}

/* The buckets of the 2×2×2 cells nearest x, with duplicates (two cells
 * hashing to one bucket) replaced by -1 so no vertex is visited twice. */
INLINE void grid_query_buckets(float3 x, float cellSize, uint cellCount, int buckets[8])
{
    float3 scaled = x / cellSize;
    float3 base = floor(scaled);
    int3 c = (int3)((int)base.x, (int)base.y, (int)base.z);
    float3 frac = scaled - base;
    int3 o = (int3)(frac.x < 0.5f ? -1 : 1, frac.y < 0.5f ? -1 : 1, frac.z < 0.5f ? -1 : 1);
    for (int i = 0; i < 8; ++i) {
        int3 cell = c + (int3)((i & 1) ? o.x : 0, (i & 2) ? o.y : 0, (i & 4) ? o.z : 0);
        int b = (int)grid_bucket(cell, cellCount);
        for (int j = 0; j < i; ++j)
            if (buckets[j] == b)
                b = -1;
        buckets[i] = b;
    }
}

#endif
