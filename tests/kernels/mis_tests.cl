/* Test-only kernel: for one fixed path z_0 (on a triangle light) … z_k (the
 * camera) over Lambertian vertices, the VCM weights of every technique that
 * samples it, computed with the production MIS quantities and weights
 * (mis.h) from the production BSDF's densities (bsdf.h). Their sum must be 1.
 * Interior vertices have a shading normal (ns) apart from the geometric one
 * (n), as smooth-shaded and normal-mapped surfaces do: the BSDF's densities
 * are the shading frame's, every solid-angle-to-area cosine is mis_cos of
 * the geometric normal, as in the kernels. */
#include "interface/inline.h"
#include "lights/camera.h"
#include "materials/bsdf.h"
#include "transport/mis.h"

typedef struct Densities {
    float fwd, rev, cont; /* fixed→out, out→fixed (both solid angle), continuation probability */
} Densities;

/* The BSDF at a vertex with normal n: densities of `out` given `fixed` and back. */
INLINE Densities densities(__global const Material* m, float3 n, float3 fixed, float3 out)
{
    Frame f = frame_from_normal(from_float3(n));
    vec3 a = to_local(&f, from_float3(fixed)), b = to_local(&f, from_float3(out));
    SurfaceMaterial at = material_factors(m);
    Bsdf bsdf = make_bsdf(m, &at, a, true);
    Densities d;
    bsdf_eval(&bsdf, a, b, false, &d.fwd, &d.rev);
    d.cont = continuation_probability(&bsdf);
    return d;
}

INLINE float3 unit(float3 from, float3 to) { return normalize(to - from); }
INLINE float gcos(float3 n, float3 w) { return mis_cos(from_float3(n), from_float3(w)); }
INLINE float dist(float3 a, float3 b) { return length(b - a); }

#define MAX_VERTICES 8

__kernel void technique_weights(__constant const Camera* camera, __global const Material* material,
                                __global const float4* positions, __global const float4* normals,
                                __global const float4* shadingNormals, int k,
                                int pathCount, float lightArea, float lightPaths, float eta,
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
    float vmWeightFactor = eta, vcWeightFactor = 1.0f / eta;

    /* Light sub-path states at z_1 … z_{k-1} (after arriving there). */
    PathMis lightAt[MAX_VERTICES];
    float cos0 = dot(n[0], unit(z[0], z[1]));
    float directPdfA = 1.0f / lightArea, emissionPdfW = directPdfA * cos0 * INV_PI_F;
    PathMis m = mis_light_start(directPdfA, emissionPdfW, cos0, true, false, vcWeightFactor);
    for (int j = 1; j < k; ++j) {
        mis_at_hit(&m, dist(z[j - 1], z[j]), gcos(n[j], unit(z[j], z[j - 1])), true);
        lightAt[j] = m;
        Densities d = densities(material, ns[j], unit(z[j], z[j - 1]), unit(z[j], z[j + 1]));
        mis_after_scatter(&m, false, gcos(n[j], unit(z[j], z[j + 1])), d.fwd * d.cont, d.rev * d.cont,
                          vmWeightFactor, vcWeightFactor);
    }

    /* Camera sub-path states at z_{k-1} … z_0. */
    PathMis cameraAt[MAX_VERTICES];
    m = mis_camera_start(lightPaths, camera_pdf_w(camera, from_float3(unit(z[k], z[k - 1]))));
    for (int j = k - 1; j >= 0; --j) {
        mis_at_hit(&m, dist(z[j + 1], z[j]), gcos(n[j], unit(z[j], z[j + 1])), true);
        cameraAt[j] = m;
        if (j == 0)
            break;
        Densities d = densities(material, ns[j], unit(z[j], z[j + 1]), unit(z[j], z[j - 1]));
        mis_after_scatter(&m, false, gcos(n[j], unit(z[j], z[j - 1])), d.fwd * d.cont, d.rev * d.cont,
                          vmWeightFactor, vcWeightFactor);
    }

    float sum = 0.0f;
    int count = 0;
    /* s = 0: the camera path hits the light. */
    sum += mis_weight_emission_hit(cameraAt[0], directPdfA, emissionPdfW);
    ++count;
    /* s = 1: next-event estimation from z_1. */
    {
        Densities d = densities(material, ns[1], unit(z[1], z[2]), unit(z[1], z[0]));
        float d01 = dist(z[0], z[1]);
        sum += mis_weight_nee(cameraAt[1], d.fwd * d.cont, d.rev * d.cont, directPdfA * d01 * d01 / cos0,
                              emissionPdfW, gcos(n[1], unit(z[1], z[0])), cos0, vmWeightFactor);
        ++count;
    }
    /* 2 ≤ s ≤ k-1: light vertex z_{s-1} connected to camera vertex z_s. */
    for (int s = 2; s <= k - 1; ++s) {
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
    {
        float3 l = z[k - 1];
        float d2 = dot(z[k] - l, z[k] - l);
        Densities d = densities(material, ns[k - 1], unit(l, z[k - 2]), unit(l, z[k]));
        float cameraPdfA = camera_pdf_w(camera, from_float3(unit(z[k], l))) * gcos(n[k - 1], unit(l, z[k])) / d2;
        sum += mis_weight_light_to_camera(lightAt[k - 1], cameraPdfA, lightPaths, d.rev * d.cont, vmWeightFactor);
        ++count;
    }
    /* Merging at z_j, 1 ≤ j ≤ k-1. */
    for (int j = 1; j <= k - 1; ++j) {
        Densities d = densities(material, ns[j], unit(z[j], z[j + 1]), unit(z[j], z[j - 1]));
        sum += mis_weight_merge(lightAt[j], cameraAt[j], d.fwd * d.cont, d.rev * d.cont, vcWeightFactor);
        ++count;
    }
    weightSums[path] = sum;
    techniques[path] = count;
}
