/* The NaN policy, written once: a throughput or a contribution that is NaN
 * or Inf is rejected where it is produced (the path ends, the contribution is
 * dropped) and counted in COUNTER_NONFINITE, which the renderer reports as
 * nan_count; it never reaches an image. accumulate applies the same rule to
 * each pixel's sum as the last guard (finite contributions can still
 * overflow when added).
 *
 * A kernel counts its rejections in a private int and adds them to the
 * counter once, at its end (report_nonfinite): an atomic where the
 * contribution is made would keep PoCL from vectorizing the kernel. */
#ifndef WAVEVCM_NAN_POLICY_H
#define WAVEVCM_NAN_POLICY_H

#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/queue_ids.h"

/* True if every component of v is finite; counts v in *rejected otherwise. */
INLINE bool accept_finite(vec3 v, int* rejected)
{
    bool finite = v3_is_finite(v);
    *rejected += finite ? 0 : 1;
    return finite;
}

/* pixels[pixel] += L, if L is nonzero and accepted. */
INLINE void add_radiance(__global float4* pixels, int pixel, vec3 L, int* rejected)
{
    if (!v3_is_zero(L) && accept_finite(L, rejected))
        add_vec3(pixels, pixel, L);
}

/* The work-item's rejections, into COUNTER_NONFINITE. */
INLINE void report_nonfinite(__global int* queueCounters, int rejected)
{
    if (rejected > 0)
        atomic_add(&queueCounters[COUNTER_INDEX(COUNTER_NONFINITE)], rejected);
}

#endif
