/* Three-component vectors as plain structs of scalars, for all shading code.
 *
 * Why not float3: PoCL runs a work-group as a loop over its work-items and
 * leaves SIMD to LLVM's loop vectorizer, which widens scalar instructions
 * only: one float3/float4 operation, load or store left in a kernel after
 * optimisation ("instruction return type cannot be vectorized") keeps the
 * whole kernel at one work-item per instruction. Written with scalars, a
 * kernel runs 8 work-items per AVX2 instruction; on a GPU, where every
 * work-item is a scalar thread anyway, the two compile alike.
 * The BVH traversal keeps OpenCL vector types: there the SIMD runs across a
 * node's children and a leaf's triangles, within one work-item
 * (geometry/bvh_traversal.h).
 *
 * Loads and stores of the float4 arrays the kernels share with the host go
 * through load_vec3/store_vec3w, component by component, for the same
 * reason. */
#ifndef WAVEVCM_VEC3_H
#define WAVEVCM_VEC3_H

#include "interface/inline.h"

/* abiPad: on x86-64 (PoCL) a struct of at most 16 bytes is passed and
 * returned in SSE registers, x and y packed as one <2 x float>; those
 * packings stay in the kernel after inlining wherever such a value meets a
 * branch, and they are vector instructions too. Over 16 bytes, the ABI
 * passes it in memory, which inlining turns back into three scalars. The
 * padding is never read, so no register or memory holds it. */
typedef struct vec3 {
    float x, y, z;
    float abiPad[2];
} vec3;

typedef struct vec2 {
    float x, y;
    float abiPad[3]; /* as vec3's */
} vec2;

INLINE vec3 v3(float x, float y, float z)
{
    vec3 v = {x, y, z};
    return v;
}
INLINE vec3 v3s(float s) { return v3(s, s, s); }
INLINE vec2 v2(float x, float y)
{
    vec2 v = {x, y};
    return v;
}

INLINE vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
INLINE vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
INLINE vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
INLINE vec3 v3_scale(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
INLINE vec3 v3_div(vec3 a, float s) { return v3(a.x / s, a.y / s, a.z / s); }
INLINE vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
INLINE vec3 v3_abs(vec3 a) { return v3(fabs(a.x), fabs(a.y), fabs(a.z)); }
/* a + s·b */
INLINE vec3 v3_add_scaled(vec3 a, vec3 b, float s) { return v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z); }

INLINE float v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
INLINE vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
INLINE float v3_length(vec3 a) { return sqrt(v3_dot(a, a)); }
INLINE vec3 v3_normalize(vec3 a) { return v3_div(a, v3_length(a)); }

INLINE float max_component(vec3 c) { return fmax(c.x, fmax(c.y, c.z)); }
INLINE float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
INLINE bool v3_is_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
INLINE bool v3_is_zero(vec3 a) { return a.x == 0.0f && a.y == 0.0f && a.z == 0.0f; }

/* Elements of the float4 arrays shared with the host, a component at a time. */
INLINE vec3 load_vec3(__global const float4* a, int i)
{
    __global const float* f = (__global const float*)a + 4 * i;
    return v3(f[0], f[1], f[2]);
}
INLINE float load_w(__global const float4* a, int i) { return ((__global const float*)a)[4 * i + 3]; }
INLINE void store_vec3w(__global float4* a, int i, vec3 v, float w)
{
    __global float* f = (__global float*)a + 4 * i;
    f[0] = v.x;
    f[1] = v.y;
    f[2] = v.z;
    f[3] = w;
}
/* pixels[pixel].xyz += v */
INLINE void add_vec3(__global float4* a, int i, vec3 v)
{
    __global float* f = (__global float*)a + 4 * i;
    f[0] += v.x;
    f[1] += v.y;
    f[2] += v.z;
}
INLINE vec2 load_vec2(__global const float2* a, int i)
{
    __global const float* f = (__global const float*)a + 2 * i;
    return v2(f[0], f[1]);
}
INLINE void store_vec2(__global float2* a, int i, vec2 v)
{
    __global float* f = (__global float*)a + 2 * i;
    f[0] = v.x;
    f[1] = v.y;
}
/* The float[3] members of the shared structs (shared_types.h). */
INLINE vec3 load3(__global const float* p) { return v3(p[0], p[1], p[2]); }
INLINE vec3 load3c(__constant const float* p) { return v3(p[0], p[1], p[2]); }
INLINE void store3(float* p, vec3 v)
{
    p[0] = v.x;
    p[1] = v.y;
    p[2] = v.z;
}

/* For the code that keeps OpenCL vectors (traversal, the hash grid, tests). */
INLINE float3 to_float3(vec3 v) { return (float3)(v.x, v.y, v.z); }
INLINE vec3 from_float3(float3 v) { return v3(v.x, v.y, v.z); }

#endif
