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

/* Concentric square-to-disk map (Shirley & Chiu 1997): low distortion. */
INLINE vec2 sample_disk(float u1, float u2)
{
    float ox = 2.0f * u1 - 1.0f, oy = 2.0f * u2 - 1.0f;
    bool xMajor = fabs(ox) > fabs(oy);
    float r = xMajor ? ox : oy;
    /* the angle in units of π: sinpi/cospi need no argument reduction */
    float theta = xMajor ? 0.25f * (oy / ox) : 0.5f - 0.25f * (ox / oy);
    if (ox == 0.0f && oy == 0.0f)
        r = theta = 0.0f;
    return v2(r * cospi(theta), r * sinpi(theta));
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
    float phi = 2.0f * u2; /* in units of π */
    return v3(r * cospi(phi), r * sinpi(phi), z);
}

/* Uniform cone of directions around +z with cos θ ≥ cosMax; pdf = 1 / (2π(1 − cosMax)). */
INLINE vec3 sample_uniform_cone(float u1, float u2, float cosMax)
{
    float z = 1.0f - u1 * (1.0f - cosMax);
    float r = sqrt(fmax(0.0f, 1.0f - z * z));
    float phi = 2.0f * u2; /* in units of π */
    return v3(r * cospi(phi), r * sinpi(phi), z);
}

/* Uniform point on a triangle as barycentrics (b1, b2) (Heitz's "low
 * distortion" map would be an option; this square-root map is standard). */
INLINE vec2 sample_triangle(float u1, float u2)
{
    float su = sqrt(u1);
    return v2(su * (1.0f - u2), su * u2);
}

#endif
