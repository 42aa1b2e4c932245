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
#include "lights/lights.h"
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

/* sample_light and sample_emission over the scene's light table, with the
 * radiance a triangle light emits at the sampled point. */
INLINE bool sample_scene_light(const RenderBuffers* b, vec3 p, Uniform4 u, LightSample* s)
{
    Environment env = {b->envRadiance, b->envMarginalCdf, b->envConditionalCdf};
    if (!sample_light(b->lights, b->lightCdf, b->triVertices, b->scene, &env, p, u, s))
        return false;
#ifdef HAS_EMISSIVE_TEXTURES
    if (s->type == LIGHT_TRIANGLE)
        s->radiance = triangle_emission(b, &b->lights[b->triangleLight[s->triangle]], s->bary);
#endif
    return true;
}

INLINE bool sample_scene_emission(const RenderBuffers* b, Uniform4 u, Uniform4 v, EmissionSample* e)
{
    Environment env = {b->envRadiance, b->envMarginalCdf, b->envConditionalCdf};
    if (!sample_emission(b->lights, b->lightCdf, b->triVertices, b->scene, &env, u, v, e))
        return false;
#ifdef HAS_EMISSIVE_TEXTURES
    if (b->lights[e->light].type == LIGHT_TRIANGLE)
        e->radiance = triangle_emission(b, &b->lights[e->light], e->bary);
#endif
    return true;
}

#endif
