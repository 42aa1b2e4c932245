/* Warping uniform numbers to directions and points, with their densities. */
#ifndef WAVEVCM_SAMPLING_H
#define WAVEVCM_SAMPLING_H

#include "interface/inline.h"

#define PI_F 3.14159265358979323846f
#define INV_PI_F 0.31830988618379067154f

/* An orthonormal basis around unit n (Duff et al., "Building an Orthonormal
 * Basis, Revisited", JCGT 2017): no division by a small number anywhere. */
typedef struct Frame {
    float3 s, t, n;
} Frame;

INLINE Frame frame_from_normal(float3 n)
{
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    Frame f;
    f.s = (float3)(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = (float3)(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

INLINE float3 to_local(const Frame* f, float3 v) { return (float3)(dot(v, f->s), dot(v, f->t), dot(v, f->n)); }
INLINE float3 to_world(const Frame* f, float3 v) { return v.x * f->s + v.y * f->t + v.z * f->n; }

/* Concentric square-to-disk map (Shirley & Chiu 1997): low distortion. */
INLINE float2 sample_disk(float2 u)
{
    float2 o = 2.0f * u - 1.0f;
    if (o.x == 0.0f && o.y == 0.0f)
        return (float2)(0.0f);
    float r, theta; /* the angle in units of π: sinpi/cospi need no argument reduction */
    if (fabs(o.x) > fabs(o.y)) {
        r = o.x;
        theta = 0.25f * (o.y / o.x);
    } else {
        r = o.y;
        theta = 0.5f - 0.25f * (o.x / o.y);
    }
    return r * (float2)(cospi(theta), sinpi(theta));
}

/* Cosine-weighted hemisphere around +z; pdf = cos θ / π. */
INLINE float3 sample_cosine_hemisphere(float2 u)
{
    float2 d = sample_disk(u);
    return (float3)(d.x, d.y, sqrt(fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y)));
}

/* Uniform sphere; pdf = 1 / 4π. */
INLINE float3 sample_uniform_sphere(float2 u)
{
    float z = 1.0f - 2.0f * u.x;
    float r = sqrt(fmax(0.0f, 1.0f - z * z));
    float phi = 2.0f * u.y; /* in units of π */
    return (float3)(r * cospi(phi), r * sinpi(phi), z);
}

/* Uniform cone of directions around +z with cos θ ≥ cosMax; pdf = 1 / (2π(1 − cosMax)). */
INLINE float3 sample_uniform_cone(float2 u, float cosMax)
{
    float z = 1.0f - u.x * (1.0f - cosMax);
    float r = sqrt(fmax(0.0f, 1.0f - z * z));
    float phi = 2.0f * u.y; /* in units of π */
    return (float3)(r * cospi(phi), r * sinpi(phi), z);
}

/* Uniform point on a triangle as barycentrics (b1, b2) (Heitz's "low
 * distortion" map would be an option; this square-root map is standard). */
INLINE float2 sample_triangle(float2 u)
{
    float su = sqrt(u.x);
    return (float2)(su * (1.0f - u.y), su * u.y);
}

INLINE float luminance(float3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
INLINE float max_component(float3 c) { return fmax(c.x, fmax(c.y, c.z)); }

#endif
