/* Work queues: an array of path-slot indices per kind of work plus one atomic
 * counter each, all counters in one small buffer. Kernels that consume a
 * queue are launched over the wavefront's capacity and return early past the
 * queue's size, so the host never reads a counter to size a launch. */
#ifndef WAVEVCM_QUEUES_H
#define WAVEVCM_QUEUES_H

#include "queue_ids.h"

inline void queue_push(__global int* items, __global int* counters, int queue, int slot)
{
    items[atomic_inc(&counters[queue])] = slot;
}

#endif
