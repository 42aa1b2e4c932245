/* Light selection (by power); sampling from a surface point for next-event
 * estimation and the density with which that would have produced a direction
 * found by BSDF sampling (for MIS); and emission sampling — a point and a
 * direction leaving the light — with its densities, which light sub-paths
 * start from. Light types the scene lacks are compiled out. */
#ifndef WAVEVCM_LIGHTS_H
#define WAVEVCM_LIGHTS_H

#include "core/ray.h"
#include "core/sampling.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

typedef struct LightSample {
    float3 direction; /* unit, from the shading point towards the light */
    float distance;   /* INFINITY for directional and background lights */
    float3 radiance;  /* arriving along -direction: f·radiance·|cos|/pdf is the estimate */
    float pdf;        /* solid angle density including selection; delta lights: the selection probability */
    bool delta;
    int type;         /* LIGHT_* */
    float3 lightPoint, lightNormal, lightError; /* triangle lights: for the shadow ray's far end */
    /* For the bidirectional MIS (mis.h): the density of having sampled this
     * direction here (directPdfW; for point and spot lights distance², as in
     * SmallVCM, since their intensity is not divided by it), that of the
     * light emitting the ray towards p (emissionPdfW), both with the
     * selection probability, and the cosine at the light (1 without a surface). */
    float directPdfW, emissionPdfW, cosAtLight;
} LightSample;

/* The light whose CDF interval holds u (binary search). */
INLINE int select_light(__global const float* cdf, int count, float u)
{
    int lo = 0, hi = count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (cdf[mid + 1] <= u)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* glTF spot cone: squared linear ramp between the outer and inner cone. */
INLINE float spot_falloff(const Light* l, float cosAngle)
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

/* Density of sampling direction `d` from the background light (uniform sphere). */
INLINE float background_light_pdf(float pmf) { return pmf * (0.25f * INV_PI_F); }

#ifdef HAS_EMISSIVE_TRIANGLES
/* A uniform point on an emissive triangle, its error bound and the
 * triangle's (emitting) geometric normal. */
INLINE float3 sample_triangle_point(__global const float4* triVertices, int triangle, float2 u, float3* error,
                                    float3* normal)
{
    float3 v0 = triVertices[3 * triangle].xyz, v1 = triVertices[3 * triangle + 1].xyz,
           v2 = triVertices[3 * triangle + 2].xyz;
    float2 b = sample_triangle(u);
    *normal = normalize(cross(v1 - v0, v2 - v0));
    return surface_point(v0, v1, v2, b.x, b.y, error);
}
#endif

INLINE bool sample_light(__global const Light* lights, __global const float* cdf,
                         __global const float4* triVertices, __constant const SceneInfo* scene, float3 p, float3 u,
                         LightSample* s)
{
    int lightCount = scene->lightCount;
    if (lightCount == 0)
        return false;
    Light l = lights[select_light(cdf, lightCount, u.x)];
    s->delta = false;
    s->distance = INFINITY;
    s->type = l.type;
    switch (l.type) {
#ifdef HAS_EMISSIVE_TRIANGLES
    case LIGHT_TRIANGLE: {
        float3 n;
        float3 q = sample_triangle_point(triVertices, l.triangle, u.yz, &s->lightError, &n);
        float3 d = q - p;
        float dist = length(d);
        if (!(dist > 0.0f))
            return false;
        s->direction = d / dist;
        float cosLight = -dot(s->direction, n); /* one-sided: emits along n only */
        if (cosLight <= 0.0f)
            return false;
        s->distance = dist;
        s->pdf = triangle_light_pdf(l.pmf, l.area, dist, cosLight);
        s->radiance = vload3(0, l.emission);
        s->lightPoint = q;
        s->lightNormal = n;
        s->directPdfW = s->pdf;
        s->emissionPdfW = l.pmf / l.area * cosLight * INV_PI_F;
        s->cosAtLight = cosLight;
        return s->pdf > 0.0f && isfinite(s->pdf);
    }
#endif
#ifdef HAS_POINT_LIGHTS
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        float3 d = vload3(0, l.position) - p;
        float dist2 = dot(d, d);
        if (!(dist2 > 0.0f))
            return false;
        float dist = sqrt(dist2);
        s->direction = d / dist;
        s->distance = dist;
        float falloff = l.type == LIGHT_SPOT ? spot_falloff(&l, -dot(s->direction, vload3(0, l.direction))) : 1.0f;
        s->radiance = vload3(0, l.emission) * (falloff / dist2);
        s->pdf = l.pmf;
        s->delta = true;
        s->directPdfW = l.pmf * dist2;
        s->emissionPdfW = l.pmf * (l.type == LIGHT_SPOT ? 1.0f / (2.0f * PI_F * (1.0f - l.cosOuterCone)) : 0.25f * INV_PI_F);
        s->cosAtLight = 1.0f;
        return falloff > 0.0f;
    }
#endif
#ifdef HAS_DIRECTIONAL_LIGHTS
    case LIGHT_DIRECTIONAL:
        s->direction = -vload3(0, l.direction);
        s->radiance = vload3(0, l.emission);
        s->pdf = l.pmf;
        s->delta = true;
        s->directPdfW = l.pmf;
        s->emissionPdfW = l.pmf / (PI_F * scene->radius * scene->radius);
        s->cosAtLight = 1.0f;
        return true;
#endif
#ifdef HAS_BACKGROUND
    case LIGHT_BACKGROUND:
        s->direction = sample_uniform_sphere(u.yz);
        s->radiance = vload3(0, l.emission);
        s->pdf = background_light_pdf(l.pmf);
        s->directPdfW = s->pdf;
        s->emissionPdfW = s->pdf / (PI_F * scene->radius * scene->radius);
        s->cosAtLight = 1.0f;
        return true;
#endif
    default:
        return false;
    }
}

/* A ray leaving a light. The power estimate it carries is
 * radiance · cosAtLight / (pdfPosition · pdfDirection); averaged over samples
 * it is the light's power divided by its selection probability. */
typedef struct EmissionSample {
    float3 position;
    float3 direction;   /* unit, the way the light travels */
    float3 radiance;    /* radiance (triangle, background), intensity (point, spot), irradiance (directional) */
    float pdfPosition;  /* area density including selection; 1 · selection for point and spot lights */
    float pdfDirection; /* solid-angle density; 1 for directional lights */
    float cosAtLight;   /* 1 for lights without a surface */
    float directPdf;    /* density of next-event estimation choosing this point (area; solid angle for
                           infinite lights), with selection; for MIS */
    bool deltaPosition, deltaDirection;
    bool finite;        /* not directional or background */
    float3 normal, positionError; /* triangle lights: where the ray leaves from */
    int light;
} EmissionSample;

/* Sampling the ray's start and direction. u.x selects the light, u.yz the
 * position, v the direction. Infinite lights (directional, background) start
 * their rays on a disk of the bounding sphere's radius, facing the scene,
 * just outside the sphere. */
INLINE bool sample_emission(__global const Light* lights, __global const float* cdf,
                            __global const float4* triVertices, __constant const SceneInfo* scene, float3 u,
                            float2 v, EmissionSample* e)
{
    int lightCount = scene->lightCount;
    if (lightCount == 0)
        return false;
    e->light = select_light(cdf, lightCount, u.x);
    Light l = lights[e->light];
    e->radiance = vload3(0, l.emission);
    e->cosAtLight = 1.0f;
    e->deltaPosition = false;
    e->deltaDirection = false;
    e->finite = true;
    e->positionError = (float3)(0.0f);
    float3 centre = vload3(0, scene->center);
    float radius = scene->radius;
    switch (l.type) {
#ifdef HAS_EMISSIVE_TRIANGLES
    case LIGHT_TRIANGLE: {
        e->position = sample_triangle_point(triVertices, l.triangle, u.yz, &e->positionError, &e->normal);
        Frame f = frame_from_normal(e->normal);
        float3 dirLocal = sample_cosine_hemisphere(v);
        e->direction = to_world(&f, dirLocal);
        e->cosAtLight = dirLocal.z;
        e->pdfPosition = l.pmf / l.area;
        e->pdfDirection = dirLocal.z * INV_PI_F;
        e->directPdf = e->pdfPosition;
        return dirLocal.z > 0.0f;
    }
#endif
#ifdef HAS_POINT_LIGHTS
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        e->position = vload3(0, l.position);
        e->pdfPosition = l.pmf;
        e->directPdf = l.pmf;
        e->deltaPosition = true;
        if (l.type == LIGHT_POINT) {
            e->direction = sample_uniform_sphere(v);
            e->pdfDirection = 0.25f * INV_PI_F;
            return true;
        }
        Frame f = frame_from_normal(vload3(0, l.direction));
        float3 dirLocal = sample_uniform_cone(v, l.cosOuterCone);
        e->direction = to_world(&f, dirLocal);
        e->pdfDirection = 1.0f / (2.0f * PI_F * (1.0f - l.cosOuterCone));
        e->radiance *= spot_falloff(&l, dirLocal.z);
        return true;
    }
#endif
#if defined(HAS_DIRECTIONAL_LIGHTS) || defined(HAS_BACKGROUND)
#ifdef HAS_DIRECTIONAL_LIGHTS
    case LIGHT_DIRECTIONAL:
#endif
#ifdef HAS_BACKGROUND
    case LIGHT_BACKGROUND:
#endif
    {
        e->finite = false;
        if (l.type == LIGHT_DIRECTIONAL) {
            e->direction = vload3(0, l.direction);
            e->pdfDirection = 1.0f;
            e->deltaDirection = true;
            e->directPdf = l.pmf;
        } else {
            e->direction = -sample_uniform_sphere(v);
            e->pdfDirection = 0.25f * INV_PI_F;
            e->directPdf = background_light_pdf(l.pmf);
        }
        Frame f = frame_from_normal(e->direction);
        float2 d = sample_disk(u.yz) * radius;
        e->position = centre - e->direction * radius + d.x * f.s + d.y * f.t;
        e->pdfPosition = l.pmf / (PI_F * radius * radius);
        return true;
    }
#endif
    default:
        return false;
    }
}

/* For MIS at a camera path's hit on an emissive triangle (front side, cosine
 * cosLight): the densities of next-event estimation choosing that point
 * (area) and of the light emitting the ray. */
INLINE void triangle_hit_pdfs(float pmf, float area, float cosLight, float* directPdfA, float* emissionPdfW)
{
    *directPdfA = pmf / area;
    *emissionPdfW = *directPdfA * cosLight * INV_PI_F;
}

/* The same for a ray escaping to the background (solid angle for the direct
 * density; the emission density adds the disk the ray would start from). */
INLINE void background_hit_pdfs(float pmf, float sceneRadius, float* directPdfW, float* emissionPdfW)
{
    *directPdfW = background_light_pdf(pmf);
    *emissionPdfW = *directPdfW / (PI_F * sceneRadius * sceneRadius);
}

/* Whether a connection between surface points p and q leaves each on a side
 * that rounding cannot flip: each point lies farther from the other's
 * tangent plane than the two error bounds reach along that plane's normal.
 * Two points of one plane, one on each side of a thin wall, fail it: their
 * sides are decided by rounding, and the shadow ray between them, parallel
 * to the wall within ~1e-7, slips through it. Such connections carry
 * cos θ ≈ 0 at both ends; dropping them costs nothing measurable. */
INLINE bool connection_resolved(float3 p, float3 pError, float3 np, float3 q, float3 qError, float3 nq)
{
    float3 d = q - p, error = pError + qError;
    return fabs(dot(d, np)) > dot(fabs(np), error) && fabs(dot(d, nq)) > dot(fabs(nq), error);
}

/* Ray from p towards a point `target` with error bound `targetError` on a
 * surface with normal targetNormal: both ends offset, the segment stopping
 * just short of the far end (pbrt-v4 SpawnRayTo). */
INLINE Ray ray_between(float3 p, float3 pError, float3 n, float3 target, float3 targetError, float3 targetNormal)
{
    Ray r;
    r.origin = offset_ray_origin(p, pError, n, target - p);
    float3 end = offset_ray_origin(target, targetError, targetNormal, p - target);
    r.direction = end - r.origin;
    r.tMax = 1.0f - 1e-4f;
    return r;
}

/* connection_resolved for a light sample at a surface hit: only a triangle
 * light has a surface, and so a side, at the far end. */
INLINE bool light_sample_resolved(float3 p, float3 pError, float3 ng, const LightSample* ls)
{
    return ls->type != LIGHT_TRIANGLE || connection_resolved(p, pError, ng, ls->lightPoint, ls->lightError, ls->lightNormal);
}

/* The shadow ray of a light sample taken at a surface hit. */
INLINE Ray shadow_ray_to_light(float3 p, float3 pError, float3 ng, const LightSample* ls)
{
    if (isinf(ls->distance))
        return spawn_ray(p, pError, ng, ls->direction);
    if (ls->type == LIGHT_TRIANGLE)
        return ray_between(p, pError, ng, ls->lightPoint, ls->lightError, ls->lightNormal);
    /* a point light: nothing at the far end to avoid */
    return ray_between(p, pError, ng, p + ls->direction * ls->distance, (float3)(0.0f), -ls->direction);
}

#endif
