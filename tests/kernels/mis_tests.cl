/* Test-only kernel: for one fixed path z_0 (on a light) … z_k (the camera)
 * over vertices of one material, one of which may be a mirror, the VCM weights of
 * every technique that samples it, computed with the production MIS
 * quantities and weights (mis.h) from the production BSDF's densities
 * (bsdf.h) and, for lights without a surface, the production light and
 * emission samplers' densities (lights.h). Their sum must be 1.
 * Interior vertices have a shading normal (ns) apart from the geometric one
 * (n), as smooth-shaded and normal-mapped surfaces do: the BSDF's densities
 * are the shading frame's, every solid-angle-to-area cosine is mis_cos of
 * the geometric normal, as in the kernels. */
#include "interface/inline.h"
#include "lights/camera.h"
#include "lights/lights.h"
#include "materials/bsdf.h"
#include "transport/mis.h"

typedef struct Densities {
    float fwd, rev, cont; /* fixed→out, out→fixed (both solid angle), continuation probability */
} Densities;

/* The BSDF at a vertex with normal n: densities of `out` given `fixed` and
 * back. Its frame is turned to fixed's side, as the kernels turn it to wo's
 * (out may lie on the other side: a transmitting vertex). */
INLINE Densities densities(__global const Material* m, float3 n, float3 fixed, float3 out)
{
    bool frontSide = dot(n, fixed) > 0.0f;
    Frame f = frame_from_normal(from_float3(frontSide ? n : -n));
    vec3 a = to_local(&f, from_float3(fixed)), b = to_local(&f, from_float3(out));
    SurfaceMaterial at = material_factors(m);
    Bsdf bsdf = make_bsdf(m, &at, a, frontSide);
#ifdef HAS_ANISOTROPY
    if (at.anisotropy > 0.0f) /* along the frame's x, whichever it is: the same at every vertex */
        set_stretch(&bsdf, at.anisotropyDirection.x, at.anisotropyDirection.y);
#endif
    Densities d;
    bsdf_eval(&bsdf, a, b, false, &d.fwd, &d.rev);
    d.cont = continuation_probability(&bsdf);
    return d;
}

INLINE float3 unit(float3 from, float3 to) { return normalize(to - from); }
INLINE float gcos(float3 n, float3 w) { return mis_cos(from_float3(n), from_float3(w)); }
INLINE float dist(float3 a, float3 b) { return length(b - a); }

/* The MIS update of scattering at z_j from `fixed` towards `out`: a mirror
 * at the specular vertex (a delta lobe: only its cosine enters, eqs. 53-55),
 * else the Lambertian BSDF. */
INLINE void scatter_at(PathMis* m, __global const Material* material, int j, int specular, float3 n, float3 ns,
                       float3 fixed, float3 out, float vmWeightFactor, float vcWeightFactor)
{
    if (j == specular) {
        mis_after_scatter(m, true, gcos(n, out), 1.0f, 1.0f, vmWeightFactor, vcWeightFactor);
        return;
    }
    Densities d = densities(material, ns, fixed, out);
    mis_after_scatter(m, false, gcos(n, out), d.fwd * d.cont, d.rev * d.cont, vmWeightFactor, vcWeightFactor);
}

#define MAX_VERTICES 8

/* lightType: LIGHT_TRIANGLE, the light at z_0 a triangle of area lightArea
 * (its densities written out here, as triangle_hit_pdfs and sample_light
 * give them); otherwise the scene's one light (`lights`), whose densities
 * come from sample_light at z_1 and sample_emission, all of them independent
 * of the direction for these lights (a point light at z_0, a directional
 * light along z_0 → z_1, a uniform background). specular[path]: the index
 * of its mirror vertex, -1 for none. */
__kernel void technique_weights(__constant const Camera* camera, __global const Material* material,
                                __global const float4* positions, __global const float4* normals,
                                __global const float4* shadingNormals, __global const int* specular, int k,
                                int pathCount, int lightType, float lightArea, float lightPaths, float eta,
                                __global const Light* lights, __global const float* cdf,
                                __global const float4* triVertices, __constant const SceneInfo* scene,
                                __global float* weightSums, __global int* techniques)
{
    int path = get_global_id(0);
    if (path >= pathCount)
        return;
    float3 z[MAX_VERTICES], n[MAX_VERTICES], ns[MAX_VERTICES];
    for (int j = 0; j <= k; ++j) {
        z[j] = positions[path * (k + 1) + j].xyz;
        n[j] = normals[path * (k + 1) + j].xyz;
        ns[j] = shadingNormals[path * (k + 1) + j].xyz;
    }
    int mirror = specular[path];
    float vmWeightFactor = eta, vcWeightFactor = 1.0f / eta;

    /* The light's densities: of next-event estimation choosing z_0 (as a
     * solid angle at z_1, and as the light start takes it: area, or solid
     * angle for infinite lights), of emitting the first segment, and the
     * cosine there. */
    float startDirectPdf, startEmissionPdfW, startCos, neeDirectPdfW, neeEmissionPdfW, neeCosAtLight;
    bool finite = true, delta = false;
    float cos0 = dot(n[0], unit(z[0], z[1]));
    float d01 = dist(z[0], z[1]);
    if (lightType == LIGHT_TRIANGLE) {
        startDirectPdf = 1.0f / lightArea;
        startEmissionPdfW = startDirectPdf * cos0 * INV_PI_F;
        startCos = cos0;
        neeDirectPdfW = startDirectPdf * d01 * d01 / cos0;
        neeEmissionPdfW = startEmissionPdfW;
        neeCosAtLight = cos0;
    } else {
        Environment env = {0, 0, 0};
        Uniform4 u = {0.25f, 0.5f, 0.75f, 0.5f};
        LightSample ls;
        EmissionSample e;
        if (!sample_light(lights, cdf, triVertices, scene, &env, from_float3(z[1]), u, &ls) ||
            !sample_emission(lights, cdf, triVertices, scene, &env, u, u, &e)) {
            weightSums[path] = -1.0f;
            techniques[path] = -1;
            return;
        }
        startDirectPdf = e.directPdf;
        startEmissionPdfW = e.pdfPosition * e.pdfDirection;
        startCos = e.cosAtLight;
        finite = e.finite;
        delta = e.deltaPosition || e.deltaDirection;
        neeDirectPdfW = ls.directPdfW;
        neeEmissionPdfW = ls.emissionPdfW;
        neeCosAtLight = ls.cosAtLight;
    }

    /* Light sub-path states at z_1 … z_{k-1} (after arriving there); the
     * first segment from an infinite light has no distance (§5.1). */
    PathMis lightAt[MAX_VERTICES];
    PathMis m = mis_light_start(startDirectPdf, startEmissionPdfW, startCos, finite, delta, vcWeightFactor);
    for (int j = 1; j < k; ++j) {
        mis_at_hit(&m, dist(z[j - 1], z[j]), gcos(n[j], unit(z[j], z[j - 1])), j > 1 || finite);
        lightAt[j] = m;
        scatter_at(&m, material, j, mirror, n[j], ns[j], unit(z[j], z[j - 1]), unit(z[j], z[j + 1]), vmWeightFactor,
                   vcWeightFactor);
    }

    /* Camera sub-path states at z_{k-1} … z_1, and after scattering at z_1
     * towards z_0 (where an escaping ray finds the background). */
    PathMis cameraAt[MAX_VERTICES];
    m = mis_camera_start(lightPaths, camera_pdf_w(camera, from_float3(unit(z[k], z[k - 1]))));
    for (int j = k - 1; j >= 1; --j) {
        mis_at_hit(&m, dist(z[j + 1], z[j]), gcos(n[j], unit(z[j], z[j + 1])), true);
        cameraAt[j] = m;
        scatter_at(&m, material, j, mirror, n[j], ns[j], unit(z[j], z[j + 1]), unit(z[j], z[j - 1]), vmWeightFactor,
                   vcWeightFactor);
    }
    PathMis towardsLight = m;

    float sum = 0.0f;
    int count = 0;
    /* s = 0: the camera path finds the light (delta lights cannot be found). */
    if (lightType == LIGHT_TRIANGLE) {
        mis_at_hit(&m, d01, gcos(n[0], unit(z[0], z[1])), true);
        sum += mis_weight_emission_hit(m, startDirectPdf, startEmissionPdfW);
        ++count;
    } else if (lightType == LIGHT_BACKGROUND) {
        Environment env = {0, 0, 0};
        float lightPdf, emissionPdfW;
        background_radiance(&lights[scene->backgroundLight], scene, &env, from_float3(unit(z[1], z[0])), &lightPdf);
        background_hit_pdfs(lightPdf, scene->radius, &emissionPdfW);
        sum += mis_weight_emission_hit(towardsLight, lightPdf, emissionPdfW);
        ++count;
    }
    /* s = 1: next-event estimation from z_1. */
    if (mirror != 1) {
        Densities d = densities(material, ns[1], unit(z[1], z[2]), unit(z[1], z[0]));
        sum += mis_weight_nee(cameraAt[1], delta ? 0.0f : d.fwd * d.cont, d.rev * d.cont, neeDirectPdfW,
                              neeEmissionPdfW, gcos(n[1], unit(z[1], z[0])), neeCosAtLight, vmWeightFactor);
        ++count;
    }
    /* 2 ≤ s ≤ k-1: light vertex z_{s-1} connected to camera vertex z_s. */
    for (int s = 2; s <= k - 1; ++s) {
        if (mirror == s - 1 || mirror == s)
            continue;
        float3 l = z[s - 1], c = z[s];
        float d2 = dot(c - l, c - l);
        Densities atCamera = densities(material, ns[s], unit(c, z[s + 1]), unit(c, l));
        Densities atLight = densities(material, ns[s - 1], unit(l, z[s - 2]), unit(l, c));
        float cosC = gcos(n[s], unit(c, l)), cosL = gcos(n[s - 1], unit(l, c));
        sum += mis_weight_connection(lightAt[s - 1], cameraAt[s], atCamera.fwd * atCamera.cont * cosL / d2,
                                     atLight.fwd * atLight.cont * cosC / d2, atLight.rev * atLight.cont,
                                     atCamera.rev * atCamera.cont, vmWeightFactor);
        ++count;
    }
    /* s = k: light vertex z_{k-1} connected to the camera. */
    if (mirror != k - 1) {
        float3 l = z[k - 1];
        float d2 = dot(z[k] - l, z[k] - l);
        Densities d = densities(material, ns[k - 1], unit(l, z[k - 2]), unit(l, z[k]));
        float cameraPdfA = camera_pdf_w(camera, from_float3(unit(z[k], l))) * gcos(n[k - 1], unit(l, z[k])) / d2;
        sum += mis_weight_light_to_camera(lightAt[k - 1], cameraPdfA, lightPaths, d.rev * d.cont, vmWeightFactor);
        ++count;
    }
    /* Merging at z_j, 1 ≤ j ≤ k-1. */
    for (int j = 1; j <= k - 1; ++j) {
        if (j == mirror)
            continue;
        Densities d = densities(material, ns[j], unit(z[j], z[j + 1]), unit(z[j], z[j - 1]));
        sum += mis_weight_merge(lightAt[j], cameraAt[j], d.fwd * d.cont, d.rev * d.cont, vcWeightFactor);
        ++count;
    }
    weightSums[path] = sum;
    techniques[path] = count;
}
