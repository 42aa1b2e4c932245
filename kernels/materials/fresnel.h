/* Fresnel reflectance. */
#ifndef WAVEVCM_FRESNEL_H
#define WAVEVCM_FRESNEL_H

#include "core/vec3.h"
#include "interface/inline.h"

/* Exact unpolarised reflectance of a smooth dielectric interface for light
 * arriving at cos θ_i (> 0) from the side where the relative index of
 * refraction η = η_t / η_i. Total internal reflection gives 1. */
INLINE float fresnel_dielectric(float cosI, float eta)
{
    cosI = clamp(cosI, 0.0f, 1.0f);
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f)
        return 1.0f;
    float cosT = sqrt(1.0f - sin2T);
    float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5f * (rs * rs + rp * rp);
}

/* glTF's metal Fresnel: Schlick's approximation with F0 = the base colour. */
INLINE vec3 fresnel_schlick(vec3 f0, float cosI)
{
    float m = clamp(1.0f - cosI, 0.0f, 1.0f);
    float m2 = m * m;
    float m5 = m2 * m2 * m;
    return v3(f0.x + (1.0f - f0.x) * m5, f0.y + (1.0f - f0.y) * m5, f0.z + (1.0f - f0.z) * m5);
}

/* Refract w (pointing away from the surface, on the side of n) through the
 * interface with normal n and relative index η = η_t / η_i. Returns false on
 * total internal reflection. */
INLINE bool refract_direction(vec3 w, vec3 n, float eta, vec3* out)
{
    float cosI = v3_dot(n, w);
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    float cosT = sqrt(fmax(0.0f, 1.0f - sin2T));
    *out = v3_add(v3_div(v3_neg(w), eta), v3_scale(n, cosI / eta - cosT));
    return sin2T < 1.0f;
}

#endif
