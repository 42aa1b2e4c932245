/* Pushing to and reading from the work queues (queue_ids.h). Kernels that
 * consume a queue are launched over the wavefront's capacity and return past
 * the queue's current size, so the host never reads a counter to size a
 * launch. A push is one global atomic; on CPU devices that is cheaper than
 * work-group aggregation with barriers (see NOTES on PoCL). */
#ifndef WAVEVCM_QUEUES_H
#define WAVEVCM_QUEUES_H

#include "queue_ids.h"

inline void queue_push(__global int* items, __global int* counters, int capacity, int queue, int slot)
{
    items[queue * capacity + atomic_inc(&counters[queue])] = slot;
}

/* The slot of the i-th entry of `queue`, or -1 past its end. */
inline int queue_item(__global const int* items, __global const int* counters, int capacity, int queue, int i)
{
    return i < counters[queue] ? items[queue * capacity + i] : -1;
}

#endif
