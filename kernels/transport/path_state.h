/* Path state in structure-of-arrays form: one array per field, indexed by
 * path slot (the fields are declared in kernel_interface.h). Rays pack tMax
 * into direction.w.
 *
 * Path length, one convention for camera and light sub-paths alike: a full
 * path's length is its number of segments, the camera's first included (a
 * light seen directly has length 1), at most maxPathLength. A sub-path
 * vertex's depth is the number of segments from its sub-path's start (camera
 * or light) to it. pathDepth holds the segments traced before the current
 * ray, so the vertex that ray finds has depth pathDepth + 1 (hit_depth). A
 * camera vertex of depth s and a light vertex of depth t make a full path of
 *   s       segments by an emission hit (or escape) there,
 *   s + 1   by next-event estimation from it,
 *   s + t + 1 by a connection (the connecting segment),
 *   s + t   by a merge (the two vertices become one),
 *   t + 1   by connecting the light vertex to the camera. */
#ifndef WAVEVCM_PATH_STATE_H
#define WAVEVCM_PATH_STATE_H

#include "core/prefetch.h"
#include "core/queues.h"
#include "core/ray.h"
#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"

/* Paths by round, in two regions of `capacity` slots, one per round parity
 * (pbrt-v4's queues of work items, as path state): a path that continues
 * from hit-queue entry i is written whole to slot i of the other region
 * (store_continuation), and generate starts the next round's new paths after
 * the places of this round's hits. So the rays of a round, and its hits, lie
 * in slot order with gaps only where paths ended, and every kernel reads its
 * queue's path state nearly in address order, with neither a list of free
 * slots nor state carried across a work-group's barriers. Against paths
 * that kept their slots (2-core machine, Cornell box, medians): pt 0.96x,
 * bpt 1.13x, vcm 1.17x on two one-core pipelines; on one over both cores,
 * which pushes through work-groups as GPUs do, 1.00-1.19x
 * (docs/performance.md). */

/* The first slot of the region that holds the rays of `rayQueue`'s round. */
INLINE int region_first_slot(int rayQueue, int capacity) { return rayQueue == QUEUE_RAYS(0) ? 0 : capacity; }

/* The slot where the path a shade kernel's work-item shades (hit-queue entry
 * get_global_id(0)) continues next round. */
INLINE int next_round_slot(const LaunchParams* p)
{
    return region_first_slot(p->nextRayQueue, p->capacity) + (int)get_global_id(0);
}

/* Bits of pathFlags. */
#define PATH_FINITE_LIGHT 1 /* a light path from a light with a position */
#define PATH_SPECULAR 2     /* a camera path with only delta scattering so far */
/* Above the bits: a light path's vertices stored so far (LightVertex.number). */
#define PATH_STORED_ONE 256

/* Depth of the vertex the current ray of `slot` finds (or of the segment it escapes along). */
INLINE int hit_depth(__global const int* pathDepth, int slot) { return pathDepth[slot] + 1; }

/* Whether a full path of `segments` segments is within the limit. */
INLINE bool path_fits(int segments, int maxPathLength) { return segments <= maxPathLength; }

/* Samples. An iteration takes samplesPerIteration samples of every pixel:
 * sample s is pixel s mod pixels in pass s div pixels, and the random
 * numbers of pass k of iteration i are those of sample index
 * i · samplesPerIteration + k of the pixel (core/rng.h). So an image is the
 * same, sample for sample, whatever the samples per iteration. The
 * bidirectional algorithms number their light paths the same way: light
 * path s is the one camera sample s connects to, and draws the numbers of
 * pass k of its pixel's light path. */
INLINE int sample_pixel(const LaunchParams* p, int sample)
{
    return p->samplesPerIteration == 1 ? sample : sample % p->pixels;
}
INLINE uint sample_index(const LaunchParams* p, int sample)
{
    return p->samplesPerIteration == 1
               ? p->iteration
               : p->iteration * (uint)p->samplesPerIteration + (uint)(sample / p->pixels);
}

INLINE Ray load_ray(__global const float4* origins, __global const float4* directions, int slot)
{
    Ray r;
    r.origin = load_vec3(origins, slot);
    r.direction = load_vec3(directions, slot);
    r.tMax = load_w(directions, slot);
    return r;
}

INLINE void store_ray(__global float4* origins, __global float4* directions, int slot, Ray r)
{
    store_vec3w(origins, slot, r.origin, 0.0f);
    store_vec3w(directions, slot, r.direction, r.tMax);
}

/* The camera sample of connection queue entry i (connect_vertices.cl): an
 * int in its contribution's w, written and read as an int, since -1 as a
 * float's bits is a NaN, which a compiler may turn into another. */
INLINE __global int* connection_sample(__global float4* contributions, int i)
{
    return (__global int*)contributions + 4 * i + 3;
}

/* Hints for the path state of queue entries ahead (CPU devices only, see
 * core/prefetch.h). Queue entries are path slots in no order the caches
 * can follow, so a kernel's first loads of each slot miss; PoCL runs a
 * work-group's work-items one after another, so the work-item of entry i
 * hints what the entries after it will load. prefetch_ray: the ray of entry
 * i + D. prefetch_hit_state: the hit and path state of entry i + 2D, and the
 * triangle of entry i + D, whose hit the hint of D entries ago brought in.
 * Measured on the 2-core machine: vcm -12 %, pt -8 % render time. */
#define PREFETCH_DISTANCE 4

INLINE void prefetch_ray(__global const int* queueItems, __global const int* queueCounters, int capacity,
                         int queue, int i, __global const float4* origins, __global const float4* directions)
{
#ifdef HAS_PREFETCH
    int slot = queue_item(queueItems, queueCounters, capacity, queue, i + PREFETCH_DISTANCE);
    if (slot < 0)
        return;
    PREFETCH(&origins[slot], 16);
    PREFETCH(&directions[slot], 16);
#endif
}

/* The pixel of `image` that entry i + D adds to (its pathPixel came with
 * prefetch_hit_state's hint D entries ago): once slots are reused, the
 * camera paths' pixels lie anywhere in the image. */
INLINE void prefetch_pixel(const RenderBuffers* b, int capacity, int queue, int i, __global const float4* image)
{
#ifdef HAS_PREFETCH
    int slot = queue_item(b->queueItems, b->queueCounters, capacity, queue, i + PREFETCH_DISTANCE);
    if (slot >= 0)
        PREFETCH(&image[b->pathPixel[slot]], 16);
#endif
}

/* What building a surface hit on triangle `tri` loads: its corners, their
 * normals, its material index. */
INLINE void prefetch_triangle(const RenderBuffers* b, int tri)
{
    PREFETCH(&b->triVertices[3 * tri], 48);
#ifdef HAS_VERTEX_NORMALS
    PREFETCH(&b->triNormals[3 * tri], 48);
#endif
    PREFETCH(&b->triMaterials[tri], 4);
}

/* For the shade kernels, the line of entry i + 2D's path state that
 * prefetch_hit_state leaves out: the bidirectional programs' path flags.
 * Hints for the shadow-ray arrays and a light path's last vertex as well
 * made shade_light slower (docs/performance.md). */
INLINE void prefetch_shade_outputs(const RenderBuffers* b, int capacity, int queue, int i)
{
#ifdef HAS_PREFETCH
    int slot = queue_item(b->queueItems, b->queueCounters, capacity, queue, i + 2 * PREFETCH_DISTANCE);
    if (slot >= 0) {
#ifdef BIDIRECTIONAL
        PREFETCH(&b->pathFlags[slot], 4);
#endif
    }
#endif
}

INLINE void prefetch_hit_state(const RenderBuffers* b, int capacity, int queue, int i)
{
#ifdef HAS_PREFETCH
    int slot = queue_item(b->queueItems, b->queueCounters, capacity, queue, i + 2 * PREFETCH_DISTANCE);
    if (slot >= 0) {
        PREFETCH(&b->hitTriangle[slot], 4);
        PREFETCH(&b->hitBary[slot], 8);
        PREFETCH(&b->hitT[slot], 4);
        PREFETCH(&b->rayDirections[slot], 16);
        PREFETCH(&b->pathDepth[slot], 4);
        PREFETCH(&b->pathPixel[slot], 4);
        PREFETCH(&b->pathThroughput[slot], 16);
#ifdef BIDIRECTIONAL
        /* pt and el never write pathMis: hinting its untouched pages (no
         * page-table entry yet) cost pt 10-14 % of its iterations on the
         * AMD EPYC (Zen 1) machine, 27 % of shade's samples waiting there. */
        PREFETCH(&b->pathMis[slot], 16);
#endif
    }
    slot = queue_item(b->queueItems, b->queueCounters, capacity, queue, i + PREFETCH_DISTANCE);
    if (slot >= 0)
        prefetch_triangle(b, b->hitTriangle[slot]);
#endif
}

/* The path slot that work-item i of a shade kernel takes from the hit queue
 * (-1 past its end), after the hints for the entries ahead: their hit and
 * path state, and the lines that continuing a path writes. Not where the
 * kernel runs its work-items in SIMD (`simd`, a constant: core/simd.h): a
 * prefetch keeps the loop vectorizer off the work-item loop, and a gather of
 * 16 work-items' state has as many misses in flight as the hints had. */
INLINE int shade_slot(const RenderBuffers* b, int capacity, int i, bool simd)
{
    if (!simd) {
        prefetch_hit_state(b, capacity, QUEUE_HITS, i);
        prefetch_shade_outputs(b, capacity, QUEUE_HITS, i);
    }
    return queue_item(b->queueItems, b->queueCounters, capacity, QUEUE_HITS, i);
}

#endif
