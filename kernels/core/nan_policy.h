/* The NaN policy, written once: a throughput or a contribution that is NaN
 * or Inf is rejected where it is produced (the path ends, the contribution is
 * dropped) and counted in COUNTER_NONFINITE, which the renderer reports as
 * nan_count; it never reaches an image. accumulate applies the same rule to
 * each pixel's sum as the last guard (finite contributions can still
 * overflow when added). */
#ifndef WAVEVCM_NAN_POLICY_H
#define WAVEVCM_NAN_POLICY_H

#include "interface/inline.h"
#include "interface/queue_ids.h"

/* True if every component of v is finite; counts v otherwise. */
INLINE bool accept_finite(float3 v, __global int* queueCounters)
{
    if (all(isfinite(v)))
        return true;
    atomic_inc(&queueCounters[COUNTER_INDEX(COUNTER_NONFINITE)]);
    return false;
}

/* pixels[pixel] += L, if L is nonzero and accepted. */
INLINE void add_radiance(__global float4* pixels, int pixel, float3 L, __global int* queueCounters)
{
    if (any(L != 0.0f) && accept_finite(L, queueCounters))
        pixels[pixel] += (float4)(L, 0.0f);
}

#endif
