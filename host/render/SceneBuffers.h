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
    cl::Buffer trianglePackets;  // TrianglePacket4[] or TrianglePacket8[]: the BVH leaves' triangles
    int packetWidth = 0;         // the tree's: the program's TRIANGLE_PACKET_WIDTH
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
    cl::Buffer triColors;        // COLOR_0 per corner (float4, BVH order) with vertex colours (else 1)
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

// The triangle packet width of the tree to build for `device` (buildBvh):
// 8 where the device's compiler tests eight lanes in one instruction
// (PoCL's CPU devices with AVX, whose native float vector is 8 or 16 wide:
// kernels/geometry/intersect_triangle.h), else 4 (GPUs, whose threads run a
// vector's lanes one after another; rusticl; CPUs without AVX).
int trianglePacketWidth(const DeviceInfo& device);

// The scene's BVH for each packet width the devices take, built once each.
std::vector<Bvh> buildBvhs(const std::vector<Vec3>& vertices, const std::vector<DeviceInfo>& devices);

// The one BVH of `trees` built for the device's packet width; throws if none is.
const Bvh& bvhFor(const std::vector<Bvh>& trees, const DeviceInfo& device);

// A read-only device buffer holding `bytes` bytes copied from `data`; checks
// the device's maximum allocation first. `what` names it in the error.
cl::Buffer uploadBuffer(DeviceContext& device, const void* data, size_t bytes, const std::string& what);

// A device buffer of `bytes` bytes, checked against the device's limits. Its
// contents are undefined (with WAVEVCM_POISON_BUFFERS=BYTE, that byte repeated).
cl::Buffer deviceBuffer(DeviceContext& device, size_t bytes, const std::string& what);

} // namespace wv
