#include "SceneBuffers.h"

#include "../Error.h"

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <sys/mman.h>

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

// On a CPU device a buffer is host memory, and a large scene's traversal
// misses the TLB on nearly every node and triangle packet: with 4 KiB pages
// the 1M-triangle displaced sphere's 58 MiB of BVH take 15,000 pages, several
// times what the second-level TLB maps. Uploads of kHugePageBuffer bytes or
// more are therefore allocated by the driver (CL_MEM_ALLOC_HOST_PTR), mapped
// before their first write, and their whole 2 MiB pages advised as huge
// (MADV_HUGEPAGE, honoured under Linux's default THP setting, "madvise"), as
// Embree does with its own BVH. On that scene (AMD EPYC, six interleaved
// pairs): wavevcm_bench's incoherent extend rays 0.69x -> 0.745x Embree's
// rate (medians), any-hit 0.74x -> 0.78x; `pt` 1.90-2.11 -> 2.13-2.15 it/s.
// The renderer's own buffers (path state, light vertices) gained nothing so
// (`vcm` on the 130K-triangle box) and keep the driver's pages. Unlike the
// BVH build's arrays (allocateLargeArray, Bvh.cpp), which skip the advice
// where a fault may stop to compact memory (defrag "madvise"), uploads take
// it there too: that cost is paid once per render, at the copy, and the
// 1M-triangle scene's setup measured the same with and without (2.7-4.4 s,
// dominated by loading the file). Advice only:
// where the mapping is a copy, or the pages are already touched, nothing
// changes but the cost of the copy.
constexpr size_t kHugePage = size_t(2) << 20;
constexpr size_t kHugePageBuffer = 2 * kHugePage;

static bool hugePageCandidate(const DeviceContext& device, size_t bytes)
{
    return (device.info.type & CL_DEVICE_TYPE_CPU) && bytes >= kHugePageBuffer;
}

// Maps `buffer`, advises its whole 2 MiB pages as huge, copies `data` into it
// and unmaps it.
static void fillWithHugePages(DeviceContext& device, const cl::Buffer& buffer, const void* data, size_t bytes)
{
    void* p = device.queue.enqueueMapBuffer(buffer, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, bytes);
#ifdef MADV_HUGEPAGE
    uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + kHugePage - 1) & ~(kHugePage - 1);
    uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHugePage - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
    std::memcpy(p, data, bytes);
    cl::Event unmapped;
    device.queue.enqueueUnmapMemObject(buffer, p, nullptr, &unmapped);
    unmapped.wait();
}

// WAVEVCM_POISON_BUFFERS=BYTE (0-255, or 0x00-0xff): every buffer
// deviceBuffer makes starts as that byte repeated instead of whatever the
// device left there, so that a kernel reading state that nothing wrote first
// (a field a path's move to a new slot forgot to carry) gives another image
// under another byte (RoundsTest). -1 when unset.
static int poisonByte()
{
    const char* env = std::getenv("WAVEVCM_POISON_BUFFERS");
    if (!env || !*env) return -1;
    char* end = nullptr;
    long byte = std::strtol(env, &end, 0);
    if (*end != '\0' || byte < 0 || byte > 255)
        throw Error(std::string("WAVEVCM_POISON_BUFFERS is \"") + env + "\"; it takes a byte, 0-255 or 0x00-0xff");
    return int(byte);
}

cl::Buffer deviceBuffer(DeviceContext& device, size_t bytes, const std::string& what)
{
    checkAllocation(device, bytes, what);
    size_t size = std::max<size_t>(bytes, 16);
    try {
        cl::Buffer buffer(device.context, CL_MEM_READ_WRITE, size);
        if (int byte = poisonByte(); byte >= 0) device.queue.enqueueFillBuffer(buffer, cl_uchar(byte), 0, size);
        return buffer;
    } catch (const cl::Error& e) {
        throw Error("cannot allocate " + what + " (" + megabytes(bytes) + ") on " + device.info.name + ": " +
                    clErrorName(e.err()));
    }
}

int trianglePacketWidth(const DeviceInfo& device)
{
    if (const char* forced = std::getenv("WAVEVCM_TRIANGLE_PACKET_WIDTH")) {
        std::string w = forced;
        if (w == "4" || w == "8") return std::stoi(w);
        throw Error("WAVEVCM_TRIANGLE_PACKET_WIDTH is \"" + w + "\"; it takes 4 or 8");
    }
    bool avx = device.isPocl() && (device.type & CL_DEVICE_TYPE_CPU) &&
               device.device.getInfo<CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT>() >= 8;
    return avx ? 8 : 4;
}

std::vector<Bvh> buildBvhs(const std::vector<Vec3>& vertices, const std::vector<DeviceInfo>& devices)
{
    std::vector<Bvh> trees;
    for (const DeviceInfo& d : devices) {
        int width = trianglePacketWidth(d);
        bool built = false;
        for (const Bvh& t : trees) built = built || t.packetWidth() == width;
        if (!built) trees.push_back(buildBvh(vertices, width));
    }
    return trees;
}

const Bvh& bvhFor(const std::vector<Bvh>& trees, const DeviceInfo& device)
{
    int width = trianglePacketWidth(device);
    for (const Bvh& bvh : trees)
        if (bvh.packetWidth() == width) return bvh;
    throw Error("internal error: no BVH of packets " + std::to_string(width) + " wide for " + device.label());
}

cl::Buffer uploadBuffer(DeviceContext& device, const void* data, size_t bytes, const std::string& what)
{
    checkAllocation(device, bytes, what);
    try {
        if (hugePageCandidate(device, bytes)) {
            cl::Buffer buffer(device.context, CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR, bytes);
            fillWithHugePages(device, buffer, data, bytes);
            return buffer;
        }
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
    std::vector<std::array<float, 4>> colors(scene.colors.empty() ? 1 : 3 * count);
    for (size_t i = 0; i < count; ++i) {
        uint32_t t = bvh.triangleOrder[i];
        triMaterial[i] = scene.triangleMaterial[t];
        if (!scene.uvs.empty())
            for (int k = 0; k < 6; ++k) uvs[6 * i + size_t(k)] = scene.uvs[6 * size_t(t) + size_t(k)];
        if (!scene.uvs1.empty())
            for (int k = 0; k < 6; ++k) uvs1[6 * i + size_t(k)] = scene.uvs1[6 * size_t(t) + size_t(k)];
        if (!scene.tangents.empty())
            for (int k = 0; k < 3; ++k) tangents[3 * i + size_t(k)] = scene.tangents[3 * size_t(t) + size_t(k)];
        if (!scene.colors.empty())
            for (int k = 0; k < 3; ++k) colors[3 * i + size_t(k)] = scene.colors[3 * size_t(t) + size_t(k)];
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
    trianglePackets = uploadBuffer(device, bvh.packetData(), bvh.packetBytes(), "the BVH's triangle packets");
    bytes += bvh.packetBytes();
    packetWidth = bvh.packetWidth();
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
    triColors = upload(colors, "the vertex colours");
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
    b.triColors = triColors;
    b.envRadiance = envRadiance;
    b.envMarginalCdf = envMarginalCdf;
    b.envConditionalCdf = envConditionalCdf;
    b.scene = sceneInfo;
}

} // namespace wv
