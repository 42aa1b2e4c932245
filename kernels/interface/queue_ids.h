/* The work queues and counters, shared by host and kernels.
 *
 * Every queue is an array of path-slot indices (queue q occupies
 * items[q·capacity, (q+1)·capacity)) and a counter. The rays alternate
 * between two queues by round parity: a round consumes RAYS(p) and fills
 * RAYS(1−p), whose paths lie in the path state's other region
 * (transport/path_state.h).
 *
 * Counters sit 64 bytes apart (COUNTER_INDEX): pushes to one queue then do not
 * invalidate the cache line that the readers of another queue's size hold,
 * which on a 2-core CPU made every queue access a cache miss. */
#ifndef WAVEVCM_QUEUE_IDS_H
#define WAVEVCM_QUEUE_IDS_H

#define QUEUE_HITS 0    /* extended rays that hit a surface: to shade */
#define QUEUE_ESCAPED 1 /* extended rays that left the scene */
#define QUEUE_SHADOW 2  /* shadow rays to connect */
#define QUEUE_RAYS(parity) (3 + (parity)) /* rays to extend */
#define QUEUE_COUNT 5

/* The render kernels' work-group size, at most (the device may allow less):
 * the queue pushes' __local scratch holds a slot per item (core/queues.h). */
#define RENDER_GROUP_SIZE 64

/* The round's plan, made on the device by plan_round (generate.cl) so that
 * the host can enqueue rounds without reading counters in between. */
#define COUNTER_ISSUED 5       /* samples of the phase handed out so far */
#define COUNTER_ROUND_FIRST 6  /* this round's first new sample, counted from the phase's first */
#define COUNTER_ROUND_NEW 7    /* paths generate starts this round */
#define COUNTER_ROUND_RAYS 8   /* continuing rays in the ray queue: generate appends after them */
#define COUNTER_ROUND_NEW_SLOT 9 /* where in the round's region its new paths start: after the
                                  * places of the last round's hits (path_state.h) */
#define COUNTER_CONNECTIONS 10 /* vertex connections queued this round (connect_vertices.cl); more
                                * than the queue holds would be a bug, which the host reports */
#define COUNTER_PHASE_STATE 11 /* counters below this one start every phase at zero */

#define COUNTER_RAYS_TRACED 11    /* extended and shadow rays this iteration (a ulong: two ints) */
#define COUNTER_LIGHT_VERTICES 12 /* light vertices stored (and wanted: may exceed the buffer) */
#define COUNTER_NONFINITE 13      /* samples dropped because they were NaN or Inf (all iterations) */
#define COUNTER_COUNT 14

#define COUNTER_STRIDE 16 /* ints: one 64-byte cache line per counter */
#define COUNTER_INDEX(c) ((c) * COUNTER_STRIDE)

#endif
