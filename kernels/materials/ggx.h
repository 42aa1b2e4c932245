/* The GGX (Trowbridge-Reitz) microfacet distribution in the local frame
 * (normal +z): distribution, height-correlated masking-shadowing, and
 * sampling of visible normals (Heitz, "Sampling the GGX Distribution of
 * Visible Normals", JCGT 2018); isotropic, and (the _aniso functions, for
 * KHR_materials_anisotropy) of roughness αx along x and αy along y (Heitz,
 * "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
 * JCGT 2014, §5.4: the isotropic one stretched by (αx, αy)). */
#ifndef WAVEVCM_GGX_H
#define WAVEVCM_GGX_H

#include "core/sampling.h"
#include "core/vec3.h"
#include "interface/inline.h"

INLINE float ggx_d(vec3 h, float alpha)
{
    float a2 = alpha * alpha;
    float t = h.z * h.z * (a2 - 1.0f) + 1.0f;
    return h.z > 0.0f ? a2 / (PI_F * t * t) : 0.0f;
}

/* Smith Λ(w) = (−1 + sqrt(1 + α² tan²θ)) / 2. */
INLINE float ggx_lambda(vec3 w, float alpha)
{
    float cos2 = w.z * w.z;
    float tan2 = fmax(0.0f, 1.0f - cos2) / cos2;
    return cos2 > 0.0f ? 0.5f * (-1.0f + sqrt(1.0f + alpha * alpha * tan2)) : INFINITY;
}

INLINE float ggx_g1(vec3 w, float alpha) { return 1.0f / (1.0f + ggx_lambda(w, alpha)); }

INLINE float ggx_g(vec3 wo, vec3 wi, float alpha)
{
    return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

/* Density of visible normals seen from wo (wo.z > 0):
 * D_wo(h) = G1(wo) · max(0, wo·h) · D(h) / wo.z. */
INLINE float ggx_visible_pdf(vec3 wo, vec3 h, float alpha)
{
    return ggx_g1(wo, alpha) * fmax(0.0f, v3_dot(wo, h)) * ggx_d(h, alpha) / wo.z;
}

#ifdef HAS_ANISOTROPY
/* D(h) = 1 / (π αx αy (hx²/αx² + hy²/αy² + hz²)²). */
INLINE float ggx_d_aniso(vec3 h, float ax, float ay)
{
    float x = h.x / ax, y = h.y / ay;
    float t = x * x + y * y + h.z * h.z;
    return h.z > 0.0f ? 1.0f / (PI_F * ax * ay * t * t) : 0.0f;
}

/* Λ(w) = (−1 + sqrt(1 + (αx² wx² + αy² wy²) / wz²)) / 2. */
INLINE float ggx_lambda_aniso(vec3 w, float ax, float ay)
{
    float cos2 = w.z * w.z;
    float x = ax * w.x, y = ay * w.y;
    return cos2 > 0.0f ? 0.5f * (-1.0f + sqrt(1.0f + (x * x + y * y) / cos2)) : INFINITY;
}

INLINE float ggx_g_aniso(vec3 wo, vec3 wi, float ax, float ay)
{
    return 1.0f / (1.0f + ggx_lambda_aniso(wo, ax, ay) + ggx_lambda_aniso(wi, ax, ay));
}

INLINE float ggx_visible_pdf_aniso(vec3 wo, vec3 h, float ax, float ay)
{
    return fmax(0.0f, v3_dot(wo, h)) * ggx_d_aniso(h, ax, ay) / (wo.z * (1.0f + ggx_lambda_aniso(wo, ax, ay)));
}

#endif

/* A visible normal seen from wo: stretch to the hemisphere configuration,
 * sample a projected disk, unstretch. */
INLINE vec3 ggx_sample_visible_aniso(vec3 wo, float ax, float ay, float u1, float u2)
{
    vec3 vh = v3_normalize(v3(ax * wo.x, ay * wo.y, wo.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    float inv = rsqrt(lensq);
    vec3 t1 = lensq > 0.0f ? v3(-vh.y * inv, vh.x * inv, 0.0f) : v3(1.0f, 0.0f, 0.0f);
    vec3 t2 = v3_cross(vh, t1);
    float r = sqrt(u1), sinPhi, cosPhi;
    sin_cos_pi(2.0f * u2, &sinPhi, &cosPhi); /* φ = 2π u2 */
    float p1 = r * cosPhi, p2 = r * sinPhi;
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * p2;
    vec3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)), v3_scale(vh, sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2))));
    return v3_normalize(v3(ax * nh.x, ay * nh.y, fmax(1e-6f, nh.z)));
}

INLINE vec3 ggx_sample_visible(vec3 wo, float alpha, float u1, float u2)
{
    return ggx_sample_visible_aniso(wo, alpha, alpha, u1, u2);
}

#endif
