/* Pushing to and reading from the work queues (queue_ids.h). Kernels that
 * consume a queue are launched over an upper bound of its size that the host
 * knows and skip items past its actual size. */
#ifndef WAVEVCM_QUEUES_H
#define WAVEVCM_QUEUES_H

#include "interface/inline.h"
#include "interface/queue_ids.h"

/* No counter (a lane of group_allocate4 that nobody wants). */
#define NO_COUNTER (-1)

/* Four ints, one per lane of group_allocate4: a struct of scalars rather than
 * an int4, which would keep PoCL from vectorizing the kernel (core/vec3.h). */
typedef struct Lanes {
    int x, y, z, w;
} Lanes;

INLINE Lanes lanes(int x, int y, int z, int w)
{
    Lanes l = {x, y, z, w};
    return l;
}

/* __local ints a kernel declares for group_allocate4. */
#define QUEUE_SCRATCH_INTS (8 + RENDER_GROUP_SIZE)
#if RENDER_GROUP_SIZE > 256
#error "group_allocate4 packs an item's indices into bytes: at most 256 items per group"
#endif

/* CPU devices (PoCL compiles for the host's x86 target) run a work-group's
 * items one after another in one thread; there one item numbers them all in
 * a loop. An atomic increment per item is a locked instruction, which waits
 * until the item's earlier stores have reached the cache: 3 % of extend's
 * and shade's time. GPUs keep the local atomics. */
#if defined(__x86_64__) || defined(__i386__)
#define SERIAL_GROUP_NUMBERING 1
#endif

/* group_allocate4's indices by a global atomic per item. */
INLINE Lanes item_allocate4(__global int* counters, Lanes counter, Lanes wants)
{
    return lanes(wants.x ? atomic_inc(&counters[COUNTER_INDEX(counter.x)]) : -1,
                 wants.y ? atomic_inc(&counters[COUNTER_INDEX(counter.y)]) : -1,
                 wants.z ? atomic_inc(&counters[COUNTER_INDEX(counter.z)]) : -1,
                 wants.w ? atomic_inc(&counters[COUNTER_INDEX(counter.w)]) : -1);
}

/* Whether a kernel pushes by a global atomic per item and no barrier, not
 * through the group: where the host set PUSH_PER_ITEM (a CPU device of one
 * compute unit, such as each of the two pipelines' sub-devices on a 2-core
 * machine, or rusticl's llvmpipe, whose barriers are coroutines) and the
 * kernel runs its work-items one at a time (`simd` 0, a
 * constant: core/simd.h; an atomic per item would keep the loop vectorizer
 * off a SIMD kernel's work-item loop). There the atomic costs less than the
 * group's barriers and the values PoCL spills across them (2-core AMD EPYC,
 * two pipelines: `pt` iterations +3-5 %, `ppm` +3-12 %, `shade_light` +8 %;
 * Intel AVX-512, a scalar shade_light beside a SIMD shade_bidirectional:
 * 7.1-7.4 against 6.1-6.2 M items/s); on the whole device, where both
 * threads push to the same counters, it made `pt` 10-20 % slower. */
INLINE bool pushes_per_item(bool simd)
{
#ifdef PUSH_PER_ITEM
    return !simd;
#else
    return false;
#endif
}

/* For each of up to four counters (lanes x, y, z, w of `counter`), the next
 * index of that counter for every work-item that `wants` one in that lane,
 * -1 for the others. Aggregated per work-group (unless pushes_per_item(simd),
 * `simd` saying whether the calling kernel runs in SIMD): one global atomic
 * per counter per group reserves room for all its items (a global atomic per
 * item cost ~95 ns on a 2-core CPU, the counter's cache line bouncing between
 * cores, more than shading). All of a kernel's pushes go through one call: it
 * has two or three barriers, and on PoCL each barrier splits the work-group
 * loop and spills the live values. Every work-item of the group must call it,
 * once per kernel; `scratch` is __local int[QUEUE_SCRATCH_INTS]: the group's
 * counts (0-3), its places in the queues (4-7), and on CPUs each item's lanes
 * (8 + local id; bit k: it wants lane k, then its four indices, a byte each). */
INLINE Lanes group_allocate4(__global int* counters, Lanes counter, Lanes wants, __local int* scratch, bool simd)
{
    if (pushes_per_item(simd))
        return item_allocate4(counters, counter, wants);
    Lanes index;
#ifdef SERIAL_GROUP_NUMBERING
    int item = get_local_id(0);
    scratch[8 + item] = (wants.x ? 1 : 0) | (wants.y ? 2 : 0) | (wants.z ? 4 : 0) | (wants.w ? 8 : 0);
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item == 0) {
        int nx = 0, ny = 0, nz = 0, nw = 0;
        for (int i = 0; i < (int)get_local_size(0); ++i) {
            int bits = scratch[8 + i];
            scratch[8 + i] = nx | ny << 8 | nz << 16 | nw << 24;
            nx += bits & 1;
            ny += (bits >> 1) & 1;
            nz += (bits >> 2) & 1;
            nw += bits >> 3;
        }
        scratch[0] = nx;
        scratch[1] = ny;
        scratch[2] = nz;
        scratch[3] = nw;
    }
#else
    if (get_local_id(0) == 0)
        scratch[0] = scratch[1] = scratch[2] = scratch[3] = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    index.x = wants.x ? atomic_inc(&scratch[0]) : 0;
    index.y = wants.y ? atomic_inc(&scratch[1]) : 0;
    index.z = wants.z ? atomic_inc(&scratch[2]) : 0;
    index.w = wants.w ? atomic_inc(&scratch[3]) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
#endif
    if (get_local_id(0) == 0) {
        scratch[4] = scratch[0] > 0 ? atomic_add(&counters[COUNTER_INDEX(counter.x)], scratch[0]) : 0;
        scratch[5] = scratch[1] > 0 ? atomic_add(&counters[COUNTER_INDEX(counter.y)], scratch[1]) : 0;
        scratch[6] = scratch[2] > 0 ? atomic_add(&counters[COUNTER_INDEX(counter.z)], scratch[2]) : 0;
        scratch[7] = scratch[3] > 0 ? atomic_add(&counters[COUNTER_INDEX(counter.w)], scratch[3]) : 0;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
#ifdef SERIAL_GROUP_NUMBERING
    int packed = scratch[8 + item];
    index.x = packed & 0xff;
    index.y = (packed >> 8) & 0xff;
    index.z = (packed >> 16) & 0xff;
    index.w = (packed >> 24) & 0xff;
#endif
    return lanes(wants.x ? scratch[4] + index.x : -1, wants.y ? scratch[5] + index.y : -1,
                 wants.z ? scratch[6] + index.z : -1, wants.w ? scratch[7] + index.w : -1);
}

/* Appends the slot of each lane of `slots` to the lane's queue of `queues`
 * where its lane of `push` is set (group_allocate4's rules apply; unused
 * lanes: NO_COUNTER, push 0). */
INLINE void queue_push4(__global int* items, __global int* counters, int capacity, Lanes queues, Lanes push,
                        Lanes slots, __local int* scratch, bool simd)
{
    Lanes at = group_allocate4(counters, queues, push, scratch, simd);
    if (at.x >= 0)
        items[queues.x * capacity + at.x] = slots.x;
    if (at.y >= 0)
        items[queues.y * capacity + at.y] = slots.y;
    if (at.z >= 0)
        items[queues.z * capacity + at.z] = slots.z;
    if (at.w >= 0)
        items[queues.w * capacity + at.w] = slots.w;
}

/* The first of `n` consecutive entries of `counter` for this work-item (the
 * group's items' blocks one after another), n ≥ 0. Aggregated per group as
 * group_allocate4 (its rules apply), without its limit of 255 per group. */
INLINE int group_allocate_n(__global int* counters, int counter, int n, __local int* scratch, bool simd)
{
    if (pushes_per_item(simd))
        return n > 0 ? atomic_add(&counters[COUNTER_INDEX(counter)], n) : 0;
    int item = get_local_id(0);
#ifdef SERIAL_GROUP_NUMBERING
    scratch[8 + item] = n;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item == 0) {
        int total = 0;
        for (int i = 0; i < (int)get_local_size(0); ++i) {
            int count = scratch[8 + i];
            scratch[8 + i] = total;
            total += count;
        }
        scratch[4] = total > 0 ? atomic_add(&counters[COUNTER_INDEX(counter)], total) : 0;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    return scratch[4] + scratch[8 + item];
#else
    if (item == 0)
        scratch[0] = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    int offset = n > 0 ? atomic_add(&scratch[0], n) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item == 0)
        scratch[4] = scratch[0] > 0 ? atomic_add(&counters[COUNTER_INDEX(counter)], scratch[0]) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    return scratch[4] + offset;
#endif
}

/* The slot of the i-th entry of `queue`, or -1 past its end. */
INLINE int queue_item(__global const int* items, __global const int* counters, int capacity, int queue, int i)
{
    return i < counters[COUNTER_INDEX(queue)] ? items[queue * capacity + i] : -1;
}

#endif
