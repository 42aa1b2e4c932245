/* Alpha (glTF alphaMode) as rays see it: an OPAQUE surface stops every ray;
 * a MASK surface is cut out where alpha < alphaCutoff; a BLEND surface lets
 * a ray through with probability 1 − alpha (stochastic transparency: the
 * expected radiance is alpha × the surface's + (1 − alpha) × what lies
 * behind). The BLEND decision is a hash of the ray and the triangle, so the
 * same ray meets the same surfaces in every kernel, on every device. alpha
 * is baseColorFactor's alpha times the base-colour texture's and COLOR_0's.
 * Traversal tests it at every candidate hit (geometry/bvh_traversal.h); a
 * surface a ray stops at is shaded as opaque. */
#ifndef WAVEVCM_ALPHA_H
#define WAVEVCM_ALPHA_H

#include "core/ray.h"
#include "core/rng.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/texture.h"

INLINE float surface_alpha(const RenderBuffers* b, __global const Material* m, int tri, vec2 bary)
{
    float alpha = m->baseColorAlpha;
#ifdef HAS_TEXTURES
    if (m->baseColorTexture > 0)
        alpha *= scene_texture_alpha(b, m->baseColorTexture, tri, bary);
#endif
#ifdef HAS_VERTEX_COLORS
    alpha *= vertex_alpha(b, tri, bary);
#endif
    return alpha;
}

/* A number in [0, 1) from the ray's origin and direction and the triangle. */
INLINE float ray_hash(Ray ray, int tri)
{
    uint h = hash32((uint)tri);
    h = hash32(h ^ as_uint(ray.origin.x));
    h = hash32(h ^ as_uint(ray.origin.y));
    h = hash32(h ^ as_uint(ray.origin.z));
    h = hash32(h ^ as_uint(ray.direction.x));
    h = hash32(h ^ as_uint(ray.direction.y));
    h = hash32(h ^ as_uint(ray.direction.z));
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* Whether `ray` stops at triangle `tri`, hit at barycentrics (b1, b2). */
INLINE bool alpha_stops_ray(const RenderBuffers* b, int tri, float b1, float b2, Ray ray)
{
    __global const Material* m = &b->materials[b->triMaterials[tri]];
    if (m->alphaMode == ALPHA_OPAQUE)
        return true;
    float alpha = surface_alpha(b, m, tri, v2(b1, b2));
    return m->alphaMode == ALPHA_MASK ? alpha >= m->alphaCutoff : ray_hash(ray, tri) < alpha;
}

#endif
