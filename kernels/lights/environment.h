/* The environment map: an equirectangular image of the background's
 * radiance (host/render/EnvironmentLight.h), importance-sampled by
 * luminance · sin θ.
 *
 * A direction d (world space, +y up) and map coordinates (u, v) ∈ [0, 1)²:
 * θ = π v is the angle from +y (row 0 looks straight up), and
 * φ = atan2(d.x, −d.z) = 2π (u + rotation − 1/2), so the map's centre column
 * lies along −z (where a glTF camera looks by default), turned by
 * `rotation` turns about +y:
 *   d = (sin θ sin φ, cos θ, −sin θ cos φ).
 * Sampling picks a row by the marginal CDF and a texel in it by the row's
 * conditional CDF, uniformly within the texel in (u, v); the density over
 * (u, v) is f(texel) · pdfScale, f = luminance · sin θ at the row's centre,
 * and over solid angle it is that divided by 2π² sin θ (dω = 2π² sin θ du dv). */
#ifndef WAVEVCM_ENVIRONMENT_H
#define WAVEVCM_ENVIRONMENT_H

#include "core/sampling.h"
#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

typedef struct Environment {
    __global const float4* radiance;       /* envWidth × envHeight texels, row 0 at +y */
    __global const float* marginalCdf;     /* envHeight + 1 */
    __global const float* conditionalCdf;  /* envHeight × (envWidth + 1) */
} Environment;

/* Steps of the map's CDF searches: enough bits for its larger side. The
 * renderer sets it for the scene's map (SceneFeatures), so that the
 * searches are fixed sequences of steps (cdf_bin); the default covers any map. */
#ifndef ENV_CDF_STEPS
#define ENV_CDF_STEPS 31
#endif

/* The bin of a CDF with n bins (n + 1 entries, 0 … 1) that holds u, and
 * where in it u lies (0 … 1). */
INLINE int sample_cdf(__global const float* cdf, int n, float u, float* within)
{
    int lo = cdf_bin(cdf, n, u, ENV_CDF_STEPS);
    float width = cdf[lo + 1] - cdf[lo];
    *within = width > 0.0f ? clamp((u - cdf[lo]) / width, 0.0f, 0x1.fffffep-1f) : 0.5f;
    return lo;
}

/* f of row y: sin θ at the row's centre (the luminance is the texel's). */
INLINE float env_row_sin(__constant const SceneInfo* scene, int y)
{
    return sinpi(((float)y + 0.5f) / (float)scene->envHeight);
}

/* The texel direction d falls in. */
INLINE int env_texel(__constant const SceneInfo* scene, vec3 d, float* sinTheta)
{
    int w = scene->envWidth, h = scene->envHeight;
    /* sin θ from x and z, not from y: sqrt(1 − y²) loses its digits near the poles */
    *sinTheta = sqrt(d.x * d.x + d.z * d.z);
    float v = atan2(*sinTheta, d.y) * INV_PI_F;
    float u = atan2(d.x, -d.z) * (0.5f * INV_PI_F) + 0.5f - scene->envRotation;
    u -= floor(u);
    return min((int)(v * (float)h), h - 1) * w + min((int)(u * (float)w), w - 1);
}

/* Density over solid angle of texel `texel` at a direction with sin θ = sinTheta. */
INLINE float env_texel_pdf(const Environment* env, __constant const SceneInfo* scene, int texel, float sinTheta)
{
    float f = luminance(load_vec3(env->radiance, texel)) * env_row_sin(scene, texel / scene->envWidth);
    return sinTheta > 0.0f ? f * scene->envPdfScale / (2.0f * PI_F * PI_F * sinTheta) : 0.0f;
}

/* The map's radiance along d, and the density with which env_sample picks d. */
INLINE vec3 env_radiance(const Environment* env, __constant const SceneInfo* scene, vec3 d, float* pdfW)
{
    float sinTheta;
    int texel = env_texel(scene, d, &sinTheta);
    *pdfW = env_texel_pdf(env, scene, texel, sinTheta);
    return load_vec3(env->radiance, texel);
}

/* A direction by importance: u1 picks the row, u2 the texel in it. False
 * where the density vanishes (a texel of no luminance, or a pole). */
INLINE bool env_sample(const Environment* env, __constant const SceneInfo* scene, float u1, float u2, vec3* d,
                       vec3* radiance, float* pdfW)
{
    int w = scene->envWidth, h = scene->envHeight;
    float fy, fx;
    int y = sample_cdf(env->marginalCdf, h, u1, &fy);
    int x = sample_cdf(env->conditionalCdf + y * (w + 1), w, u2, &fx);
    float v = ((float)y + fy) / (float)h, u = ((float)x + fx) / (float)w;
    float sinTheta, cosTheta, sinPhi, cosPhi;
    sin_cos_pi(v, &sinTheta, &cosTheta);
    sin_cos_pi(2.0f * (u + scene->envRotation - 0.5f), &sinPhi, &cosPhi); /* φ in units of π */
    *d = v3(sinTheta * sinPhi, cosTheta, -sinTheta * cosPhi);
    int texel = y * w + x;
    *radiance = load_vec3(env->radiance, texel);
    *pdfW = env_texel_pdf(env, scene, texel, sinTheta);
    return *pdfW > 0.0f;
}

#endif
