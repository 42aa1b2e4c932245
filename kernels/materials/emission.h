/* What an emissive triangle emits at a point: its light's radiance (the
 * material's emissiveFactor × emissive strength) times the material's
 * emissive texture there (sRGB-decoded colour). The light table selects
 * textured emitters by the texture's mean over each triangle
 * (host/render/LightTable.cpp); emission hits, next-event estimation and
 * light sub-paths all read the texel at their point. */
#ifndef WAVEVCM_EMISSION_H
#define WAVEVCM_EMISSION_H

#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "materials/texture.h"

INLINE vec3 triangle_emission(const RenderBuffers* b, __global const Light* light, vec2 bary)
{
    vec3 radiance = load3(light->emission);
#ifdef HAS_EMISSIVE_TEXTURES
    __global const Material* m = &b->materials[b->triMaterials[light->triangle]];
    if (m->emissiveTexture > 0)
        radiance = v3_mul(radiance, scene_texture(b, m->emissiveTexture, light->triangle, bary));
#endif
    return radiance;
}

#endif
