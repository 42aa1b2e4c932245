/* Pushing to and reading from the work queues (queue_ids.h). Kernels that
 * consume a queue are launched over an upper bound of its size that the host
 * knows and skip items past its actual size. */
#ifndef WAVEVCM_QUEUES_H
#define WAVEVCM_QUEUES_H

#include "queue_ids.h"

/* Takes the next index of counter `counter` for every work-item that
 * `wants` one (-1 for the others). Aggregated per work-group: one global
 * atomic per group reserves room for all its items. A global atomic per item
 * cost ~95 ns on a 2-core CPU (the counter's cache line bounces between the
 * cores), more than the shading itself. Contains barriers: every work-item
 * of the group must call it. `scratch` is __local int[2], free after the call. */
/* Helpers with barriers are always inlined: with a static helper that LLVM
 * decides to inline late, PoCL 3.1 (LLVM 15) crashes building the
 * work-group function. */
#define BARRIER_HELPER static inline __attribute__((always_inline))

BARRIER_HELPER int group_allocate(__global int* counters, int counter, bool wants, __local int* scratch)
{
    if (get_local_id(0) == 0)
        scratch[0] = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    int index = wants ? atomic_inc(&scratch[0]) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0)
        scratch[1] = scratch[0] > 0 ? atomic_add(&counters[COUNTER_INDEX(counter)], scratch[0]) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    int result = wants ? scratch[1] + index : -1;
    barrier(CLK_LOCAL_MEM_FENCE);
    return result;
}

/* Appends `slot` to `queue` if `push` (group_allocate's rules apply). */
BARRIER_HELPER void queue_push(__global int* items, __global int* counters, int capacity, int queue, bool push, int slot,
                       __local int* scratch)
{
    int index = group_allocate(counters, queue, push, scratch);
    if (push)
        items[queue * capacity + index] = slot;
}

/* The slot of the i-th entry of `queue`, or -1 past its end. */
static inline int queue_item(__global const int* items, __global const int* counters, int capacity, int queue, int i)
{
    return i < counters[COUNTER_INDEX(queue)] ? items[queue * capacity + i] : -1;
}

#endif
