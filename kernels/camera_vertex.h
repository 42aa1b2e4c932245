/* A camera sub-path vertex as vertex connection and merging see it: the
 * surface, the BSDF seen from the camera side, and the MIS quantities
 * converted to area measure at this hit (shared by connect_vertices and merge). */
#ifndef WAVEVCM_CAMERA_VERTEX_H
#define WAVEVCM_CAMERA_VERTEX_H

#include "bsdf.h"
#include "mis.h"
#include "surface.h"

typedef struct CameraVertex {
    SurfaceHit hit;
    float3 woL; /* towards the camera, local frame */
    Bsdf bsdf;
    PathMis mis;
    float continuation;
} CameraVertex;

inline CameraVertex camera_vertex(int slot, __global const float4* triVertices, __global const float4* triNormals,
                                  __global const int* triMaterials, __global const Material* materials,
                                  __global const float4* rayDirections, __global const float* hitT,
                                  __global const int* hitTriangle, __global const float2* hitBary,
                                  __global const float4* pathMis)
{
    CameraVertex v;
    int tri = hitTriangle[slot];
    float3 wo = -rayDirections[slot].xyz;
    v.hit = surface_hit(triVertices, triNormals, tri, hitBary[slot], wo);
    v.woL = to_local(&v.hit.frame, wo);
    v.bsdf = make_bsdf(&materials[triMaterials[tri]], v.woL, v.hit.frontSide);
    v.mis = load_mis(pathMis, slot);
    mis_at_hit(&v.mis, hitT[slot], fabs(v.woL.z), true);
    v.continuation = continuation_probability(&v.bsdf);
    return v;
}

#endif
