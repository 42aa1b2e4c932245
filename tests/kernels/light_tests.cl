/* Test-only kernels for lights.h. */
#include "core/rng.h"
#include "lights/lights.h"

/* Per sample: the power estimate radiance · cos / (pdfPosition · pdfDirection)
 * of one emission sample (0 if none was produced). Its mean is the total
 * power of all lights. */
__kernel void emission_power(__global const Light* lights, __global const float* cdf,
                             __global const float4* triVertices, __constant const SceneInfo* scene,
                             __global const float4* envRadiance, __global const float* envMarginalCdf,
                             __global const float* envConditionalCdf, int n, __global float4* estimates)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    Uniform4 u = rng_uniform4(1u, 0u, (uint)i, 0u, 0u), v = rng_uniform4(1u, 0u, (uint)i, 0u, 1u);
    EmissionSample e;
    vec3 estimate = v3s(0.0f);
    Environment env = {envRadiance, envMarginalCdf, envConditionalCdf};
    if (sample_emission(lights, cdf, triVertices, scene, &env, u, v, &e))
        estimate = v3_scale(e.radiance, e.cosAtLight / (e.pdfPosition * e.pdfDirection));
    estimates[i] = (float4)(to_float3(estimate), 0.0f);
}

/* Per sample: the NEE estimate of irradiance at point p with normal n,
 * radiance · max(0, cos) / pdf. Its mean is the irradiance from all lights. */
__kernel void nee_irradiance(__global const Light* lights, __global const float* cdf,
                             __global const float4* triVertices, __constant const SceneInfo* scene,
                             __global const float4* envRadiance, __global const float* envMarginalCdf,
                             __global const float* envConditionalCdf, float4 p, float4 n, int count,
                             __global float4* estimates)
{
    int i = get_global_id(0);
    if (i >= count)
        return;
    Uniform4 u = rng_uniform4(2u, 0u, (uint)i, 0u, 0u);
    LightSample s;
    vec3 estimate = v3s(0.0f);
    Environment env = {envRadiance, envMarginalCdf, envConditionalCdf};
    if (sample_light(lights, cdf, triVertices, scene, &env, from_float3(p.xyz), u, &s))
        estimate = v3_scale(s.radiance, fmax(0.0f, v3_dot(s.direction, from_float3(n.xyz))) / s.pdf);
    estimates[i] = (float4)(to_float3(estimate), 0.0f);
}

/* Per sample: a direction towards the background by importance (d, pdf in
 * samples[4i]; radiance and whether looking d up gives the same radiance
 * and density in samples[4i + 1].w); what the lookup found, for a failing
 * test to show: its density, texel, u, and the rotation the kernel read in
 * samples[4i + 2], its radiance and whether that alone agrees in
 * samples[4i + 3]. */
__kernel void environment_samples(__global const Light* lights, __constant const SceneInfo* scene,
                                  __global const float4* envRadiance, __global const float* envMarginalCdf,
                                  __global const float* envConditionalCdf, int n, __global float4* samples)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    Environment env = {envRadiance, envMarginalCdf, envConditionalCdf};
    __global const Light* bg = &lights[scene->backgroundLight];
    Uniform4 u = rng_uniform4(3u, 0u, (uint)i, 0u, 0u);
    vec3 d, radiance;
    float pdf = 0.0f, lookupPdf, sinTheta;
    bool ok = sample_background(bg, scene, &env, u.x, u.y, &d, &radiance, &pdf);
    vec3 lookup = background_radiance(bg, scene, &env, d, &lookupPdf);
    /* The same to a few ulp, not exactly: NVIDIA's compiler contracts
     * e·t1 − e·t2 across the inlined calls into fma(e, t1, −e·t2), which
     * leaves e·t2's rounding error (PoCL contracts within a statement only). */
    vec3 diff = v3_sub(lookup, radiance);
    bool sameRadiance = fabs(diff.x) <= 1e-6f * fabs(radiance.x) && fabs(diff.y) <= 1e-6f * fabs(radiance.y) &&
                        fabs(diff.z) <= 1e-6f * fabs(radiance.z);
    bool same = sameRadiance && fabs(lookupPdf - pdf) <= 1e-4f * pdf;
    int texel = env_texel(scene, d, &sinTheta);
    float lookupU = atan2(d.x, -d.z) * (0.5f * INV_PI_F) + 0.5f - scene->envRotation;
    samples[4 * i] = (float4)(to_float3(d), ok ? pdf : -1.0f);
    samples[4 * i + 1] = (float4)(to_float3(radiance), same ? 1.0f : 0.0f);
    samples[4 * i + 2] = (float4)(lookupPdf, (float)texel, lookupU, scene->envRotation);
    samples[4 * i + 3] = (float4)(to_float3(lookup), sameRadiance ? 1.0f : 0.0f);
}
