/* Light selection (by power); sampling from a surface point for next-event
 * estimation and the density with which that would have produced a direction
 * found by BSDF sampling (for MIS); and emission sampling — a point and a
 * direction leaving the light — with its densities, which light sub-paths
 * start from. Light types the scene lacks are compiled out. */
#ifndef WAVEVCM_LIGHTS_H
#define WAVEVCM_LIGHTS_H

#include "core/ray.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/vec3.h"
#include "interface/inline.h"
#include "interface/shared_types.h"
#include "lights/environment.h"

typedef struct LightSample {
    vec3 direction; /* unit, from the shading point towards the light */
    float distance; /* INFINITY for directional and background lights */
    vec3 radiance;  /* arriving along -direction: f·radiance·|cos|/pdf is the estimate */
    float pdf;      /* solid angle density including selection; delta lights: the selection probability */
    bool delta;
    int type;       /* LIGHT_* */
    vec3 lightPoint, lightNormal, lightError; /* triangle lights: for the shadow ray's far end */
    int triangle;   /* triangle lights: the triangle and the point's barycentrics (emissive textures) */
    vec2 bary;
    /* For the bidirectional MIS (mis.h): the density of having sampled this
     * direction here (directPdfW; for point and spot lights distance², as in
     * SmallVCM, since their intensity is not divided by it), that of the
     * light emitting the ray towards p (emissionPdfW), both with the
     * selection probability, and the cosine at the light (1 without a surface). */
    float directPdfW, emissionPdfW, cosAtLight;
} LightSample;

/* Steps of the light selection's binary search: enough bits for the largest
 * light index. The renderer sets it for its scene's light table, so the
 * search is a fixed sequence of steps (a data-dependent loop would keep PoCL
 * from vectorizing the kernel); the default covers any table. */
#ifndef LIGHT_SELECT_STEPS
#define LIGHT_SELECT_STEPS 31
#endif

/* The light whose CDF interval holds u (cdf[0] = 0). */
INLINE int select_light(__global const float* cdf, int count, float u)
{
    return cdf_bin(cdf, count, u, LIGHT_SELECT_STEPS);
}

/* Whether a light of type `type` is one of `types`, a set of LIGHT_BIT(t).
 * Sampling branches on the light's type with these tests, not with
 * comparisons: LLVM turns a chain of equality tests on one value into a
 * switch, and its loop vectorizer refuses a loop with a switch (PoCL's SIMD
 * work-item loops, core/simd.h). A test of one bit of a mask is not folded
 * back into a comparison. */
#define LIGHT_BIT(type) (1u << (type))
INLINE bool light_is(int type, uint types) { return ((1u << (uint)type) & types) != 0u; }

/* glTF spot cone: squared linear ramp between the outer and inner cone. */
INLINE float spot_falloff(__global const Light* l, float cosAngle)
{
    float t = clamp((cosAngle - l->cosOuterCone) / fmax(1e-4f, l->cosInnerCone - l->cosOuterCone), 0.0f, 1.0f);
    return t * t;
}

/* Density (solid angle at p) of sampling triangle light `l` towards a point
 * at distance `dist` whose normal makes cosine `cosLight` with the direction. */
INLINE float triangle_light_pdf(float pmf, float area, float dist, float cosLight)
{
    return cosLight > 0.0f ? pmf * dist * dist / (cosLight * area) : 0.0f;
}

/* The background's radiance along d, and the density (solid angle, with
 * selection probability pmf) with which light sampling picks d: the
 * environment map's, or the uniform sphere's. */
INLINE vec3 background_radiance(__global const Light* bg, __constant const SceneInfo* scene, const Environment* env,
                                vec3 d, float* pdfW)
{
    vec3 emission = load3(bg->emission);
#ifdef HAS_ENVIRONMENT_MAP
    float envPdf;
    vec3 radiance = v3_mul(emission, env_radiance(env, scene, d, &envPdf));
    *pdfW = bg->pmf * envPdf;
    return radiance;
#else
    *pdfW = bg->pmf * (0.25f * INV_PI_F);
    return emission;
#endif
}

/* A direction towards the background: its radiance, and the density with
 * selection probability. False where the density vanishes. */
INLINE bool sample_background(__global const Light* bg, __constant const SceneInfo* scene, const Environment* env,
                              float u1, float u2, vec3* d, vec3* radiance, float* pdfW)
{
    *radiance = load3(bg->emission);
#ifdef HAS_ENVIRONMENT_MAP
    vec3 texel;
    float envPdf;
    bool ok = env_sample(env, scene, u1, u2, d, &texel, &envPdf);
    *radiance = v3_mul(*radiance, texel);
    *pdfW = bg->pmf * envPdf;
    return ok;
#else
    *d = sample_uniform_sphere(u1, u2);
    *pdfW = bg->pmf * (0.25f * INV_PI_F);
    return true;
#endif
}

#ifdef HAS_EMISSIVE_TRIANGLES
/* A uniform point on an emissive triangle, its barycentrics, error bound and
 * the triangle's (emitting) geometric normal. */
INLINE vec3 sample_triangle_point(__global const float4* triVertices, int triangle, float u1, float u2, vec2* bary,
                                  vec3* error, vec3* normal)
{
    vec3 v0 = load_vec3(triVertices, 3 * triangle), v1 = load_vec3(triVertices, 3 * triangle + 1),
         v2 = load_vec3(triVertices, 3 * triangle + 2);
    *bary = sample_triangle(u1, u2);
    *normal = v3_normalize(v3_cross(v3_sub(v1, v0), v3_sub(v2, v0)));
    return surface_point(v0, v1, v2, bary->x, bary->y, error);
}
#endif

/* Next-event estimation: a light chosen by power with u.x, a point or
 * direction on it with u.y, u.z, seen from p. */
INLINE bool sample_light(__global const Light* lights, __global const float* cdf,
                         __global const float4* triVertices, __constant const SceneInfo* scene, const Environment* env,
                         vec3 p, Uniform4 u, LightSample* s)
{
    int lightCount = scene->lightCount;
    if (lightCount == 0)
        return false;
    __global const Light* l = &lights[select_light(cdf, lightCount, u.x)];
    int type = l->type;
    s->delta = false;
    s->distance = INFINITY;
    s->type = type;
    s->radiance = load3(l->emission);
    s->cosAtLight = 1.0f;
#ifdef HAS_EMISSIVE_TRIANGLES
    if (light_is(type, LIGHT_BIT(LIGHT_TRIANGLE))) {
        vec3 n;
        vec3 q = sample_triangle_point(triVertices, l->triangle, u.y, u.z, &s->bary, &s->lightError, &n);
        s->triangle = l->triangle;
        vec3 d = v3_sub(q, p);
        float dist = v3_length(d);
        s->direction = v3_div(d, dist);
        float cosLight = -v3_dot(s->direction, n); /* one-sided: emits along n only */
        if (l->sides == 2 && cosLight < 0.0f) { /* its back face, which emits too */
            cosLight = -cosLight;
            n = v3_neg(n);
        }
        s->distance = dist;
        s->pdf = triangle_light_pdf(l->pmf, l->area, dist, cosLight);
        s->lightPoint = q;
        s->lightNormal = n;
        s->directPdfW = s->pdf;
        s->emissionPdfW = l->pmf / l->area * cosLight * INV_PI_F / (float)l->sides;
        s->cosAtLight = cosLight;
        return dist > 0.0f && cosLight > 0.0f && s->pdf > 0.0f && isfinite(s->pdf);
    }
#endif
#ifdef HAS_POINT_LIGHTS
    if (light_is(type, LIGHT_BIT(LIGHT_POINT) | LIGHT_BIT(LIGHT_SPOT))) {
        vec3 d = v3_sub(load3(l->position), p);
        float dist2 = v3_dot(d, d);
        float dist = sqrt(dist2);
        s->direction = v3_div(d, dist);
        s->distance = dist;
        float falloff = type == LIGHT_SPOT ? spot_falloff(l, -v3_dot(s->direction, load3(l->direction))) : 1.0f;
        s->radiance = v3_scale(s->radiance, falloff / dist2);
        s->pdf = l->pmf;
        s->delta = true;
        s->directPdfW = l->pmf * dist2;
        s->emissionPdfW = l->pmf * (type == LIGHT_SPOT ? 1.0f / (2.0f * PI_F * (1.0f - l->cosOuterCone)) : 0.25f * INV_PI_F);
        return dist2 > 0.0f && falloff > 0.0f;
    }
#endif
#ifdef HAS_DIRECTIONAL_LIGHTS
    if (light_is(type, LIGHT_BIT(LIGHT_DIRECTIONAL))) {
        s->direction = v3_neg(load3(l->direction));
        s->pdf = l->pmf;
        s->delta = true;
        s->directPdfW = l->pmf;
        s->emissionPdfW = l->pmf / (PI_F * scene->radius * scene->radius);
        return true;
    }
#endif
#ifdef HAS_BACKGROUND
    if (light_is(type, LIGHT_BIT(LIGHT_BACKGROUND))) {
        bool ok = sample_background(l, scene, env, u.y, u.z, &s->direction, &s->radiance, &s->pdf);
        s->directPdfW = s->pdf;
        s->emissionPdfW = s->pdf / (PI_F * scene->radius * scene->radius);
        return ok;
    }
#endif
    return false;
}

/* A ray leaving a light. The power estimate it carries is
 * radiance · cosAtLight / (pdfPosition · pdfDirection); averaged over samples
 * it is the light's power divided by its selection probability. */
typedef struct EmissionSample {
    vec3 position;
    vec3 direction;     /* unit, the way the light travels */
    vec3 radiance;      /* radiance (triangle, background), intensity (point, spot), irradiance (directional) */
    float pdfPosition;  /* area density including selection; 1 · selection for point and spot lights */
    float pdfDirection; /* solid-angle density; 1 for directional lights */
    float cosAtLight;   /* 1 for lights without a surface */
    float directPdf;    /* density of next-event estimation choosing this point (area; solid angle for
                           infinite lights), with selection; for MIS */
    bool deltaPosition, deltaDirection;
    bool finite;        /* not directional or background */
    vec3 normal, positionError; /* triangle lights: where the ray leaves from */
    vec2 bary;                  /* triangle lights: the point's barycentrics (emissive textures) */
    int light;
} EmissionSample;

/* Sampling the ray's start and direction. u.x selects the light, u.y, u.z
 * the position, v.y, v.z the direction. Infinite lights (directional,
 * background) start their rays on a disk of the bounding sphere's radius,
 * facing the scene, just outside the sphere. */
INLINE bool sample_emission(__global const Light* lights, __global const float* cdf,
                            __global const float4* triVertices, __constant const SceneInfo* scene,
                            const Environment* env, Uniform4 u, Uniform4 v, EmissionSample* e)
{
    int lightCount = scene->lightCount;
    if (lightCount == 0)
        return false;
    e->light = select_light(cdf, lightCount, u.x);
    __global const Light* l = &lights[e->light];
    int type = l->type;
    e->radiance = load3(l->emission);
    e->cosAtLight = 1.0f;
    e->deltaPosition = false;
    e->deltaDirection = false;
    e->finite = true;
    e->positionError = v3s(0.0f);
    vec3 centre = load3c(scene->center);
    float radius = scene->radius;
#ifdef HAS_EMISSIVE_TRIANGLES
    if (light_is(type, LIGHT_BIT(LIGHT_TRIANGLE))) {
        e->position =
            sample_triangle_point(triVertices, l->triangle, u.y, u.z, &e->bary, &e->positionError, &e->normal);
        /* Two-sided: either face with probability 1/2, v.y reused for the direction. */
        float ux = v.y;
        if (l->sides == 2) {
            bool back = ux >= 0.5f;
            ux = back ? 2.0f * ux - 1.0f : 2.0f * ux;
            e->normal = back ? v3_neg(e->normal) : e->normal;
        }
        Frame f = frame_from_normal(e->normal);
        vec3 dirLocal = sample_cosine_hemisphere(ux, v.z);
        e->direction = to_world(&f, dirLocal);
        e->cosAtLight = dirLocal.z;
        e->pdfPosition = l->pmf / l->area;
        e->pdfDirection = dirLocal.z * INV_PI_F / (float)l->sides;
        e->directPdf = e->pdfPosition;
        return dirLocal.z > 0.0f;
    }
#endif
#ifdef HAS_POINT_LIGHTS
    if (light_is(type, LIGHT_BIT(LIGHT_POINT) | LIGHT_BIT(LIGHT_SPOT))) {
        e->position = load3(l->position);
        e->pdfPosition = l->pmf;
        e->directPdf = l->pmf;
        e->deltaPosition = true;
        if (type == LIGHT_POINT) {
            e->direction = sample_uniform_sphere(v.y, v.z);
            e->pdfDirection = 0.25f * INV_PI_F;
            return true;
        }
        Frame f = frame_from_normal(load3(l->direction));
        vec3 dirLocal = sample_uniform_cone(v.y, v.z, l->cosOuterCone);
        e->direction = to_world(&f, dirLocal);
        e->pdfDirection = 1.0f / (2.0f * PI_F * (1.0f - l->cosOuterCone));
        e->radiance = v3_scale(e->radiance, spot_falloff(l, dirLocal.z));
        return true;
    }
#endif
#if defined(HAS_DIRECTIONAL_LIGHTS) || defined(HAS_BACKGROUND)
    if (light_is(type, LIGHT_BIT(LIGHT_DIRECTIONAL) | LIGHT_BIT(LIGHT_BACKGROUND))) {
        e->finite = false;
        bool ok = true;
        if (type == LIGHT_DIRECTIONAL) {
            e->direction = load3(l->direction);
            e->pdfDirection = 1.0f;
            e->deltaDirection = true;
            e->directPdf = l->pmf;
        } else {
            /* the light travels against the direction towards the background */
            vec3 towards;
            ok = sample_background(l, scene, env, v.y, v.z, &towards, &e->radiance, &e->directPdf);
            e->direction = v3_neg(towards);
            e->pdfDirection = l->pmf > 0.0f ? e->directPdf / l->pmf : 0.0f;
        }
        Frame f = frame_from_normal(e->direction);
        vec2 d = sample_disk(u.y, u.z);
        e->position = v3_add(v3_add(v3_sub(centre, v3_scale(e->direction, radius)), v3_scale(f.s, d.x * radius)),
                             v3_scale(f.t, d.y * radius));
        e->pdfPosition = l->pmf / (PI_F * radius * radius);
        return ok;
    }
#endif
    return false;
}

/* For MIS at a camera path's hit on an emissive triangle (front side, cosine
 * cosLight): the densities of next-event estimation choosing that point
 * (area) and of the light emitting the ray. */
INLINE void triangle_hit_pdfs(__global const Light* l, float cosLight, float* directPdfA, float* emissionPdfW)
{
    *directPdfA = l->pmf / l->area;
    *emissionPdfW = *directPdfA * cosLight * INV_PI_F / (float)l->sides;
}

/* The same for a ray escaping to the background, given the density
 * (solid angle, with selection) of light sampling picking its direction:
 * the emission density adds the disk the ray would start from. */
INLINE void background_hit_pdfs(float directPdfW, float sceneRadius, float* emissionPdfW)
{
    *emissionPdfW = directPdfW / (PI_F * sceneRadius * sceneRadius);
}

/* Whether a connection between surface points p and q leaves each on a side
 * that rounding cannot flip: each point lies farther from the other's
 * tangent plane than the two error bounds reach along that plane's normal.
 * Two points of one plane, one on each side of a thin wall, fail it: their
 * sides are decided by rounding, and the shadow ray between them, parallel
 * to the wall within ~1e-7, slips through it. Such connections carry
 * cos θ ≈ 0 at both ends; dropping them costs nothing measurable. */
INLINE bool connection_resolved(vec3 p, vec3 pError, vec3 np, vec3 q, vec3 qError, vec3 nq)
{
    vec3 d = v3_sub(q, p), error = v3_add(pError, qError);
    return fabs(v3_dot(d, np)) > v3_dot(v3_abs(np), error) && fabs(v3_dot(d, nq)) > v3_dot(v3_abs(nq), error);
}

/* Ray from p towards a point `target` with error bound `targetError` on a
 * surface with normal targetNormal: both ends offset, the segment stopping
 * just short of the far end (pbrt-v4 SpawnRayTo). */
INLINE Ray ray_between(vec3 p, vec3 pError, vec3 n, vec3 target, vec3 targetError, vec3 targetNormal)
{
    Ray r;
    r.origin = offset_ray_origin(p, pError, n, v3_sub(target, p));
    vec3 end = offset_ray_origin(target, targetError, targetNormal, v3_sub(p, target));
    r.direction = v3_sub(end, r.origin);
    r.tMax = 1.0f - 1e-4f;
    return r;
}

/* connection_resolved for a light sample at a surface hit: only a triangle
 * light has a surface, and so a side, at the far end. */
INLINE bool light_sample_resolved(vec3 p, vec3 pError, vec3 ng, const LightSample* ls)
{
    return ls->type != LIGHT_TRIANGLE || connection_resolved(p, pError, ng, ls->lightPoint, ls->lightError, ls->lightNormal);
}

/* The shadow ray of a light sample taken at a surface hit: to the point on a
 * triangle light, to a point light (nothing at the far end to avoid), or
 * along the direction of an infinite light. */
INLINE Ray shadow_ray_to_light(vec3 p, vec3 pError, vec3 ng, const LightSample* ls)
{
    if (isinf(ls->distance))
        return spawn_ray(p, pError, ng, ls->direction);
    if (ls->type == LIGHT_TRIANGLE)
        return ray_between(p, pError, ng, ls->lightPoint, ls->lightError, ls->lightNormal);
    return ray_between(p, pError, ng, v3_add_scaled(p, ls->direction, ls->distance), v3s(0.0f), v3_neg(ls->direction));
}

#endif
