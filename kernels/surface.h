/* Surface geometry at a hit: geometric normal from the triangle's winding,
 * shading normal interpolated from vertex normals when the scene has them. */
#ifndef WAVEVCM_SURFACE_H
#define WAVEVCM_SURFACE_H

inline float3 geometric_normal(__global const float4* triVertices, int tri)
{
    float3 v0 = triVertices[3 * tri].xyz;
    return normalize(cross(triVertices[3 * tri + 1].xyz - v0, triVertices[3 * tri + 2].xyz - v0));
}

#ifdef HAS_VERTEX_NORMALS
/* Falls back to the geometric normal where the interpolated normal vanishes. */
inline float3 shading_normal(__global const float4* triNormals, int tri, float2 bary, float3 ng)
{
    float3 n = (1.0f - bary.x - bary.y) * triNormals[3 * tri].xyz +
               bary.x * triNormals[3 * tri + 1].xyz + bary.y * triNormals[3 * tri + 2].xyz;
    float len = length(n);
    return len > 1e-12f ? n / len : ng;
}
#endif

#endif
