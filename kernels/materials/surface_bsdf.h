/* The BSDF of a surface point of the scene: triangle `tri`'s material as its
 * textures make it at barycentrics `bary`, seen from local direction woL
 * (frontSide as in make_bsdf). */
#ifndef WAVEVCM_SURFACE_BSDF_H
#define WAVEVCM_SURFACE_BSDF_H

#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/bsdf.h"
#include "materials/texture.h"

INLINE Bsdf surface_bsdf(const RenderBuffers* b, int tri, vec2 bary, vec3 woL, bool frontSide)
{
    __global const Material* m = &b->materials[b->triMaterials[tri]];
    SurfaceMaterial at = surface_material(m, b->textureTexels, b->textures, b->triUVs, tri, bary);
    return make_bsdf(m, &at, woL, frontSide);
}

#endif
