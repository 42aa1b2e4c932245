/* Pushing to and reading from the work queues (queue_ids.h). Kernels that
 * consume a queue are launched over an upper bound of its size that the host
 * knows and skip items past its actual size. */
#ifndef WAVEVCM_QUEUES_H
#define WAVEVCM_QUEUES_H

#include "queue_ids.h"

/* Appends `slot` to `queue` if `push`. Aggregated per work-group: one
 * global atomic per group reserves room for all its items. A global atomic
 * per item cost ~95 ns on a 2-core CPU (the counter's cache line bounces
 * between the cores), more than the shading itself. Contains barriers: every
 * work-item of the group must call it, pushing or not. `scratch` is __local
 * int[2], free for reuse after the call. */
inline void queue_push(__global int* items, __global int* counters, int capacity, int queue, bool push, int slot,
                       __local int* scratch)
{
    if (get_local_id(0) == 0)
        scratch[0] = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    int index = push ? atomic_inc(&scratch[0]) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0)
        scratch[1] = scratch[0] > 0 ? atomic_add(&counters[COUNTER_INDEX(queue)], scratch[0]) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (push)
        items[queue * capacity + scratch[1] + index] = slot;
    barrier(CLK_LOCAL_MEM_FENCE);
}

/* The slot of the i-th entry of `queue`, or -1 past its end. */
inline int queue_item(__global const int* items, __global const int* counters, int capacity, int queue, int i)
{
    return i < counters[COUNTER_INDEX(queue)] ? items[queue * capacity + i] : -1;
}

#endif
