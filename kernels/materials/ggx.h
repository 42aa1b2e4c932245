/* The GGX (Trowbridge-Reitz) microfacet distribution in the local frame
 * (normal +z): distribution, height-correlated masking-shadowing, and
 * sampling of visible normals (Heitz, "Sampling the GGX Distribution of
 * Visible Normals", JCGT 2018). */
#ifndef WAVEVCM_GGX_H
#define WAVEVCM_GGX_H

#include "core/sampling.h"
#include "interface/inline.h"

INLINE float ggx_d(float3 h, float alpha)
{
    if (h.z <= 0.0f)
        return 0.0f;
    float a2 = alpha * alpha;
    float t = h.z * h.z * (a2 - 1.0f) + 1.0f;
    return a2 / (PI_F * t * t);
}

/* Smith Λ(w) = (−1 + sqrt(1 + α² tan²θ)) / 2. */
INLINE float ggx_lambda(float3 w, float alpha)
{
    float cos2 = w.z * w.z;
    if (cos2 <= 0.0f)
        return INFINITY;
    float tan2 = fmax(0.0f, 1.0f - cos2) / cos2;
    return 0.5f * (-1.0f + sqrt(1.0f + alpha * alpha * tan2));
}

INLINE float ggx_g1(float3 w, float alpha) { return 1.0f / (1.0f + ggx_lambda(w, alpha)); }

INLINE float ggx_g(float3 wo, float3 wi, float alpha)
{
    return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

/* Density of visible normals seen from wo (wo.z > 0):
 * D_wo(h) = G1(wo) · max(0, wo·h) · D(h) / wo.z. */
INLINE float ggx_visible_pdf(float3 wo, float3 h, float alpha)
{
    return ggx_g1(wo, alpha) * fmax(0.0f, dot(wo, h)) * ggx_d(h, alpha) / wo.z;
}

INLINE float3 ggx_sample_visible(float3 wo, float alpha, float2 u)
{
    /* Stretch to the hemisphere configuration, sample a projected disk,
     * unstretch. */
    float3 vh = normalize((float3)(alpha * wo.x, alpha * wo.y, wo.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    float3 t1 = lensq > 0.0f ? (float3)(-vh.y, vh.x, 0.0f) * rsqrt(lensq) : (float3)(1.0f, 0.0f, 0.0f);
    float3 t2 = cross(vh, t1);
    float r = sqrt(u.x), phi = 2.0f * u.y; /* in units of π */
    float p1 = r * cospi(phi), p2 = r * sinpi(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * p2;
    float3 nh = p1 * t1 + p2 * t2 + sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return normalize((float3)(alpha * nh.x, alpha * nh.y, fmax(1e-6f, nh.z)));
}

#endif
