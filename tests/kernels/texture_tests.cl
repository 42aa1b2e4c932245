/* Test-only kernel for tests/TextureTest.cpp: the production bilinear lookup
 * (kernels/materials/texture.h) of one texture at host-chosen coordinates. */
#include "materials/texture.h"

__kernel void texture_lookups(__global const float4* texels, __global const TextureInfo* texture,
                              __global const float2* uvs, int count, __global float4* out)
{
    int i = get_global_id(0);
    if (i >= count)
        return;
    vec3 c = texture_bilinear(texels, texture, uvs[i].x, uvs[i].y);
    out[i] = (float4)(c.x, c.y, c.z, texture_alpha(texels, texture, uvs[i].x, uvs[i].y));
}
