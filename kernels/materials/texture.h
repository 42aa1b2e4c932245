/* Material textures (host/scene/Scene.h: Texture; TextureInfo in
 * interface/shared_types.h): bilinear filtering between texel centres at
 * ((i + 1/2) / width, (j + 1/2) / height), row 0 at v = 0 as in glTF, with
 * the sampler's wrap mode per axis. */
#ifndef WAVEVCM_TEXTURE_H
#define WAVEVCM_TEXTURE_H

#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/kernel_interface.h"
#include "interface/shared_types.h"
#include "materials/bsdf.h"

/* Texel index i of a row or column of n under a glTF wrap mode: repeat,
 * clamp to the edge, or repeat mirrored every other time. */
INLINE int wrap_texel(int i, int n, int mode)
{
    int period = mode == WRAP_MIRROR ? 2 * n : n;
    int m = i % period;
    m = m < 0 ? m + period : m;
    m = mode == WRAP_MIRROR && m >= n ? period - 1 - m : m;
    return mode == WRAP_CLAMP ? clamp(i, 0, n - 1) : m;
}

/* The four texels a bilinear lookup at (u0, v0) blends, top row first, and
 * its weights along x and y. */
typedef struct TexelFootprint {
    int top0, top1, bottom0, bottom1;
    float ax, ay;
} TexelFootprint;

INLINE TexelFootprint texel_footprint(__global const TextureInfo* t, float u0, float v0)
{
    float u = t->uvTransform[0] * u0 + t->uvTransform[1] * v0 + t->uvTransform[2];
    float v = t->uvTransform[3] * u0 + t->uvTransform[4] * v0 + t->uvTransform[5];
    /* Far outside [0, 1] only the wrap matters; keep the texel indices in int range. */
    float x = clamp(u, -1e6f, 1e6f) * (float)t->width - 0.5f, y = clamp(v, -1e6f, 1e6f) * (float)t->height - 0.5f;
    float fx = floor(x), fy = floor(y);
    TexelFootprint f;
    f.ax = x - fx;
    f.ay = y - fy;
    int x0 = wrap_texel((int)fx, t->width, t->wrapS), x1 = wrap_texel((int)fx + 1, t->width, t->wrapS);
    int y0 = wrap_texel((int)fy, t->height, t->wrapT), y1 = wrap_texel((int)fy + 1, t->height, t->wrapT);
    int row0 = t->offset + y0 * t->width, row1 = t->offset + y1 * t->width;
    f.top0 = row0 + x0;
    f.top1 = row0 + x1;
    f.bottom0 = row1 + x0;
    f.bottom1 = row1 + x1;
    return f;
}

INLINE vec3 texture_bilinear(__global const float4* texels, __global const TextureInfo* t, float u0, float v0)
{
    TexelFootprint f = texel_footprint(t, u0, v0);
    vec3 top = v3_add(v3_scale(load_vec3(texels, f.top0), 1.0f - f.ax), v3_scale(load_vec3(texels, f.top1), f.ax));
    vec3 bottom =
        v3_add(v3_scale(load_vec3(texels, f.bottom0), 1.0f - f.ax), v3_scale(load_vec3(texels, f.bottom1), f.ax));
    return v3_add(v3_scale(top, 1.0f - f.ay), v3_scale(bottom, f.ay));
}

/* The texture's alpha (texel w; 1 where its image has no alpha channel). */
INLINE float texture_alpha(__global const float4* texels, __global const TextureInfo* t, float u0, float v0)
{
    TexelFootprint f = texel_footprint(t, u0, v0);
    float top = texels[f.top0].w * (1.0f - f.ax) + texels[f.top1].w * f.ax;
    float bottom = texels[f.bottom0].w * (1.0f - f.ax) + texels[f.bottom1].w * f.ax;
    return top * (1.0f - f.ay) + bottom * f.ay;
}

/* One set of texture coordinates (triUVs: TEXCOORD_0 or _1 per triangle
 * corner) at barycentrics `bary` of triangle `tri`. */
INLINE vec2 surface_uv(__global const float2* triUVs, int tri, vec2 bary)
{
    vec2 t0 = load_vec2(triUVs, 3 * tri), t1 = load_vec2(triUVs, 3 * tri + 1), t2 = load_vec2(triUVs, 3 * tri + 2);
    float b0 = 1.0f - bary.x - bary.y;
    return v2(b0 * t0.x + bary.x * t1.x + bary.y * t2.x, b0 * t0.y + bary.x * t1.y + bary.y * t2.y);
}

/* Texture `index` (1 + its place in the table, as materials refer to it) at
 * barycentrics `bary` of triangle `tri`, looked up at the texture
 * coordinates it reads (TEXCOORD_0 or _1); colour, then alpha. */
INLINE vec2 scene_texture_uv(const RenderBuffers* b, __global const TextureInfo* t, int tri, vec2 bary)
{
#ifdef HAS_TEXCOORD1
    if (t->texCoord == 1)
        return surface_uv(b->triUVs1, tri, bary);
#endif
    return surface_uv(b->triUVs, tri, bary);
}

INLINE vec3 scene_texture(const RenderBuffers* b, int index, int tri, vec2 bary)
{
    __global const TextureInfo* t = &b->textures[index - 1];
    vec2 uv = scene_texture_uv(b, t, tri, bary);
    return texture_bilinear(b->textureTexels, t, uv.x, uv.y);
}

INLINE float scene_texture_alpha(const RenderBuffers* b, int index, int tri, vec2 bary)
{
    __global const TextureInfo* t = &b->textures[index - 1];
    vec2 uv = scene_texture_uv(b, t, tri, bary);
    return texture_alpha(b->textureTexels, t, uv.x, uv.y);
}

#ifdef HAS_VERTEX_COLORS
/* COLOR_0 interpolated over triangle `tri` at barycentrics `bary`: its RGB
 * multiplies the base colour (surface_material), its alpha the base
 * colour's alpha (alpha.h). Component by component, as core/vec3.h loads
 * them, so that PoCL can still run the shade kernels in SIMD. */
INLINE vec3 vertex_color(const RenderBuffers* b, int tri, vec2 bary)
{
    float w0 = 1.0f - bary.x - bary.y;
    return v3_add(v3_scale(load_vec3(b->triColors, 3 * tri), w0),
                  v3_add(v3_scale(load_vec3(b->triColors, 3 * tri + 1), bary.x),
                         v3_scale(load_vec3(b->triColors, 3 * tri + 2), bary.y)));
}

INLINE float vertex_alpha(const RenderBuffers* b, int tri, vec2 bary)
{
    return load_w(b->triColors, 3 * tri) * (1.0f - bary.x - bary.y) + load_w(b->triColors, 3 * tri + 1) * bary.x +
           load_w(b->triColors, 3 * tri + 2) * bary.y;
}
#endif

/* What material m is on triangle `tri` at barycentrics `bary`: its factors
 * times its vertex colours and textures there — the base-colour texture's
 * RGB, the metallic-roughness texture's B (metallic) and G (roughness), the
 * transmission texture's R, the specular layer's alpha (factor) and RGB
 * (colour), the clear coat's R (weight) and G (roughness), the sheen's RGB
 * (colour) and alpha (roughness), diffuse transmission's alpha (factor) and
 * RGB (colour), the anisotropy's RG (direction) and B (strength). */
INLINE SurfaceMaterial surface_material(const RenderBuffers* b, __global const Material* m, int tri, vec2 bary)
{
    SurfaceMaterial s = material_factors(m);
#ifdef HAS_VERTEX_COLORS
    s.baseColor = v3_mul(s.baseColor, vertex_color(b, tri, bary));
#endif
#ifdef HAS_TEXTURES
    if (m->baseColorTexture > 0)
        s.baseColor = v3_mul(s.baseColor, scene_texture(b, m->baseColorTexture, tri, bary));
    if (m->metallicRoughnessTexture > 0) {
        vec3 mr = scene_texture(b, m->metallicRoughnessTexture, tri, bary);
        s.roughness *= mr.y;
        s.metallic *= mr.z;
    }
    if (m->transmissionTexture > 0)
        s.transmission *= scene_texture(b, m->transmissionTexture, tri, bary).x;
    if (m->specularTexture > 0)
        s.specular *= scene_texture_alpha(b, m->specularTexture, tri, bary);
    if (m->specularColorTexture > 0)
        s.specularColor = v3_mul(s.specularColor, scene_texture(b, m->specularColorTexture, tri, bary));
#if SCENE_LOBES & LOBES_COAT
    if (m->clearcoatTexture > 0)
        s.clearcoat *= scene_texture(b, m->clearcoatTexture, tri, bary).x;
    if (m->clearcoatRoughnessTexture > 0)
        s.clearcoatRoughness *= scene_texture(b, m->clearcoatRoughnessTexture, tri, bary).y;
#endif
#if SCENE_LOBES & LOBE_SHEEN
    if (m->sheenColorTexture > 0)
        s.sheenColor = v3_mul(s.sheenColor, scene_texture(b, m->sheenColorTexture, tri, bary));
    if (m->sheenRoughnessTexture > 0)
        s.sheenRoughness *= scene_texture_alpha(b, m->sheenRoughnessTexture, tri, bary);
#endif
#ifdef HAS_ANISOTROPY
    if (m->anisotropyTexture > 0) {
        /* RG: a direction in [−1, 1]², turned by the material's rotation; B
         * scales the strength. */
        vec3 c = scene_texture(b, m->anisotropyTexture, tri, bary);
        float x = 2.0f * c.x - 1.0f, y = 2.0f * c.y - 1.0f;
        vec2 r = s.anisotropyDirection;
        s.anisotropyDirection = v2(r.x * x - r.y * y, r.y * x + r.x * y);
        s.anisotropy *= c.z;
    }
#endif
#if SCENE_LOBES & LOBE_DIFFUSE_TRANSMISSION
    if (m->diffuseTransmissionTexture > 0)
        s.diffuseTransmission *= scene_texture_alpha(b, m->diffuseTransmissionTexture, tri, bary);
    if (m->diffuseTransmissionColorTexture > 0)
        s.diffuseTransmissionColor =
            v3_mul(s.diffuseTransmissionColor, scene_texture(b, m->diffuseTransmissionColorTexture, tri, bary));
#endif
#endif
    return s;
}

#endif
