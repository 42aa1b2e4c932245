/* The recursive MIS quantities of vertex connection and merging (Georgiev,
 * "Implementing Vertex Connection and Merging", tech. report 2012, §5; the
 * equation numbers below are that report's). Every sub-path vertex carries
 * dVCM, dVC and dVM, from which the balance-heuristic weight of any technique
 * that ends at it costs O(1). Mis(x) = x: the balance heuristic, which keeps
 * these ratios of pdfs within float range (a power heuristic squares them). */
#ifndef WAVEVCM_MIS_H
#define WAVEVCM_MIS_H

typedef struct PathMis {
    float dVCM, dVC, dVM;
} PathMis;

inline PathMis load_mis(__global const float4* m, int slot)
{
    float4 v = m[slot];
    PathMis r = {v.x, v.y, v.z};
    return r;
}

inline void store_mis(__global float4* m, int slot, PathMis v) { m[slot] = (float4)(v.dVCM, v.dVC, v.dVM, 0.0f); }

/* Light sub-path start (eqs. 31-33; delta lights 48-50): directPdf is the
 * density of next-event estimation choosing this point (area) or direction
 * (infinite lights), emissionPdfW that of emitting this ray; cosine 1 for
 * lights without a surface. */
inline PathMis mis_light_start(float directPdf, float emissionPdfW, float cosAtLight, bool finite, bool delta,
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
inline PathMis mis_camera_start(float lightPaths, float cameraPdfW)
{
    PathMis m = {lightPaths / cameraPdfW, 0.0f, 0.0f};
    return m;
}

/* At a new hit at distance `dist`, seen at |cos| `cosHit` from the incoming
 * direction (shading normal): convert the pdfs of the last segment to area
 * measure. The first segment of a path from an infinite light has no
 * distance (§5.1). */
inline void mis_at_hit(PathMis* m, float dist, float cosHit, bool convertDistance)
{
    if (convertDistance)
        m->dVCM *= dist * dist;
    float inv = 1.0f / cosHit;
    m->dVCM *= inv;
    m->dVC *= inv;
    m->dVM *= inv;
}

/* After sampling a new direction with solid-angle pdf pdfW (continuation
 * probability included), reverse pdf revPdfW, and |cos| cosOut at this
 * vertex (eqs. 34-36; specular vertices 53-55). */
inline void mis_after_scatter(PathMis* m, bool delta, float cosOut, float pdfW, float revPdfW, float vmWeightFactor,
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

#endif
