/* Indices of the queue counters in the counter buffer and of the statistics
 * counters after them; shared by host and kernels. */
#ifndef WAVEVCM_QUEUE_IDS_H
#define WAVEVCM_QUEUE_IDS_H

#define QUEUE_RAYS 0          /* rays to extend */
#define COUNTER_NONFINITE 1   /* samples dropped because they were NaN or Inf */
#define COUNTER_COUNT 2

#endif
