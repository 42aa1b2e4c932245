/* Warping uniform numbers to directions and points, with their densities. */
#ifndef WAVEVCM_SAMPLING_H
#define WAVEVCM_SAMPLING_H

#include "core/vec3.h"
#include "interface/inline.h"

#define PI_F 3.14159265358979323846f
#define INV_PI_F 0.31830988618379067154f

/* An orthonormal basis around unit n (Duff et al., "Building an Orthonormal
 * Basis, Revisited", JCGT 2017): no division by a small number anywhere. */
typedef struct Frame {
    vec3 s, t, n;
} Frame;

INLINE Frame frame_from_normal(vec3 n)
{
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    Frame f;
    f.s = v3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = v3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

INLINE vec3 to_local(const Frame* f, vec3 v) { return v3(v3_dot(v, f->s), v3_dot(v, f->t), v3_dot(v, f->n)); }
INLINE vec3 to_world(const Frame* f, vec3 v)
{
    return v3(v.x * f->s.x + v.y * f->t.x + v.z * f->n.x, v.x * f->s.y + v.y * f->t.y + v.z * f->n.y,
              v.x * f->s.z + v.y * f->t.z + v.z * f->n.z);
}

/* sin(πx) and cos(πx) for |x| <= 1/4: minimax polynomials in φ = πx on
 * [-π/4, π/4] (Cephes's sinf and cosf coefficients), within about an ulp;
 * the library's sinpi and cospi reduce any argument and cost several times
 * as many instructions. */
INLINE void sin_cos_pi_quarter(float x, float* s, float* c)
{
    float p = PI_F * x, z = p * p;
    *s = p + p * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
    *c = 1.0f - 0.5f * z + z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
}

/* sin(πx) and cos(πx) for x of moderate size (the sampling angles, in
 * units of π): x = q/2 + r with q the nearest integer to 2x, so |r| <= 1/4
 * (r is exact), then q quarter turns: (s, c) -> (c, -s) per turn. */
INLINE void sin_cos_pi(float x, float* s, float* c)
{
    float q = rint(2.0f * x);
    float sr, cr;
    sin_cos_pi_quarter(x - 0.5f * q, &sr, &cr);
    int k = (int)q & 3;
    float sq = (k & 1) ? cr : sr, cq = (k & 1) ? sr : cr;
    *s = (k & 2) ? -sq : sq;
    *c = ((k + 1) & 2) ? -cq : cq;
}

/* Concentric square-to-disk map (Shirley & Chiu 1997): low distortion. The
 * angle is (π/4)(oy/ox) on the wedges where |x| is larger, π/2 - (π/4)(ox/oy)
 * on the others, whose sine and cosine are the cosine and sine of
 * (π/4)(ox/oy): one quarter-range pair either way. */
INLINE vec2 sample_disk(float u1, float u2)
{
    float ox = 2.0f * u1 - 1.0f, oy = 2.0f * u2 - 1.0f;
    bool xMajor = fabs(ox) > fabs(oy);
    float r = xMajor ? ox : oy;
    float t = ox == 0.0f && oy == 0.0f ? 0.0f : 0.25f * (xMajor ? oy / ox : ox / oy);
    float s, c;
    sin_cos_pi_quarter(t, &s, &c);
    return xMajor ? v2(r * c, r * s) : v2(r * s, r * c);
}

/* Cosine-weighted hemisphere around +z; pdf = cos θ / π. */
INLINE vec3 sample_cosine_hemisphere(float u1, float u2)
{
    vec2 d = sample_disk(u1, u2);
    return v3(d.x, d.y, sqrt(fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y)));
}

/* Uniform sphere; pdf = 1 / 4π. */
INLINE vec3 sample_uniform_sphere(float u1, float u2)
{
    float z = 1.0f - 2.0f * u1;
    float r = sqrt(fmax(0.0f, 1.0f - z * z));
    float s, c;
    sin_cos_pi(2.0f * u2, &s, &c); /* φ = 2π u2 */
    return v3(r * c, r * s, z);
}

/* Uniform cone of directions around +z with cos θ ≥ cosMax; pdf = 1 / (2π(1 − cosMax)). */
INLINE vec3 sample_uniform_cone(float u1, float u2, float cosMax)
{
    float z = 1.0f - u1 * (1.0f - cosMax);
    float r = sqrt(fmax(0.0f, 1.0f - z * z));
    float s, c;
    sin_cos_pi(2.0f * u2, &s, &c);
    return v3(r * c, r * s, z);
}

/* The bin of a CDF with `count` bins (count + 1 entries, non-decreasing,
 * cdf[0] = 0) that holds u: the largest i < count with cdf[i] <= u, by a
 * binary search over the bits of i from bit steps − 1 down (count <= 2^steps).
 * Called with a constant `steps`, it is a fixed sequence of steps, no loop:
 * a data-dependent loop would keep PoCL from vectorizing the kernel
 * (core/simd.h). */
INLINE int cdf_bin(__global const float* cdf, int count, float u, int steps)
{
    int lo = 0;
#pragma unroll
    for (int bit = steps - 1; bit >= 0; --bit) {
        int mid = lo + (1 << bit);
        bool below = cdf[min(mid, count - 1)] <= u;
        lo = mid < count && below ? mid : lo;
    }
    return lo;
}

/* Uniform point on a triangle as barycentrics (b1, b2) (Heitz's "low
 * distortion" map would be an option; this square-root map is standard). */
INLINE vec2 sample_triangle(float u1, float u2)
{
    float su = sqrt(u1);
    return v2(su * (1.0f - u2), su * u2);
}

#endif
