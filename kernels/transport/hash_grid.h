/* The hash grid over light vertices (SmallVCM's hashgrid.hxx, on the
 * device): cells of size 2r hashed into `cellCount` buckets; bucket b holds
 * the vertices bucketVertices[bucketStarts[b], bucketStarts[b+1]), each a
 * 64-byte MergeVertex. A query sphere of radius r around x lies within the
 * 2×2×2 cells nearest x. */
#ifndef WAVEVCM_HASH_GRID_H
#define WAVEVCM_HASH_GRID_H

#include "core/simd.h"
#include "interface/inline.h"

INLINE int3 grid_cell(float3 p, float cellSize)
{
    float3 c = floor(p / cellSize);
    return (int3)((int)c.x, (int)c.y, (int)c.z);
}

/* Teschner et al.'s primes, one per axis. */
#define GRID_PRIME_X 73856093u
#define GRID_PRIME_Y 19349663u
#define GRID_PRIME_Z 83492791u

/* Cells are hashed in blocks of 2×2×2, whose eight cells take eight
 * consecutive buckets: the bucket starts and the records of the 2×2×2 cells
 * a query visits then lie in the query's 1-8 blocks (3.4 on average) instead
 * of in eight places anywhere in the grid. A block's hash is Teschner et
 * al.'s spatial hash (SmallVCM's), folded to the table's 2^k / 8 blocks by a
 * multiplicative (Fibonacci) hash, whose top bits mix all of the hash's bits
 * where `% cellCount` costs an integer division. */

/* One axis's term of a block's hash (the block's coordinate is
 * floor(cell / 2), an arithmetic shift), and the cell's bit of its place in
 * the block. */
INLINE uint grid_axis_hash(int coordinate, uint prime) { return (uint)(coordinate >> 1) * prime; }
INLINE uint grid_axis_bit(int coordinate, int axis) { return (uint)(coordinate & 1) << axis; }

/* The bucket of the cell at place inBlock of the block whose hash is h. */
INLINE uint grid_fold(uint h, uint inBlock, uint cellCount)
{
    return (h * 2654435769u) >> (clz(cellCount) + 4) << 3 | inBlock;
}

INLINE uint grid_bucket(int3 cell, uint cellCount)
{
    uint h = grid_axis_hash(cell.x, GRID_PRIME_X) ^ grid_axis_hash(cell.y, GRID_PRIME_Y) ^
             grid_axis_hash(cell.z, GRID_PRIME_Z);
    return grid_fold(h, grid_axis_bit(cell.x, 0) | grid_axis_bit(cell.y, 1) | grid_axis_bit(cell.z, 2), cellCount);
}

/* The buckets of the 2×2×2 cells nearest x: cell c = floor(x / cellSize) and
 * its neighbour n = c ± 1 on each axis, toward x's nearer side, bucket k
 * taking axis a's coordinate from n where bit a of k is set (the order of
 * the loop merge.cl walks). The eight buckets are always distinct: two of
 * the cells differ by 1 on some axis, so their parities, the bucket's low
 * three bits, differ there, whatever their blocks hash to. The block hash
 * is a XOR of one term per axis, so it takes six products, not 24. */
INLINE void grid_query_buckets(float3 x, float cellSize, uint cellCount, int buckets[8])
{
    float3 scaled = x / cellSize;
    float3 base = floor(scaled);
    int cx = (int)base.x, cy = (int)base.y, cz = (int)base.z;
    int nx = cx + (scaled.x - base.x < 0.5f ? -1 : 1);
    int ny = cy + (scaled.y - base.y < 0.5f ? -1 : 1);
    int nz = cz + (scaled.z - base.z < 0.5f ? -1 : 1);
    /* grid_bucket's terms, per axis, for c (0) and n (1). */
    uint hx0 = grid_axis_hash(cx, GRID_PRIME_X), hx1 = grid_axis_hash(nx, GRID_PRIME_X);
    uint hy0 = grid_axis_hash(cy, GRID_PRIME_Y), hy1 = grid_axis_hash(ny, GRID_PRIME_Y);
    uint hz0 = grid_axis_hash(cz, GRID_PRIME_Z), hz1 = grid_axis_hash(nz, GRID_PRIME_Z);
    uint px0 = grid_axis_bit(cx, 0), px1 = grid_axis_bit(nx, 0);
    uint py0 = grid_axis_bit(cy, 1), py1 = grid_axis_bit(ny, 1);
    uint pz0 = grid_axis_bit(cz, 2), pz1 = grid_axis_bit(nz, 2);
    SCALAR_LOOP
    for (int k = 0; k < 8; ++k) {
        uint h = ((k & 1) ? hx1 : hx0) ^ ((k & 2) ? hy1 : hy0) ^ ((k & 4) ? hz1 : hz0);
        uint inBlock = ((k & 1) ? px1 : px0) | ((k & 2) ? py1 : py0) | ((k & 4) ? pz1 : pz0);
        buckets[k] = (int)grid_fold(h, inBlock, cellCount);
    }
}

#endif
