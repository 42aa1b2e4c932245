/* KHR_materials_volume absorption, by the Beer-Lambert law as glTF defines
 * it: light that crosses length t inside a refracting solid keeps
 * attenuationColor^(t / attenuationDistance) of itself. A segment lies
 * inside a solid where it runs from the surface into the side its geometric
 * normal faces away from (glTF's counter-clockwise front face looks out of
 * a closed mesh); solids are taken not to nest or overlap. Every segment
 * type applies it — extended rays (extend.cl), next-event shadow rays,
 * vertex connections and connections to the camera — so that every
 * technique sampling a path carries the same factor and the MIS weights,
 * ratios of densities, need none. Compiled in only where a scene's material
 * absorbs (HAS_VOLUME_ABSORPTION). */
#ifndef WAVEVCM_VOLUME_H
#define WAVEVCM_VOLUME_H

#include "core/vec3.h"
#include "geometry/surface.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

/* What is left of light after length t inside material m's solid (1 for a
 * thin-walled or non-absorbing material). pow, not exp(t·log c): c = 1
 * with t = ∞ (a shadow ray to an infinite light) gives 1, not NaN. */
INLINE vec3 absorption(__global const Material* m, float t)
{
    if (m->thinWalled != 0 || !(m->attenuationDistance > 0.0f))
        return v3s(1.0f);
    float s = t / m->attenuationDistance;
    return v3(pow(m->attenuationColor[0], s), pow(m->attenuationColor[1], s), pow(m->attenuationColor[2], s));
}

/* Whether direction d, leaving surface point h, goes into the solid behind
 * the surface (against its outward geometric normal). */
INLINE bool enters_solid(const SurfaceHit* h, vec3 d)
{
    float c = v3_dot(d, h->ngF); /* ngF faces where h was reached from */
    return h->frontSide ? c < 0.0f : c > 0.0f;
}

/* The absorption along a segment of length t leaving h (on a triangle of
 * material m) along d: inside m's solid, or none. */
INLINE vec3 segment_absorption(__global const Material* m, const SurfaceHit* h, vec3 d, float t)
{
    return enters_solid(h, d) ? absorption(m, t) : v3s(1.0f);
}

#endif
