/* Test-only kernels for tests/BsdfTest.cpp: the production make_bsdf,
 * bsdf_sample and bsdf_eval (kernels/materials/bsdf.h) for host-chosen materials,
 * local directions and random numbers. A setup is (material index,
 * frontSide, adjoint, unused); every work item has its own setup and wo. */
#include "interface/inline.h"
#include "materials/bsdf.h"

/* The BSDF of material setup.x seen from wo (setup.y: on the front side),
 * its anisotropy turned by the material's rotation from the local x axis:
 * the tests' local frame is the tangent frame, the same x and y seen from
 * either side (the frame mirrored in z). */
INLINE Bsdf test_bsdf(__global const Material* materials, int4 setup, vec3 wo)
{
    SurfaceMaterial at = material_factors(&materials[setup.x]);
    Bsdf b = make_bsdf(&materials[setup.x], &at, wo, setup.y != 0);
#ifdef HAS_ANISOTROPY
    if (at.anisotropy > 0.0f)
        set_stretch(&b, at.anisotropyDirection.x, at.anisotropyDirection.y);
#endif
    return b;
}

/* One bsdf_sample per work item with the host's random numbers u[i].xyz,
 * plus bsdf_eval at the sampled pair (non-delta samples only).
 * wiPdf: sampled wi and pdf; weightStatus: weight and 0 (no sample),
 * 1 (non-delta) or 2 (delta); evalF: f and forward pdf. */
__kernel void sample_bsdf(__global const Material* materials, __global const int4* setups,
                          __global const float4* wos, __global const float4* us, int count,
                          __global float4* wiPdf, __global float4* weightStatus, __global float4* evalF)
{
    int i = get_global_id(0);
    if (i >= count)
        return;
    int4 setup = setups[i];
    vec3 wo = from_float3(wos[i].xyz);
    bool adjoint = setup.z != 0;
    Bsdf b = test_bsdf(materials, setup, wo);
    BsdfSample s;
    s.wi = v3s(0.0f);
    s.weight = v3s(0.0f);
    s.pdf = s.pdfRev = 0.0f;
    s.delta = false;
    float4 u = us[i];
    bool ok = bsdf_sample(&b, wo, u.x, u.y, u.z, adjoint, &s);
    float pdfFwd = 0.0f, pdfRev = 0.0f;
    vec3 f = v3s(0.0f);
    if (ok && !s.delta)
        f = bsdf_eval(&b, wo, s.wi, adjoint, &pdfFwd, &pdfRev);
    wiPdf[i] = (float4)(to_float3(s.wi), s.pdf);
    weightStatus[i] = (float4)(to_float3(s.weight), ok ? (s.delta ? 2.0f : 1.0f) : 0.0f);
    evalF[i] = (float4)(to_float3(f), pdfFwd);
}

/* bsdf_eval(wo[i], wi[i]): f and the forward pdf in evalF, the reverse pdf in
 * evalPdfRev; the lobe probabilities at wo in lobeProb: reflection,
 * transmission, the cosine-sampled lobes (diffuse and sheen), the coat. */
__kernel void eval_bsdf(__global const Material* materials, __global const int4* setups,
                        __global const float4* wos, __global const float4* wis, int count,
                        __global float4* evalF, __global float* evalPdfRev, __global float4* lobeProb)
{
    int i = get_global_id(0);
    if (i >= count)
        return;
    int4 setup = setups[i];
    vec3 wo = from_float3(wos[i].xyz);
    Bsdf b = test_bsdf(materials, setup, wo);
    float pdfFwd, pdfRev;
    vec3 f = bsdf_eval(&b, wo, from_float3(wis[i].xyz), setup.z != 0, &pdfFwd, &pdfRev);
    evalF[i] = (float4)(to_float3(f), pdfFwd);
    evalPdfRev[i] = pdfRev;
    lobeProb[i] = (float4)(b.lobeProb.x, b.lobeProb.y, b.lobeProb.z + b.sheenProb, b.coatProb);
}

/* The sheen's tabulated directional albedo (materials/sheen.h) at roughness
 * rMu[i].x and cos θ = rMu[i].y. */
__kernel void sheen_albedo_lookup(__global const float2* rMu, int count, __global float* albedo)
{
    int i = get_global_id(0);
    if (i < count)
        albedo[i] = sheen_albedo(rMu[i].x, rMu[i].y);
}

/* The forward pdf over one bin [θ0, θ0 + dθ] × [φ0, φ0 + dφ]: the midpoint
 * rule with sub × sub points, dω = sin θ dθ dφ. Row sums keep the float
 * accumulation short. */
INLINE float bin_integral(const Bsdf* b, vec3 wo, bool adjoint, float theta0, float dTheta, float phi0,
                          float dPhi, int sub)
{
    float sum = 0.0f;
    for (int a = 0; a < sub; ++a) {
        float theta = theta0 + ((float)a + 0.5f) / (float)sub * dTheta;
        float sinTheta = sin(theta), cosTheta = cos(theta);
        float row = 0.0f;
        for (int c = 0; c < sub; ++c) {
            float phi = phi0 + ((float)c + 0.5f) / (float)sub * dPhi;
            vec3 wi = v3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
            float pdfFwd, pdfRev;
            bsdf_eval(b, wo, wi, adjoint, &pdfFwd, &pdfRev);
            row += pdfFwd;
        }
        sum += row * sinTheta;
    }
    return sum * (dTheta / (float)sub) * (dPhi / (float)sub);
}

/* The forward pdf at wo integrated over each bin of a grid of the sphere
 * uniform in θ ∈ [0, π] (thetaBins) and φ ∈ [−π, π) (phiBins), one bin per
 * work item. The midpoint rule's resolution doubles from 16 × 16 points
 * until two estimates agree to 3e-4 relative (the rule's error is then
 * ~1e-4, it falls as the spacing squared) or 256 × 256: narrow GGX lobes
 * need ~1e-3 rad spacing, broad ones settle at once. */
__kernel void pdf_bin_integrals(__global const Material* materials, int4 setup, float4 wo4, int thetaBins,
                                int phiBins, __global float* integrals)
{
    int bin = get_global_id(0);
    if (bin >= thetaBins * phiBins)
        return;
    vec3 wo = from_float3(wo4.xyz);
    bool adjoint = setup.z != 0;
    Bsdf b = test_bsdf(materials, setup, wo);
    float dTheta = PI_F / (float)thetaBins, dPhi = 2.0f * PI_F / (float)phiBins;
    float theta0 = (float)(bin / phiBins) * dTheta, phi0 = -PI_F + (float)(bin % phiBins) * dPhi;
    float estimate = bin_integral(&b, wo, adjoint, theta0, dTheta, phi0, dPhi, 16);
    for (int sub = 32; sub <= 256; sub *= 2) {
        float finer = bin_integral(&b, wo, adjoint, theta0, dTheta, phi0, dPhi, sub);
        bool converged = fabs(finer - estimate) <= 3e-4f * finer + 1e-9f;
        estimate = finer;
        if (converged)
            break;
    }
    integrals[bin] = estimate;
}
