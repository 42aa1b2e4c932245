/* The BSDF of a glTF material (docs/scenes.md): up to six lobes —
 * reflection (metal plus the dielectric specular layer; GGX or smooth),
 * transmission (GGX or smooth), Lambert diffuse, Lambert diffuse
 * transmission (KHR_materials_diffuse_transmission), a sheen of fibres over them
 * (KHR_materials_sheen, materials/sheen.h) and a clear coat over all
 * (KHR_materials_clearcoat; GGX or smooth) — with lobes the scene lacks
 * compiled out through SCENE_LOBES.
 *
 * Directions are in the local shading frame (normal +z), pointing away from
 * the surface. `wo` is the direction towards the camera end of the path and
 * `wi` the one towards the light end, whichever of them was sampled; the
 * frame is flipped so that wo.z > 0. Values are for radiance transport
 * (camera paths); `adjoint` selects importance transport (light paths), which
 * differs only by the 1/η² of refraction (Veach 1997, §5.2). */
#ifndef WAVEVCM_BSDF_H
#define WAVEVCM_BSDF_H

#include "fresnel.h"
#include "ggx.h"
#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

#ifndef SCENE_LOBES
#define SCENE_LOBES LOBES_ALL
#endif
#define LOBES_REFLECT (LOBE_GGX_REFLECTION | LOBE_DELTA_REFLECTION)
#define LOBES_TRANSMIT (LOBE_GGX_TRANSMISSION | LOBE_DELTA_TRANSMISSION)
#define LOBES_COAT (LOBE_GGX_COAT | LOBE_DELTA_COAT)

#if SCENE_LOBES & LOBE_SHEEN
#include "materials/sheen.h"
#endif

typedef struct Bsdf {
    uint lobes;
    float alpha;          /* GGX α = roughness² (across the anisotropy's direction) */
#ifdef HAS_ANISOTROPY
    float alphaT;         /* α along it: mix(α, 1, strength²) (KHR_materials_anisotropy) */
    float stretchX, stretchY; /* that direction in the local frame (unit) */
#endif
    float eta;            /* η_t / η_i for light crossing from wo's side */
    bool solid;           /* light enters a closed solid (not thin-walled): transmission
                             bends, η inverts inside */
    vec3 metalF0;       /* base colour, Schlick's F0 for the metal part */
    float metallic;
    vec3 specularTint;  /* (1 − metallic) · specularFactor · specularColor */
    float specular;     /* (1 − metallic) · specularFactor */
    vec3 transmitColor; /* (1 − metallic) · transmission · base colour */
    vec3 diffuseColor;  /* (1 − metallic) · (1 − transmission) · (1 − diffuse transmission) · base colour */
    vec3 diffuseTransmitColor; /* (1 − metallic) · (1 − transmission) · diffuse transmission · its colour */
    float diffuseTransmitShare; /* of the diffuse lobes' probability, diffuse transmission's */
    float coat;         /* the clear coat's weight on wo's side (0: none there) */
    float coatBack;     /* the same on the other side, which transmission crosses */
    float coatAlpha;    /* the coat's GGX α */
    vec3 sheenColor;    /* KHR_materials_sheen's colour */
    float sheenRoughness;
    float sheen;        /* max(sheenColor) on wo's side (0: no sheen there) */
    float sheenBack;    /* the same on the other side */
    vec3 lobeProb;      /* probabilities of picking reflection, transmission, diffuse (both ways) at wo */
    float coatProb;     /* that of picking the coat */
    float sheenProb;    /* that of picking the sheen; the five sum to 1 */
} Bsdf;

typedef struct BsdfSample {
    vec3 wi;
    vec3 weight; /* f · |cos θi| / pdf */
    float pdf;     /* solid angle; for a delta lobe the lobe's selection probability */
    float pdfRev;  /* of sampling wo from wi (bidirectional MIS); a delta lobe: pdf */
    bool delta;
} BsdfSample;

/* Fresnel reflectance of the dielectric layer at cos θ; 0 where the material
 * has no layer (specular 0: Lambert, metal), whose Fresnel is then not
 * computed at all (it costs a square root and three divisions, several
 * times per BSDF). */
INLINE float layer_fresnel(const Bsdf* b, float cosH, float eta)
{
    return b->specular == 0.0f ? 0.0f : fresnel_dielectric(cosH, eta);
}

/* Reflectance of the reflection lobe at cos θ (of a microfacet, or of the
 * surface for the smooth lobe): metal Schlick plus the layer's exact Fresnel. */
INLINE vec3 reflectance(const Bsdf* b, float cosH, float eta)
{
    return v3_add(v3_scale(fresnel_schlick(b->metalF0, cosH), b->metallic),
                  v3_scale(b->specularTint, layer_fresnel(b, cosH, eta)));
}

/* What the dielectric layer lets through to transmission and diffuse. */
INLINE float layer_transmittance(const Bsdf* b, float cosH, float eta)
{
    return 1.0f - b->specular * layer_fresnel(b, cosH, eta);
}

/* What the interface itself lets through at cos θ from the side of relative
 * index eta: nothing beyond the critical angle, whatever the specular
 * layer's weight (Snell's law, not Fresnel's), else the layer's
 * transmittance. */
INLINE float interface_transmittance(const Bsdf* b, float cosW, float eta)
{
    return 1.0f - cosW * cosW >= eta * eta ? 0.0f : layer_transmittance(b, cosW, eta);
}

/* The clear coat (KHR_materials_clearcoat): glTF's dielectric layer of
 * index 1.5, Schlick's Fresnel with F0 = 0.04, reflecting weight · F and
 * letting 1 − weight · F through to the lobes beneath, at each direction that
 * crosses it. The extension weighs the layers by F at the view direction
 * alone; a factor for both directions keeps the BSDF reciprocal, which light
 * paths need (pbrt-v4's and Enterprise PBR's layering do the same). */
INLINE float coat_fresnel(float cosI)
{
    float m = clamp(1.0f - cosI, 0.0f, 1.0f);
    float m2 = m * m;
    return 0.04f + 0.96f * m2 * m2 * m;
}

/* What a coat of weight `coat` lets through at cos θ = cosW (1 in scenes
 * without coats, so that the compiler drops it). */
INLINE float coat_through(float coat, float cosW)
{
#if SCENE_LOBES & LOBES_COAT
    return 1.0f - coat * coat_fresnel(fabs(cosW));
#else
    return 1.0f;
#endif
}

/* The sheen (KHR_materials_sheen) over the lobes beneath it: they are
 * scaled by 1 − s · E at each direction, E the sheen's directional albedo and
 * s = max(sheenColor) on that side, so that sheen and lobes beneath reflect
 * at most what arrives (glTF's albedo scaling, at both directions as for the
 * coat). */
INLINE float sheen_through(const Bsdf* b, float sheen, float cosW)
{
#if SCENE_LOBES & LOBE_SHEEN
    return 1.0f - sheen * sheen_albedo(b->sheenRoughness, fabs(cosW));
#else
    return 1.0f;
#endif
}

/* What the coat and the sheen let through to the lobes beneath at cos θ =
 * cosW, on wo's side or (back) the other. */
INLINE float layers_through(const Bsdf* b, bool back, float cosW)
{
    return coat_through(back ? b->coatBack : b->coat, cosW) * sheen_through(b, back ? b->sheenBack : b->sheen, cosW);
}

/* Lobe selection probabilities for a path arriving from direction w
 * (cos θ = cosW > 0, relative index eta, on wo's side or, back, the other),
 * proportional to each lobe's albedo estimate there: reflection,
 * transmission, diffuse, and the coat's and the sheen's in *coatProb and
 * *sheenProb. */
INLINE vec3 lobe_probabilities(const Bsdf* b, float cosW, float eta, bool back, float* coatProb, float* sheenProb)
{
    float layers = layers_through(b, back, cosW);
    float through = layer_transmittance(b, cosW, eta) * layers;
    float r = (b->lobes & LOBES_REFLECT) ? layers * luminance(reflectance(b, cosW, eta)) : 0.0f;
    /* Rough refraction keeps a floor: microfacets tilted towards w refract
     * even where the macro-surface reflects totally (through = 0 beyond the
     * critical angle), and a zero probability would zero its f and pdfs
     * there, breaking reciprocity with the other side. */
    float tThrough = ((b->lobes & LOBE_GGX_TRANSMISSION) && b->solid) ? fmax(through, 0.1f) : through;
    float t = (b->lobes & LOBES_TRANSMIT) ? tThrough * luminance(b->transmitColor) : 0.0f;
    float d = (b->lobes & LOBE_DIFFUSE) ? through * luminance(b->diffuseColor) : 0.0f;
#if SCENE_LOBES & LOBE_DIFFUSE_TRANSMISSION
    /* Both diffuse lobes see the layers at w alike, so diffuse transmission
     * takes a fixed share of their probability, whichever side w is on. */
    d += (b->lobes & LOBE_DIFFUSE_TRANSMISSION) ? through * luminance(b->diffuseTransmitColor) : 0.0f;
#endif
    float sum = r + t + d;
    /* Written out, not left at 0 to fold: a float + 0 or 0 / sum does not. */
#if SCENE_LOBES & LOBE_SHEEN
    float sh = (back ? b->sheenBack : b->sheen) > 0.0f
                   ? coat_through(back ? b->coatBack : b->coat, cosW) * luminance(b->sheenColor) *
                         sheen_albedo(b->sheenRoughness, cosW)
                   : 0.0f;
    sum += sh;
#endif
#if SCENE_LOBES & LOBES_COAT
    float c = (back ? b->coatBack : b->coat) * coat_fresnel(cosW);
    sum += c;
    *coatProb = sum > 0.0f ? c / sum : 0.0f;
#else
    *coatProb = 0.0f;
#endif
#if SCENE_LOBES & LOBE_SHEEN
    *sheenProb = sum > 0.0f ? sh / sum : 0.0f;
#else
    *sheenProb = 0.0f;
#endif
    return sum > 0.0f ? v3(r / sum, t / sum, d / sum) : v3s(0.0f);
}

/* What a material is at one surface point: its factors, times its textures
 * there where it has them (materials/texture.h: surface_material). */
typedef struct SurfaceMaterial {
    vec3 baseColor;
    float metallic, roughness, transmission;
    float specular;
    vec3 specularColor;
    float clearcoat, clearcoatRoughness;
    vec3 sheenColor;
    float sheenRoughness;
    float diffuseTransmission;
    vec3 diffuseTransmissionColor;
#ifdef HAS_ANISOTROPY
    float anisotropy;
    vec2 anisotropyDirection; /* in the tangent frame (tangent, bitangent) */
#endif
} SurfaceMaterial;

/* The factors alone (untextured). */
INLINE SurfaceMaterial material_factors(__global const Material* m)
{
    SurfaceMaterial s;
    s.baseColor = load3(m->baseColor);
    s.metallic = m->metallic;
    s.roughness = m->roughness;
    s.transmission = m->transmission;
    s.specular = m->specular;
    s.specularColor = load3(m->specularColor);
    s.clearcoat = m->clearcoat;
    s.clearcoatRoughness = m->clearcoatRoughness;
    s.sheenColor = load3(m->sheenColor);
    s.sheenRoughness = m->sheenRoughness;
    s.diffuseTransmission = m->diffuseTransmission;
    s.diffuseTransmissionColor = load3(m->diffuseTransmissionColor);
#ifdef HAS_ANISOTROPY
    s.anisotropy = m->anisotropy;
    s.anisotropyDirection = v2(m->anisotropyRotation[0], m->anisotropyRotation[1]);
#endif
    return s;
}

/* The BSDF at a hit seen from local direction wo (wo.z > 0 after the caller
 * flipped the frame); frontSide: wo is on the side the normal points to;
 * `at` what the material is there. */
INLINE Bsdf make_bsdf(__global const Material* m, const SurfaceMaterial* at, vec3 wo, bool frontSide)
{
    Bsdf b;
    b.lobes = m->lobes & SCENE_LOBES;
    vec3 base = at->baseColor;
    float alpha = at->roughness * at->roughness;
    b.alpha = fmax(alpha, 1e-3f);
#ifdef HAS_ANISOTROPY
    float strength2 = at->anisotropy * at->anisotropy;
    b.alphaT = fmax(alpha + (1.0f - alpha) * strength2, 1e-3f);
    b.stretchX = 1.0f; /* the local frame's x until set_stretch turns it */
    b.stretchY = 0.0f;
#endif
    b.solid = (b.lobes & (LOBES_TRANSMIT | LOBE_DIFFUSE_TRANSMISSION)) != 0u && !m->thinWalled;
    /* Opaque and thin-walled surfaces are two-sided: their Fresnel always
     * sees air → material. A refracting solid sees the inverse from inside. */
    b.eta = (b.solid && !frontSide) ? 1.0f / m->ior : m->ior;
    float dielectric = 1.0f - at->metallic;
    b.metallic = at->metallic;
    b.metalF0 = base;
    b.specular = m->ior == 1.0f ? 0.0f : dielectric * at->specular; /* index-matched: no reflection */
    b.specularTint = v3_scale(at->specularColor, b.specular);
    b.transmitColor = v3_scale(base, dielectric * at->transmission);
    float diffuse = dielectric * (1.0f - at->transmission);
#if SCENE_LOBES & LOBE_DIFFUSE_TRANSMISSION
    /* KHR_materials_diffuse_transmission splits the diffuse part between
     * reflection (base colour) and transmission (its own colour). */
    float dt = (b.lobes & LOBE_DIFFUSE_TRANSMISSION) ? at->diffuseTransmission : 0.0f;
    b.diffuseColor = v3_scale(base, diffuse * (1.0f - dt));
    b.diffuseTransmitColor = v3_scale(at->diffuseTransmissionColor, diffuse * dt);
    float dtLum = luminance(b.diffuseTransmitColor), diffuseLum = dtLum + luminance(b.diffuseColor);
    b.diffuseTransmitShare = diffuseLum > 0.0f ? dtLum / diffuseLum : 0.0f;
#else
    b.diffuseColor = v3_scale(base, diffuse);
    b.diffuseTransmitColor = v3s(0.0f);
    b.diffuseTransmitShare = 0.0f;
#endif
#if SCENE_LOBES & LOBES_COAT
    /* A refracting solid is coated outside; a two-sided surface on both faces. */
    float coat = (b.lobes & LOBES_COAT) ? at->clearcoat : 0.0f;
    b.coat = (b.solid && !frontSide) ? 0.0f : coat;
    b.coatBack = (b.solid && frontSide) ? 0.0f : coat;
    b.coatAlpha = fmax(at->clearcoatRoughness * at->clearcoatRoughness, 1e-3f);
#else
    b.coat = b.coatBack = 0.0f;
    b.coatAlpha = 1.0f;
#endif
#if SCENE_LOBES & LOBE_SHEEN
    /* Sided as the coat is. */
    float sheen = (b.lobes & LOBE_SHEEN) ? max_component(at->sheenColor) : 0.0f;
    b.sheen = (b.solid && !frontSide) ? 0.0f : sheen;
    b.sheenBack = (b.solid && frontSide) ? 0.0f : sheen;
    b.sheenColor = at->sheenColor;
    b.sheenRoughness = at->sheenRoughness;
#else
    b.sheen = b.sheenBack = 0.0f;
    b.sheenColor = v3s(0.0f);
    b.sheenRoughness = 1.0f;
#endif
    b.lobeProb = lobe_probabilities(&b, wo.z, b.eta, false, &b.coatProb, &b.sheenProb);
    return b;
}

/* Russian roulette survival probability for the bidirectional algorithms:
 * an upper bound of the material's albedo that does not depend on direction,
 * so the same probability enters the forward and the reverse pdfs and the
 * MIS weights of all techniques still sum to one. */
INLINE float continuation_probability(const Bsdf* b)
{
    vec3 albedo = v3_add(v3_add(v3_add(v3_scale(b->metalF0, b->metallic), b->specularTint), b->transmitColor),
                         b->diffuseColor);
#if SCENE_LOBES & LOBE_DIFFUSE_TRANSMISSION
    albedo = v3_add(albedo, b->diffuseTransmitColor);
#endif
    float bound = max_component(albedo);
    /* The layers' weights whichever side they are on, so that both sides agree. */
#if SCENE_LOBES & LOBES_COAT
    bound += fmax(b->coat, b->coatBack);
#endif
#if SCENE_LOBES & LOBE_SHEEN
    bound += fmax(b->sheen, b->sheenBack);
#endif
    return clamp(bound, 0.0f, 1.0f);
}

/* False when the material has only delta lobes (in this scene): then no
 * BSDF made from it has a nondelta lobe, and connections and merges at its
 * surface can be skipped before building one. */
INLINE bool material_has_nondelta(__global const Material* m)
{
    return (m->lobes & SCENE_LOBES & (LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_GGX_TRANSMISSION | LOBE_GGX_COAT |
                                          LOBE_SHEEN | LOBE_DIFFUSE_TRANSMISSION)) != 0u;
}

INLINE bool bsdf_is_black(const Bsdf* b)
{
    float sum = b->lobeProb.x + b->lobeProb.y + b->lobeProb.z;
#if SCENE_LOBES & LOBES_COAT
    sum += b->coatProb;
#endif
#if SCENE_LOBES & LOBE_SHEEN
    sum += b->sheenProb;
#endif
    return sum <= 0.0f;
}

/* Whether some lobe has a finite density, i.e. light sampling and
 * connections can contribute here. */
INLINE bool bsdf_has_nondelta(const Bsdf* b)
{
    return b->lobeProb.z > 0.0f || (b->lobeProb.x > 0.0f && (b->lobes & LOBE_GGX_REFLECTION)) ||
           (b->lobeProb.y > 0.0f && (b->lobes & LOBE_GGX_TRANSMISSION) && b->solid) ||
           (b->coatProb > 0.0f && (b->lobes & LOBE_GGX_COAT)) || b->sheenProb > 0.0f;
}

/* The microfacets of the base's reflection and transmission: GGX of α, or
 * with anisotropy (HAS_ANISOTROPY) of alphaT along the direction (stretchX,
 * stretchY) and α across it, directions turned into that direction's frame.
 * The coat stays isotropic. */
#ifdef HAS_ANISOTROPY
INLINE vec3 to_stretch(const Bsdf* b, vec3 w)
{
    return v3(b->stretchX * w.x + b->stretchY * w.y, b->stretchX * w.y - b->stretchY * w.x, w.z);
}
INLINE float base_d(const Bsdf* b, vec3 h) { return ggx_d_aniso(to_stretch(b, h), b->alphaT, b->alpha); }
INLINE float base_g(const Bsdf* b, vec3 wo, vec3 wi)
{
    return ggx_g_aniso(to_stretch(b, wo), to_stretch(b, wi), b->alphaT, b->alpha);
}
INLINE float base_visible_pdf(const Bsdf* b, vec3 w, vec3 h)
{
    return ggx_visible_pdf_aniso(to_stretch(b, w), to_stretch(b, h), b->alphaT, b->alpha);
}
INLINE vec3 base_sample_visible(const Bsdf* b, vec3 wo, float u1, float u2)
{
    vec3 h = ggx_sample_visible_aniso(to_stretch(b, wo), b->alphaT, b->alpha, u1, u2);
    return v3(b->stretchX * h.x - b->stretchY * h.y, b->stretchY * h.x + b->stretchX * h.y, h.z);
}

/* Turns the anisotropy towards direction (x, y) of the local frame (the
 * tangent frame's direction there: materials/surface_bsdf.h). */
INLINE void set_stretch(Bsdf* b, float x, float y)
{
    float length = sqrt(x * x + y * y);
    b->stretchX = length > 0.0f ? x / length : 1.0f;
    b->stretchY = length > 0.0f ? y / length : 0.0f;
}
#else
INLINE float base_d(const Bsdf* b, vec3 h) { return ggx_d(h, b->alpha); }
INLINE float base_g(const Bsdf* b, vec3 wo, vec3 wi) { return ggx_g(wo, wi, b->alpha); }
INLINE float base_visible_pdf(const Bsdf* b, vec3 w, vec3 h) { return ggx_visible_pdf(w, h, b->alpha); }
INLINE vec3 base_sample_visible(const Bsdf* b, vec3 wo, float u1, float u2)
{
    return ggx_sample_visible(wo, b->alpha, u1, u2);
}
#endif

/* Generalised half vector of refraction h ∝ wo + η·wi, oriented to +z. */
INLINE vec3 refraction_half_vector(vec3 wo, vec3 wi, float eta)
{
    vec3 h = v3_normalize(v3_add_scaled(wo, wi, eta));
    return h.z < 0.0f ? v3_neg(h) : h;
}

/* Jacobian dω_h/dω_i of refraction, |wi·h| / (wi·h + wo·h/η)² (Walter et al. 2007). */
INLINE float refraction_jacobian(float oh, float ih, float eta)
{
    float denom = ih + oh / eta;
    return fabs(ih) / (denom * denom);
}

/* f(wo, wi) of the non-delta lobes; *pdfFwd is the density of sampling wi
 * from wo, *pdfRev that of sampling wo from wi (bidirectional MIS). */
INLINE vec3 bsdf_eval(const Bsdf* b, vec3 wo, vec3 wi, bool adjoint, float* pdfFwd, float* pdfRev)
{
    vec3 f = v3s(0.0f);
    *pdfFwd = 0.0f;
    *pdfRev = 0.0f;
    if (wo.z <= 0.0f || wi.z == 0.0f)
        return f;
    if (wi.z > 0.0f) {
        /* Reflection: wi is on wo's side, sees the same η and layers. */
        float coatRev, sheenRev;
        vec3 probRev = lobe_probabilities(b, wi.z, b->eta, false, &coatRev, &sheenRev);
        /* What reaches the lobes beneath the coat and the sheen and comes back out. */
        float under = layers_through(b, false, wo.z) * layers_through(b, false, wi.z);
#if SCENE_LOBES & LOBE_DIFFUSE
        if (b->lobeProb.z > 0.0f) {
            /* Light enters and leaves through the dielectric layer: both
             * transmittances, so the lobe is reciprocal. */
            f = v3_add(f, v3_scale(b->diffuseColor, under * layer_transmittance(b, wo.z, b->eta) *
                                                        layer_transmittance(b, wi.z, b->eta) * INV_PI_F));
            float share = 1.0f - b->diffuseTransmitShare;
            *pdfFwd += b->lobeProb.z * share * wi.z * INV_PI_F;
            *pdfRev += probRev.z * share * wo.z * INV_PI_F;
        }
#endif
#if SCENE_LOBES & LOBE_GGX_REFLECTION
        if (b->lobeProb.x > 0.0f && (b->lobes & LOBE_GGX_REFLECTION)) {
            vec3 h = v3_normalize(v3_add(wo, wi));
            float cosH = v3_dot(wo, h);
            f = v3_add(f, v3_scale(reflectance(b, cosH, b->eta),
                                   under * base_d(b, h) * base_g(b, wo, wi) / (4.0f * wo.z * wi.z)));
            *pdfFwd += b->lobeProb.x * base_visible_pdf(b, wo, h) / (4.0f * cosH);
            *pdfRev += probRev.x * base_visible_pdf(b, wi, h) / (4.0f * cosH);
        }
#endif
#if SCENE_LOBES & LOBE_SHEEN
        if (b->sheenProb > 0.0f) { /* beneath the coat only; sampled as diffuse is */
            float value = coat_through(b->coat, wo.z) * coat_through(b->coat, wi.z) *
                          sheen_value(b->sheenRoughness, wo, wi);
            f = v3_add(f, v3_scale(b->sheenColor, value));
            *pdfFwd += b->sheenProb * wi.z * INV_PI_F;
            *pdfRev += sheenRev * wo.z * INV_PI_F;
        }
#endif
#if SCENE_LOBES & LOBE_GGX_COAT
        if (b->coatProb > 0.0f && (b->lobes & LOBE_GGX_COAT)) {
            vec3 h = v3_normalize(v3_add(wo, wi));
            float cosH = v3_dot(wo, h);
            f = v3_add(f, v3s(b->coat * coat_fresnel(cosH) * ggx_d(h, b->coatAlpha) *
                              ggx_g(wo, wi, b->coatAlpha) / (4.0f * wo.z * wi.z)));
            *pdfFwd += b->coatProb * ggx_visible_pdf(wo, h, b->coatAlpha) / (4.0f * cosH);
            *pdfRev += coatRev * ggx_visible_pdf(wi, h, b->coatAlpha) / (4.0f * cosH);
        }
#endif
    } else {
#if SCENE_LOBES & LOBE_GGX_TRANSMISSION
        if (b->lobeProb.y > 0.0f && (b->lobes & LOBE_GGX_TRANSMISSION) && b->solid) {
            vec3 h = refraction_half_vector(wo, wi, b->eta);
            float oh = v3_dot(wo, h), ih = v3_dot(wi, h);
            if (oh > 0.0f && ih < 0.0f) { /* a microfacet both directions see */
                float denom = ih + oh / b->eta;
                float T = layer_transmittance(b, oh, b->eta) * layers_through(b, false, wo.z) *
                          layers_through(b, true, wi.z);
                float value = base_d(b, h) * base_g(b, wo, wi) * fabs(ih * oh / (wi.z * wo.z * denom * denom));
                if (!adjoint)
                    value /= b->eta * b->eta;
                f = v3_add(f, v3_scale(b->transmitColor, T * value));
                *pdfFwd += b->lobeProb.y * base_visible_pdf(b, wo, h) * refraction_jacobian(oh, ih, b->eta);
                /* Reverse: from wi's side (mirrored so it is "above"), η
                 * inverts and the roles of the directions swap. */
                vec3 wiUp = v3(wi.x, wi.y, -wi.z), hUp = v3(-h.x, -h.y, h.z);
                float coatRev, sheenRev;
                vec3 probRev = lobe_probabilities(b, -wi.z, 1.0f / b->eta, true, &coatRev, &sheenRev);
                *pdfRev += probRev.y * base_visible_pdf(b, wiUp, hUp) *
                           refraction_jacobian(-ih, -oh, 1.0f / b->eta);
            }
        }
#endif
#if SCENE_LOBES & LOBE_DIFFUSE_TRANSMISSION
        if (b->diffuseTransmitShare > 0.0f) { /* even where wo cannot pass: pdfRev */
            /* Lambert through the surface and the layers on both sides (of
             * a solid, η inverts at wi). Into a solid it keeps refraction's
             * convention, as a rough interface would: the adjoint value
             * carries max(η², 1) and the radiance value that over η², so
             * f(wi, wo) = η² f(wo, wi) (generalised reciprocity). Inside,
             * only the cone within the critical angle passes, a 1/η² share
             * of the cosine-weighted hemisphere, so light entering from
             * outside keeps all of what the layers let through: with F̄ the
             * Fresnel reflectance averaged over that hemisphere,
             * η² (1 − F̄_inside) = 1 − F̄_outside. */
            float etaBack = b->solid ? 1.0f / b->eta : b->eta;
            float value = interface_transmittance(b, wo.z, b->eta) * layers_through(b, false, wo.z) *
                          interface_transmittance(b, -wi.z, etaBack) * layers_through(b, true, wi.z) * INV_PI_F;
            if (b->solid) {
                float eta2 = b->eta * b->eta;
                value *= adjoint ? fmax(eta2, 1.0f) : fmax(1.0f, 1.0f / eta2);
            }
            f = v3_add(f, v3_scale(b->diffuseTransmitColor, value));
            *pdfFwd += b->lobeProb.z * b->diffuseTransmitShare * -wi.z * INV_PI_F;
            float coatRev, sheenRev;
            vec3 probRev = lobe_probabilities(b, -wi.z, etaBack, true, &coatRev, &sheenRev);
            *pdfRev += probRev.z * b->diffuseTransmitShare * wo.z * INV_PI_F;
        }
#endif
    }
    return f;
}

/* Samples wi given wo with the lobe probabilities, then the lobe. Returns
 * false if no direction was produced (black BSDF, below the surface, TIR in
 * a rough transmission sample). u1 picks the lobe; u2, u3 sample it. */
INLINE bool bsdf_sample(const Bsdf* b, vec3 wo, float u1, float u2, float u3, bool adjoint, BsdfSample* s)
{
    if (wo.z <= 0.0f || bsdf_is_black(b))
        return false;
    float pR = b->lobeProb.x, pT = b->lobeProb.y;
    s->delta = false;
    if (u1 < pR) {
        if (b->lobes & LOBE_DELTA_REFLECTION) {
            s->wi = v3(-wo.x, -wo.y, wo.z);
            s->pdf = s->pdfRev = pR;
            s->delta = true;
            /* f·cos/pdf with f = R·δ/cos, through the layers both ways */
            float under = layers_through(b, false, wo.z) * layers_through(b, false, wo.z);
            s->weight = v3_scale(reflectance(b, wo.z, b->eta), under / pR);
            return true;
        }
#if SCENE_LOBES & LOBE_GGX_REFLECTION
        vec3 h = base_sample_visible(b, wo, u2, u3);
        s->wi = v3_sub(v3_scale(h, 2.0f * v3_dot(wo, h)), wo);
        if (s->wi.z <= 0.0f)
            return false;
#else
        return false;
#endif
    } else if (u1 < pR + pT) {
        if ((b->lobes & LOBE_DELTA_TRANSMISSION) || !b->solid) {
            float T = layer_transmittance(b, wo.z, b->eta) * layers_through(b, false, wo.z);
            s->delta = true;
            s->pdf = s->pdfRev = pT;
            if (!b->solid) { /* thin-walled: straight through */
                s->wi = v3_neg(wo);
                s->weight = v3_scale(b->transmitColor, T * layers_through(b, true, wo.z) / pT);
                return true;
            }
            if (!refract_direction(wo, v3(0.0f, 0.0f, 1.0f), b->eta, &s->wi))
                return false; /* TIR: T = 0 here anyway */
            float scale = layers_through(b, true, s->wi.z) * (adjoint ? 1.0f : 1.0f / (b->eta * b->eta));
            s->weight = v3_div(v3_scale(b->transmitColor, T * scale), pT);
            return true;
        }
#if SCENE_LOBES & LOBE_GGX_TRANSMISSION
        vec3 h = base_sample_visible(b, wo, u2, u3);
        if (!refract_direction(wo, h, b->eta, &s->wi) || s->wi.z >= 0.0f)
            return false;
#else
        return false;
#endif
#if SCENE_LOBES & LOBES_COAT
    } else if (u1 >= 1.0f - b->coatProb) {
        if (b->lobes & LOBE_DELTA_COAT) {
            s->wi = v3(-wo.x, -wo.y, wo.z);
            s->pdf = s->pdfRev = b->coatProb;
            s->delta = true;
            s->weight = v3s(b->coat * coat_fresnel(wo.z) / b->coatProb);
            return true;
        }
        vec3 h = ggx_sample_visible(wo, b->coatAlpha, u2, u3);
        s->wi = v3_sub(v3_scale(h, 2.0f * v3_dot(wo, h)), wo);
        if (s->wi.z <= 0.0f)
            return false;
#endif
    } else { /* diffuse, diffuse transmission (the first part of the range) or sheen */
        s->wi = sample_cosine_hemisphere(u2, u3);
        if (s->wi.z <= 0.0f)
            return false;
#if SCENE_LOBES & LOBE_DIFFUSE_TRANSMISSION
        if (u1 < pR + pT + b->lobeProb.z * b->diffuseTransmitShare)
            s->wi.z = -s->wi.z;
#endif
    }
    vec3 f = bsdf_eval(b, wo, s->wi, adjoint, &s->pdf, &s->pdfRev);
    if (!(s->pdf > 0.0f))
        return false;
    s->weight = v3_scale(f, fabs(s->wi.z) / s->pdf);
    return true;
}

#endif
