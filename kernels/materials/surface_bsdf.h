/* A surface point of the scene as its material makes it: the hit shaded
 * with the material's normal map (scene_surface_hit), and the BSDF its
 * textures and tangent frame give (surface_bsdf). */
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

/* Triangle `tri`'s BSDF at barycentrics `bary` of hit h, seen from local
 * direction woL. */
INLINE Bsdf surface_bsdf(const RenderBuffers* b, const SurfaceHit* h, int tri, vec2 bary, vec3 woL)
{
    __global const Material* m = &b->materials[b->triMaterials[tri]];
    SurfaceMaterial at = surface_material(b, m, tri, bary);
    Bsdf bsdf = make_bsdf(m, &at, woL, h->frontSide);
#ifdef HAS_ANISOTROPY
    if (at.anisotropy > 0.0f) {
        /* The anisotropy's direction, given in the tangent frame (about the
         * side the file's normals face, so that both sides see one
         * direction), in the local one. Without tangents a frame made from
         * that normal alone stands in. */
        vec3 n = h->frontSide ? h->nsF : v3_neg(h->nsF);
        Frame f = frame_from_normal(n);
        vec3 t = f.s, bt = f.t;
#ifdef HAS_TANGENTS
        tangent_frame(b, tri, bary, n, &t, &bt);
#endif
        vec3 d = to_local(&h->frame, v3_add(v3_scale(t, at.anisotropyDirection.x), v3_scale(bt, at.anisotropyDirection.y)));
        set_stretch(&bsdf, d.x, d.y);
    }
#endif
    return bsdf;
}

#endif
