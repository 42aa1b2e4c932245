/* Continuing a sub-path from a vertex, written once for camera paths (pt and
 * the bidirectional algorithms) and light paths: the BSDF sample (scatter),
 * the bidirectional algorithms' Russian roulette and MIS update
 * (continue_bidirectional), and storing the next segment with the NaN policy
 * (store_continuation). pt's own Russian roulette is in shade.cl. */
#ifndef WAVEVCM_CONTINUE_PATH_H
#define WAVEVCM_CONTINUE_PATH_H

#include "core/nan_policy.h"
#include "core/rng.h"
#include "core/vec3.h"
#include "geometry/surface.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/bsdf.h"
#include "mis.h"
#include "path_state.h"

typedef struct Scatter {
    vec3 wi;       /* the sampled direction, world space */
    vec3 weight;   /* f·|cos θi|/pdf; light paths: adjoint form with Veach's shading-normal correction */
    float pdfW;    /* solid-angle pdf of wi (a delta lobe: its selection probability) */
    float revPdfW; /* pdf of sampling wo from wi (= pdfW for a delta lobe) */
    float misCos;  /* mis_cos of wi: |cos θi| at the geometric normal */
    int delta;
    int refracted; /* crossed into or out of a solid: radiance carries 1/η² */
} Scatter;

/* Samples the BSDF at `hit`, wo pointing back along the path (woL in the
 * shading frame); `adjoint` for light paths. Fails when the sample is void or
 * wi lies on the other side of the geometric surface than its side of the
 * shading frame says (sides_agree). */
INLINE bool scatter(const Bsdf* bsdf, const SurfaceHit* hit, vec3 wo, vec3 woL, Uniform4 u, bool adjoint,
                    Scatter* s)
{
    BsdfSample bs;
    if (!bsdf_sample(bsdf, woL, u.x, u.y, u.z, adjoint, &bs))
        return false;
    s->wi = to_world(&hit->frame, bs.wi);
    if (!sides_agree(hit, s->wi, bs.wi))
        return false;
    s->weight = adjoint ? v3_scale(bs.weight, adjoint_shading_correction(hit, wo, s->wi)) : bs.weight;
    s->pdfW = bs.pdf;
    s->revPdfW = bs.pdfRev;
    s->misCos = mis_cos(hit->ngF, s->wi);
    s->delta = bs.delta;
    s->refracted = bsdf->solid && bs.wi.z < 0.0f;
    return true;
}

/* The bidirectional algorithms' continuation (SmallVCM's SampleScattering):
 * scatter, survive Russian roulette with the material's continuation
 * probability `cont` (u.w < cont; it is part of both pdfs, so of every MIS
 * weight), update the MIS quantities (Georgiev's report, eqs. 34-36) and the
 * throughput, β ← β · weight / cont. */
INLINE bool continue_bidirectional(const Bsdf* bsdf, const SurfaceHit* hit, vec3 wo, vec3 woL, Uniform4 u,
                                   bool adjoint, float cont, const LaunchParams* params, PathMis* mis, vec3* beta,
                                   Scatter* s)
{
    if (!scatter(bsdf, hit, wo, woL, u, adjoint, s) || !(u.w < cont))
        return false;
    mis_after_scatter(mis, s->delta, s->misCos, s->pdfW * cont, s->revPdfW * cont, params->vmWeightFactor,
                      params->vcWeightFactor);
    *beta = v3_mul(*beta, v3_div(s->weight, cont));
    return true;
}

/* The next segment of path `slot`: from `hit` along wi, with throughput beta
 * (w: pt's η² scale, else 0) and depth `depth` for the vertex it leaves.
 * Returns the slot it continues in (next_round_slot, path_state.h), with its
 * sample carried there; the caller stores there the rest of what the path
 * keeps (its MIS quantities, its flags, a light path's last vertex).
 * -1, and nothing stored, when beta is zero or rejected by the NaN policy
 * (counted in *rejected): the path ends. */
INLINE int store_continuation(const RenderBuffers* b, const LaunchParams* params, int slot, const SurfaceHit* hit,
                              vec3 wi, vec3 beta, float w, int depth, int* rejected)
{
    if (!accept_finite(beta, rejected) || !(max_component(beta) > 0.0f))
        return -1;
    int next = next_round_slot(params);
    b->pathPixel[next] = b->pathPixel[slot];
    store_ray(b->rayOrigins, b->rayDirections, next, spawn_ray(hit->p, hit->pError, hit->ngF, wi));
    store_vec3w(b->pathThroughput, next, beta, w);
    b->pathDepth[next] = depth;
    return next;
}

#endif
