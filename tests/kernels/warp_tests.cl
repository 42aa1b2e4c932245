/* Test-only kernels for core/sampling.h's warps: sin_cos_pi at host-chosen
 * arguments, and sample_disk at host-chosen (u1, u2). */
#include "core/sampling.h"

__kernel void sin_cos_pi_values(__global const float* x, int n, __global float2* out)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    float s, c;
    sin_cos_pi(x[i], &s, &c);
    out[i] = (float2)(s, c);
}

__kernel void disk_points(__global const float2* u, int n, __global float2* out)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    vec2 d = sample_disk(u[i].x, u[i].y);
    out[i] = (float2)(d.x, d.y);
}
