/* Rays and the self-intersection-free origin offset. */
#ifndef WAVEVCM_RAY_H
#define WAVEVCM_RAY_H

typedef struct Ray {
    float3 origin;
    float3 direction; /* not necessarily unit length; t is in units of it */
    float tMax;
} Ray;

/* Offset a surface point p along the geometric normal n (already flipped to
 * the side the new ray leaves from) far enough that the new ray cannot hit the
 * surface it starts on, at any scene scale (Wächter & Binder, "A Fast and
 * Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6).
 * Away from the origin the offset is a fixed number of ULPs of p (added to
 * the float's bit pattern, so it scales with |p|); near the origin, where ULPs
 * become tiny, a fixed absolute offset takes over. */
inline float offset_component(float p, float n)
{
    const float ORIGIN = 1.0f / 32.0f, FLOAT_SCALE = 1.0f / 65536.0f, INT_SCALE = 256.0f;
    if (fabs(p) < ORIGIN)
        return p + FLOAT_SCALE * n;
    int ulps = (int)(INT_SCALE * n);
    return as_float(as_int(p) + (p < 0.0f ? -ulps : ulps));
}

inline float3 offset_ray_origin(float3 p, float3 n)
{
    return (float3)(offset_component(p.x, n.x), offset_component(p.y, n.y),
                    offset_component(p.z, n.z));
}

/* Spawn a ray from surface point p (geometric normal ng) in direction d. */
inline Ray spawn_ray(float3 p, float3 ng, float3 d)
{
    Ray r;
    r.origin = offset_ray_origin(p, dot(d, ng) < 0.0f ? -ng : ng);
    r.direction = d;
    r.tMax = INFINITY;
    return r;
}

#endif
