/* A light vertex's surface (LightVertex in interface/shared_types.h): stored
 * by shade_light as it built it, read back by connect_vertices for every
 * connection instead of being rebuilt from the triangle. */
#ifndef WAVEVCM_LIGHT_VERTEX_H
#define WAVEVCM_LIGHT_VERTEX_H

#include "core/sampling.h"
#include "core/vec3.h"
#include "geometry/surface.h"
#include "interface/inline.h"
#include "interface/shared_types.h"

INLINE void store_light_vertex_surface(LightVertex* v, const SurfaceHit* h)
{
    store3(v->position, h->p);
    store3(v->positionError, h->pError);
    store3(v->geometricNormal, h->ngF);
    store3(v->shadingNormal, h->nsF);
    v->frontSide = h->frontSide ? 1 : 0;
}

/* The SurfaceHit stored with v; its frame follows from the shading normal
 * as surface_hit makes it. */
INLINE SurfaceHit light_vertex_surface(__global const LightVertex* v)
{
    SurfaceHit h;
    h.p = load3(v->position);
    h.pError = load3(v->positionError);
    h.ngF = load3(v->geometricNormal);
    h.nsF = load3(v->shadingNormal);
    h.frame = frame_from_normal(h.nsF);
    h.frontSide = v->frontSide != 0;
    return h;
}

#endif
