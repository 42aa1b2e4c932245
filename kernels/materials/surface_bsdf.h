/* A surface point of the scene as its material makes it: the hit shaded
 * with the material's normal map (scene_surface_hit), and the BSDF its
 * textures give (surface_bsdf). */
#ifndef WAVEVCM_SURFACE_BSDF_H
#define WAVEVCM_SURFACE_BSDF_H

#include "geometry/surface.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/bsdf.h"
#include "materials/normal_map.h"
#include "materials/texture.h"

/* The hit on triangle `tri` at barycentrics `bary`, seen from direction w
 * (surface_hit), its shading normal from the material's normal map if it
 * has one. */
INLINE SurfaceHit scene_surface_hit(const RenderBuffers* b, int tri, vec2 bary, vec3 w)
{
    SurfaceHit h = surface_hit(b->triVertices, b->triNormals, tri, bary, w);
#ifdef HAS_NORMAL_MAPS
    __global const Material* m = &b->materials[b->triMaterials[tri]];
    if (m->normalTexture > 0)
        set_shading_normal(&h, mapped_normal(b, m, tri, bary, h.frontSide ? h.nsF : v3_neg(h.nsF)), w);
#endif
    return h;
}

/* Triangle `tri`'s BSDF at barycentrics `bary`, seen from local direction
 * woL (frontSide as in make_bsdf). */
INLINE Bsdf surface_bsdf(const RenderBuffers* b, int tri, vec2 bary, vec3 woL, bool frontSide)
{
    __global const Material* m = &b->materials[b->triMaterials[tri]];
    SurfaceMaterial at = surface_material(b, m, tri, bary);
    return make_bsdf(m, &at, woL, frontSide);
}

#endif
