/* A camera sub-path vertex as vertex connection and merging see it: the
 * surface, the BSDF seen from the camera side, and the MIS quantities
 * converted to area measure at this hit (shared by connect_vertices and merge). */
#ifndef WAVEVCM_CAMERA_VERTEX_H
#define WAVEVCM_CAMERA_VERTEX_H

#include "geometry/surface.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/bsdf.h"
#include "materials/surface_bsdf.h"
#include "mis.h"

typedef struct CameraVertex {
    SurfaceHit hit;
    vec3 woL; /* towards the camera, local frame */
    Bsdf bsdf;
    PathMis mis;
    float continuation;
} CameraVertex;

INLINE CameraVertex camera_vertex(const RenderBuffers* b, int slot)
{
    CameraVertex v;
    int tri = b->hitTriangle[slot];
    vec3 wo = v3_neg(load_vec3(b->rayDirections, slot));
    vec2 bary = load_vec2(b->hitBary, slot);
    v.hit = scene_surface_hit(b, tri, bary, wo);
    v.woL = to_local(&v.hit.frame, wo);
    v.bsdf = surface_bsdf(b, &v.hit, tri, bary, v.woL);
    v.mis = load_mis(b->pathMis, slot);
    mis_at_hit(&v.mis, b->hitT[slot], mis_cos(v.hit.ngF, wo), true);
    v.continuation = continuation_probability(&v.bsdf);
    return v;
}

#endif
