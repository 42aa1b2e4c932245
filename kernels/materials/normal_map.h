/* The surface's tangent frame, and normal maps (glTF normalTexture). The
 * frame: the tangent t (+u), the bitangent cross(n, t)·w (−v: "up" in the
 * texture image) and the shading normal n; tangents and handedness w come
 * per triangle corner from the file's TANGENT or from the texture
 * coordinates (host/scene/GltfLoader.cpp). A normal map's texel RGB c in
 * [0, 1] is the normal 2c − 1 in that frame, its x and y times the
 * material's normalScale, z along the unmapped shading normal. */
#ifndef WAVEVCM_NORMAL_MAP_H
#define WAVEVCM_NORMAL_MAP_H

#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/texture.h"

#ifdef HAS_TANGENTS
/* The unit tangent and bitangent at barycentrics `bary` of triangle `tri`
 * about the unit normal n (on the side the file's normals face); false
 * where the frame degenerates. */
INLINE bool tangent_frame(const RenderBuffers* b, int tri, vec2 bary, vec3 n, vec3* tangent, vec3* bitangent)
{
    float b0 = 1.0f - bary.x - bary.y;
    vec3 t = v3_add(v3_add(v3_scale(load_vec3(b->triTangents, 3 * tri), b0),
                           v3_scale(load_vec3(b->triTangents, 3 * tri + 1), bary.x)),
                    v3_scale(load_vec3(b->triTangents, 3 * tri + 2), bary.y));
    t = v3_sub(t, v3_scale(n, v3_dot(n, t))); /* Gram-Schmidt: the interpolated tangent need not be ⊥ n */
    float tLength = v3_length(t);
    if (!(tLength > 1e-12f))
        return false;
    *tangent = v3_div(t, tLength);
    float handedness = b->triTangents[3 * tri].w < 0.0f ? -1.0f : 1.0f;
    *bitangent = v3_scale(v3_cross(n, *tangent), handedness);
    return true;
}
#endif

#ifdef HAS_NORMAL_MAPS
/* The normal that material m's normal map makes of the unit normal n at
 * barycentrics `bary` of triangle `tri` (all on the side the file's normals
 * face); n itself where the tangent frame degenerates. */
INLINE vec3 mapped_normal(const RenderBuffers* b, __global const Material* m, int tri, vec2 bary, vec3 n)
{
    vec3 t, bitangent;
    if (!tangent_frame(b, tri, bary, n, &t, &bitangent))
        return n;
    vec3 c = scene_texture(b, m->normalTexture, tri, bary);
    vec3 mapped = v3_add(v3_add(v3_scale(t, (2.0f * c.x - 1.0f) * m->normalScale),
                                v3_scale(bitangent, (2.0f * c.y - 1.0f) * m->normalScale)),
                         v3_scale(n, 2.0f * c.z - 1.0f));
    float length = v3_length(mapped);
    return length > 1e-12f ? v3_div(mapped, length) : n;
}
#endif

#endif
