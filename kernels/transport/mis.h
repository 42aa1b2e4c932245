/* The recursive MIS quantities of vertex connection and merging (Georgiev,
 * "Implementing Vertex Connection and Merging", tech. report 2012, §5; the
 * equation numbers below are that report's). Every sub-path vertex carries
 * dVCM, dVC and dVM, from which the balance-heuristic weight of any technique
 * that ends at it costs O(1). Mis(x) = x: the balance heuristic, which keeps
 * these ratios of pdfs within float range (a power heuristic squares them). */
#ifndef WAVEVCM_MIS_H
#define WAVEVCM_MIS_H

#include "core/vec3.h"
#include "interface/inline.h"

typedef struct PathMis {
    float dVCM, dVC, dVM;
    float abiPad[2]; /* see vec3 (core/vec3.h): 12 bytes would travel as <2 x float> + float */
} PathMis;

/* ppm and lt give every path they sample to one technique, weighted 1 (ppm:
 * a merge, or emission at the end of a purely specular camera path; lt:
 * light tracing), so their paths carry no MIS quantities: loading and
 * storing them is left out, and with it the arithmetic that only feeds them
 * (interleaved 8 s pairs of kernel copies: iterations +2.5-3.9 % for ppm
 * and +2.7-3.2 % for lt on the Cornell box, within the spread on the
 * caustics scene; the same images). */
#if defined(PPM) || defined(LIGHT_TRACING)
#define PATHS_CARRY_MIS 0
#else
#define PATHS_CARRY_MIS 1
#endif

INLINE PathMis load_mis(__global const float4* m, int slot)
{
    PathMis r = {0.0f, 0.0f, 0.0f};
    if (PATHS_CARRY_MIS) {
        vec3 v = load_vec3(m, slot);
        r.dVCM = v.x;
        r.dVC = v.y;
        r.dVM = v.z;
    }
    return r;
}

INLINE void store_mis(__global float4* m, int slot, PathMis v)
{
    if (PATHS_CARRY_MIS)
        store_vec3w(m, slot, v3(v.dVCM, v.dVC, v.dVM), 0.0f);
}

/* Light sub-path start (eqs. 31-33; delta lights 48-50): directPdf is the
 * density of next-event estimation choosing this point (area) or direction
 * (infinite lights), emissionPdfW that of emitting this ray; cosine 1 for
 * lights without a surface. */
INLINE PathMis mis_light_start(float directPdf, float emissionPdfW, float cosAtLight, bool finite, bool delta,
                               float vcWeightFactor)
{
    PathMis m;
    m.dVCM = directPdf / emissionPdfW;
    m.dVC = delta ? 0.0f : (finite ? cosAtLight : 1.0f) / emissionPdfW;
    m.dVM = m.dVC * vcWeightFactor;
    return m;
}

/* Camera sub-path start: light tracing (t = 1) has lightPaths samples per
 * pixel; cameraPdfW is the camera's density of the primary direction. */
INLINE PathMis mis_camera_start(float lightPaths, float cameraPdfW)
{
    PathMis m = {lightPaths / cameraPdfW, 0.0f, 0.0f};
    return m;
}

/* The one rule for the cosines in these quantities and in the densities the
 * weights compare: each converts a density per solid angle into one per unit
 * area at the vertex a direction arrives at or leaves, dA = d² dω / |cos θ|,
 * so it is the cosine to the surface itself, the geometric normal's, whatever
 * normal shades the vertex (the emitters' densities use it too). With a
 * shading normal's cosine in some of them, the weights of a smooth-shaded or
 * normal-mapped vertex would not sum to one. */
INLINE float mis_cos(vec3 ng, vec3 w) { return fabs(v3_dot(ng, w)); }

/* At a new hit at distance `dist`, seen at `cosHit` = mis_cos from the
 * incoming direction: convert the pdfs of the last segment to area measure.
 * The first segment of a path from an infinite light has no distance
 * (§5.1). */
INLINE void mis_at_hit(PathMis* m, float dist, float cosHit, bool convertDistance)
{
    if (convertDistance)
        m->dVCM *= dist * dist;
    float inv = 1.0f / cosHit;
    m->dVCM *= inv;
    m->dVC *= inv;
    m->dVM *= inv;
}

/* After sampling a new direction with solid-angle pdf pdfW (continuation
 * probability included), reverse pdf revPdfW, and cosOut = mis_cos at this
 * vertex (eqs. 34-36; specular vertices 53-55). */
INLINE void mis_after_scatter(PathMis* m, bool delta, float cosOut, float pdfW, float revPdfW, float vmWeightFactor,
                              float vcWeightFactor)
{
    if (delta) {
        m->dVCM = 0.0f;
        m->dVC *= cosOut;
        m->dVM *= cosOut;
        return;
    }
    float ratio = cosOut / pdfW;
    float dVC = ratio * (m->dVC * revPdfW + m->dVCM + vmWeightFactor);
    float dVM = ratio * (m->dVM * revPdfW + m->dVCM * vcWeightFactor + 1.0f);
    m->dVC = dVC;
    m->dVM = dVM;
    m->dVCM = 1.0f / pdfW;
}

/* The weights. Each is 1 / (1 + Σ p_other / p_this) over the techniques
 * that could have sampled the same path, read from the MIS quantities of the
 * sub-path vertices that this technique joins. Densities carry the
 * continuation probability of Russian roulette wherever they involve a
 * scattering event. */

/* A camera path (state `camera`, at the hit) finding an emitter whose
 * next-event density (area, or solid angle for the background) is
 * directPdf and whose emission density for the ray is emissionPdfW
 * (eqs. 42-43). */
INLINE float mis_weight_emission_hit(PathMis camera, float directPdf, float emissionPdfW)
{
    return 1.0f / (1.0f + directPdf * camera.dVCM + emissionPdfW * camera.dVC);
}

/* Next-event estimation from a camera vertex: bsdfDirPdfW is the density of
 * the BSDF sampling the light's direction (0 for delta lights), bsdfRevPdfW
 * that of the reverse direction, cosToLight mis_cos there; directPdfW,
 * emissionPdfW and cosAtLight as in LightSample (eqs. 44-45). */
INLINE float mis_weight_nee(PathMis camera, float bsdfDirPdfW, float bsdfRevPdfW, float directPdfW,
                            float emissionPdfW, float cosToLight, float cosAtLight, float vmWeightFactor)
{
    float wLight = bsdfDirPdfW / directPdfW;
    float wCamera = emissionPdfW * cosToLight / (directPdfW * cosAtLight) *
                    (vmWeightFactor + camera.dVCM + camera.dVC * bsdfRevPdfW);
    return 1.0f / (wLight + 1.0f + wCamera);
}

/* A light vertex connected to the camera (t = 1): cameraPdfA is the camera's
 * density of sampling the vertex (per unit area), lightPaths the light paths
 * per pass of an iteration (one per pixel), bsdfRevPdfW the light vertex's density of sampling its
 * incoming direction from the camera's (eqs. 46-47). */
INLINE float mis_weight_light_to_camera(PathMis light, float cameraPdfA, float lightPaths, float bsdfRevPdfW,
                                        float vmWeightFactor)
{
    float wLight = cameraPdfA / lightPaths * (vmWeightFactor + light.dVCM + light.dVC * bsdfRevPdfW);
    return 1.0f / (wLight + 1.0f);
}

/* A camera vertex connected to a light vertex: cameraDirPdfA is the camera
 * vertex's BSDF density of the light vertex (area), lightDirPdfA the light
 * vertex's of the camera vertex; the reverse densities are solid angle
 * (eqs. 40-41, 37). */
INLINE float mis_weight_connection(PathMis light, PathMis camera, float cameraDirPdfA, float lightDirPdfA,
                                   float lightRevPdfW, float cameraRevPdfW, float vmWeightFactor)
{
    float wLight = cameraDirPdfA * (vmWeightFactor + light.dVCM + light.dVC * lightRevPdfW);
    float wCamera = lightDirPdfA * (vmWeightFactor + camera.dVCM + camera.dVC * cameraRevPdfW);
    return 1.0f / (wLight + 1.0f + wCamera);
}

/* A camera vertex merged with a light vertex: cameraDirPdfW is the camera
 * BSDF's density of the light vertex's incoming direction, cameraRevPdfW
 * the reverse (eqs. 37-39). */
INLINE float mis_weight_merge(PathMis light, PathMis camera, float cameraDirPdfW, float cameraRevPdfW,
                              float vcWeightFactor)
{
    float wLight = light.dVCM * vcWeightFactor + light.dVM * cameraDirPdfW;
    float wCamera = camera.dVCM * vcWeightFactor + camera.dVM * cameraRevPdfW;
    return 1.0f / (wLight + 1.0f + wCamera);
}

#endif
