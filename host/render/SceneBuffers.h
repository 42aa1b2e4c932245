// The scene on the device: BVH nodes and BVH-ordered triangle data, uploaded
// once per render.
#pragma once

#include "../bvh/Bvh.h"
#include "../cl/DeviceContext.h"
#include "../scene/Scene.h"
#include "KernelBindings.h"
#include "LightTable.h"

namespace wv {

struct SceneBuffers {
    cl::Buffer nodes;            // BvhNode[]
    cl::Buffer trianglePackets;  // TrianglePacket[]: the BVH leaves' triangles
    cl::Buffer triVertices;      // float4[3 · triangles], BVH order
    cl::Buffer triNormals;       // float4[3 · triangles] with vertex normals, else 1 float4
    cl::Buffer triMaterials;     // int[triangles]
    cl::Buffer materials;        // Material[]
    cl::Buffer lights;           // Light[] (at least one element)
    cl::Buffer lightCdf;         // float[lights + 1]
    cl::Buffer triangleLight;    // int[triangles]: light index or -1
    cl::Buffer textureTexels;    // float4 per texel of every texture (1 element without textures)
    cl::Buffer textures;         // TextureInfo[] (1 element without textures)
    cl::Buffer triUVs;           // float2[3 · triangles] with textures, BVH order (else 1)
    cl::Buffer triUVs1;          // the same for TEXCOORD_1 when a texture reads it (else 1)
    cl::Buffer triTangents;      // float4[3 · triangles] with normal maps, BVH order (else 1)
    cl::Buffer envRadiance;      // float4 per environment-map texel (1 element without a map)
    cl::Buffer envMarginalCdf;   // float[height + 1]
    cl::Buffer envConditionalCdf; // float[height · (width + 1)]
    cl::Buffer sceneInfo;        // SceneInfo
    size_t bytes = 0;

    // Throws wv::Error naming the device if a buffer exceeds its limits.
    SceneBuffers(DeviceContext& device, const Scene& scene, const Bvh& bvh, const LightTable& lights);

    // Sets the scene's buffers of a kernel's buffer set (all of SCENE_BUFFERS
    // but the camera, which depends on the image size).
    void bind(KernelBuffers& b) const;
};

// A read-only device buffer holding `bytes` bytes copied from `data`; checks
// the device's maximum allocation first. `what` names it in the error.
cl::Buffer uploadBuffer(DeviceContext& device, const void* data, size_t bytes, const std::string& what);

// A device buffer of `bytes` bytes, checked against the device's limits.
cl::Buffer deviceBuffer(DeviceContext& device, size_t bytes, const std::string& what);

} // namespace wv
