#include "SceneBuffers.h"

#include "../Error.h"

#include <array>
#include <cstdint>

namespace wv {

static std::string megabytes(size_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

// What a memory error adds on a pipeline's share of a device (pipelineDevices).
static std::string pipelineShare(const DeviceInfo& device)
{
    if (device.pipelines <= 1) return "";
    return " (each of its " + std::to_string(device.pipelines) + " pipelines gets 1/" +
           std::to_string(device.pipelines) + " of its memory; --pipelines 1 gives one all of it)";
}

static void checkAllocation(const DeviceContext& device, size_t bytes, const std::string& what)
{
    if (bytes > device.info.maxAllocation)
        throw Error(what + " needs " + megabytes(bytes) + " but " + device.info.label() + " allows at most " +
                    megabytes(device.info.maxAllocation) + " per buffer" + pipelineShare(device.info));
}

cl::Buffer deviceBuffer(DeviceContext& device, size_t bytes, const std::string& what)
{
    checkAllocation(device, bytes, what);
    try {
        return cl::Buffer(device.context, CL_MEM_READ_WRITE, std::max<size_t>(bytes, 16));
    } catch (const cl::Error& e) {
        throw Error("cannot allocate " + what + " (" + megabytes(bytes) + ") on " + device.info.name + ": " +
                    clErrorName(e.err()));
    }
}

cl::Buffer uploadBuffer(DeviceContext& device, const void* data, size_t bytes, const std::string& what)
{
    checkAllocation(device, bytes, what);
    try {
        return cl::Buffer(device.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<void*>(data));
    } catch (const cl::Error& e) {
        throw Error("cannot allocate " + what + " (" + megabytes(bytes) + ") on " + device.info.name + ": " +
                    clErrorName(e.err()));
    }
}

SceneBuffers::SceneBuffers(DeviceContext& device, const Scene& scene, const Bvh& bvh, const LightTable& lightTable)
{
    size_t count = bvh.triangleOrder.size();
    std::vector<std::array<float, 4>> vertices(3 * count), normals(scene.normals.empty() ? 1 : 3 * count);
    std::vector<int> triMaterial(count);
    std::vector<float> uvs(scene.uvs.empty() ? 2 : 6 * count, 0.0f); // BVH order, like the vertices
    std::vector<float> uvs1(scene.uvs1.empty() ? 2 : 6 * count, 0.0f);
    std::vector<std::array<float, 4>> tangents(scene.tangents.empty() ? 1 : 3 * count);
    for (size_t i = 0; i < count; ++i) {
        uint32_t t = bvh.triangleOrder[i];
        triMaterial[i] = scene.triangleMaterial[t];
        if (!scene.uvs.empty())
            for (int k = 0; k < 6; ++k) uvs[6 * i + size_t(k)] = scene.uvs[6 * size_t(t) + size_t(k)];
        if (!scene.uvs1.empty())
            for (int k = 0; k < 6; ++k) uvs1[6 * i + size_t(k)] = scene.uvs1[6 * size_t(t) + size_t(k)];
        if (!scene.tangents.empty())
            for (int k = 0; k < 3; ++k) tangents[3 * i + size_t(k)] = scene.tangents[3 * size_t(t) + size_t(k)];
        for (int k = 0; k < 3; ++k) {
            const Vec3& v = scene.vertices[3 * t + k];
            vertices[3 * i + k] = {v.x, v.y, v.z, 0.0f};
            if (!scene.normals.empty()) {
                const Vec3& n = scene.normals[3 * t + k];
                normals[3 * i + k] = {n.x, n.y, n.z, 0.0f};
            }
        }
    }
    std::vector<Light> lightData = lightTable.lights;
    if (lightData.empty()) lightData.push_back(Light{}); // OpenCL buffers cannot be empty
    std::vector<SceneInfo> info{lightTable.info};

    auto upload = [&](const auto& v, const char* what) {
        size_t b = v.size() * sizeof(v[0]);
        bytes += b;
        return uploadBuffer(device, v.data(), b, what);
    };
    nodes = upload(bvh.nodes, "the BVH");
    trianglePackets = upload(bvh.packets, "the BVH's triangle packets");
    triVertices = upload(vertices, "the triangle vertices");
    triNormals = upload(normals, "the vertex normals");
    triMaterials = upload(triMaterial, "the triangle materials");
    materials = upload(scene.materials, "the materials");
    lights = upload(lightData, "the lights");
    lightCdf = upload(lightTable.cdf, "the light distribution");
    triangleLight = upload(lightTable.triangleLight, "the triangle lights");
    sceneInfo = upload(info, "the scene constants");
    // The textures: every texel in one float4 buffer, a table of where each starts.
    std::vector<std::array<float, 4>> texels;
    std::vector<TextureInfo> textureTable;
    for (const Texture& t : scene.textures) {
        TextureInfo info{};
        info.offset = int(texels.size());
        info.width = t.image.width;
        info.height = t.image.height;
        info.wrapS = t.wrapS;
        info.wrapT = t.wrapT;
        for (int k = 0; k < 6; ++k) info.uvTransform[k] = t.uvTransform[size_t(k)];
        info.texCoord = t.texCoord;
        textureTable.push_back(info);
        for (size_t p = 0; p < t.image.rgb.size() / 3; ++p) // alpha in w (1 where the image has none)
            texels.push_back({t.image.rgb[3 * p], t.image.rgb[3 * p + 1], t.image.rgb[3 * p + 2],
                              t.image.alpha.empty() ? 1.0f : t.image.alpha[p]});
    }
    if (texels.size() > size_t(INT32_MAX)) throw Error("the textures have more than 2^31 texels");
    if (texels.empty()) texels.push_back({0, 0, 0, 0}); // OpenCL buffers cannot be empty
    if (textureTable.empty()) textureTable.push_back(TextureInfo{});
    textureTexels = upload(texels, "the textures");
    textures = upload(textureTable, "the texture table");
    triUVs = upload(uvs, "the texture coordinates");
    triUVs1 = upload(uvs1, "the second texture coordinates");
    triTangents = upload(tangents, "the tangents");
    const EnvironmentLight& env = lightTable.environment;
    auto nonEmpty = [](std::vector<float> v, size_t n) { // OpenCL buffers cannot be empty
        if (v.empty()) v.assign(n, 0.0f);
        return v;
    };
    envRadiance = upload(nonEmpty(env.radiance, 4), "the environment map");
    envMarginalCdf = upload(nonEmpty(env.marginalCdf, 1), "the environment map's distribution");
    envConditionalCdf = upload(nonEmpty(env.conditionalCdf, 1), "the environment map's distribution");
    if (bytes > device.info.globalMemory)
        throw Error("the scene needs " + megabytes(bytes) + " but " + device.info.label() + " has " +
                    megabytes(device.info.globalMemory) + pipelineShare(device.info));
}

void SceneBuffers::bind(KernelBuffers& b) const
{
    b.nodes = nodes;
    b.trianglePackets = trianglePackets;
    b.triVertices = triVertices;
    b.triNormals = triNormals;
    b.triMaterials = triMaterials;
    b.materials = materials;
    b.lights = lights;
    b.lightCdf = lightCdf;
    b.triangleLight = triangleLight;
    b.textureTexels = textureTexels;
    b.textures = textures;
    b.triUVs = triUVs;
    b.triUVs1 = triUVs1;
    b.triTangents = triTangents;
    b.envRadiance = envRadiance;
    b.envMarginalCdf = envMarginalCdf;
    b.envConditionalCdf = envConditionalCdf;
    b.scene = sceneInfo;
}

} // namespace wv
