#include "TestRendering.h"
#include "TestDevices.h"

#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>

namespace wv::test {

void addSphere(Scene& s, Vec3 centre, float radius, bool inward, int material, int rings, int segments)
{
    auto point = [&](int ring, int seg) {
        float theta = float(M_PI) * float(ring) / float(rings), phi = 2.0f * float(M_PI) * float(seg) / float(segments);
        return centre + Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)) * radius;
    };
    auto triangle = [&](Vec3 a, Vec3 b, Vec3 c) {
        if (inward) std::swap(b, c);
        for (Vec3 v : {a, b, c}) s.vertices.push_back(v);
        s.triangleMaterial.push_back(material);
    };
    for (int r = 0; r < rings; ++r)
        for (int g = 0; g < segments; ++g) {
            Vec3 p00 = point(r, g), p01 = point(r, g + 1), p10 = point(r + 1, g), p11 = point(r + 1, g + 1);
            // Outward winding: counter-clockwise seen from outside.
            if (r > 0) triangle(p00, p01, p10);
            if (r < rings - 1) triangle(p01, p11, p10);
        }
}

void addFlatNormals(Scene& s)
{
    for (size_t v = s.normals.size(); v < s.vertices.size(); v += 3) {
        const Vec3* t = &s.vertices[v];
        Vec3 n = normalize(cross(t[1] - t[0], t[2] - t[0]));
        for (int k = 0; k < 3; ++k) s.normals.push_back(n);
    }
}

Material lambert(float albedo, float emission)
{
    Material m{};
    for (int c = 0; c < 3; ++c) {
        m.baseColor[c] = albedo;
        m.emission[c] = emission;
        m.specularColor[c] = 1;
    }
    m.roughness = 1;
    m.ior = 1.5f;
    m.thinWalled = 1;
    m.lobes = LOBE_DIFFUSE;
    return m;
}

void meanAndStandardError(const Image& image, double* mean, double* se)
{
    size_t n = image.rgb.size();
    double sum = 0, sq = 0;
    for (float v : image.rgb) sum += v;
    *mean = sum / double(n);
    for (float v : image.rgb) sq += (v - *mean) * (v - *mean);
    *se = std::sqrt(sq / double(n - 1) / double(n / 3));
}

void expectMean(const Render& r, double expected, double maxRelativeError)
{
    double mean, se;
    meanAndStandardError(r.image, &mean, &se);
    EXPECT_NEAR(mean, expected, 5 * se) << "standard error " << se;
    EXPECT_LT(se, maxRelativeError * expected) << "too noisy: an error of " << 500 * maxRelativeError
                                               << " % could pass unseen";
    EXPECT_EQ(r.nonFinite, 0u);
}

Material smoothGlass(float ior)
{
    Material glass{};
    for (int c = 0; c < 3; ++c) {
        glass.baseColor[c] = 1;
        glass.specularColor[c] = 1;
    }
    glass.specular = 1;
    glass.transmission = 1;
    glass.ior = ior;
    glass.lobes = LOBE_DELTA_REFLECTION | LOBE_DELTA_TRANSMISSION;
    return glass;
}

Render renderOn(DeviceContext& device, const Scene& scene, const Bvh& bvh, Algorithm algorithm, int width,
                       int height, int iterations, uint32_t seed, int maxPathLength, float radiusFactor)
{
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = width;
    s.height = height;
    s.seed = seed;
    s.maxPathLength = maxPathLength;
    s.wavefront = 1024;
    s.radiusFactor = radiusFactor;
    Renderer renderer(device, scene, bvh, s);
    for (int i = 0; i < iterations; ++i) renderer.iterate();
    return {renderer.image(), renderer.nonFiniteCount()};
}

DeviceContext& sharedContext(const DeviceInfo& info)
{
    // Never destroyed: the drivers may be unloaded before static destructors run.
    // Keyed by the OpenCL device itself: two identical GPUs share a name.
    static auto* contexts = new std::map<cl_device_id, std::unique_ptr<DeviceContext>>;
    std::unique_ptr<DeviceContext>& context = (*contexts)[info.device()];
    if (!context) context = std::make_unique<DeviceContext>(info);
    return *context;
}

Render render(const DeviceInfo& info, const Scene& scene, Algorithm algorithm, int width, int height, int iterations,
              uint32_t seed, int maxPathLength, float radiusFactor)
{
    DeviceContext& device = sharedContext(info);
    Bvh bvh = buildBvh(scene.vertices, trianglePacketWidth(info));
    return renderOn(device, scene, bvh, algorithm, width, height, iterations, seed, maxPathLength, radiusFactor);
}

std::vector<Image> renderSeeds(const DeviceInfo& info, const Scene& scene, Algorithm algorithm, int width,
                               int height, int iterations, int seeds, int maxPathLength, float radiusFactor)
{
    DeviceContext& device = sharedContext(info);
    Bvh bvh = buildBvh(scene.vertices, trianglePacketWidth(info));
    std::vector<Image> out;
    for (int s = 1; s <= seeds; ++s)
        out.push_back(renderOn(device, scene, bvh, algorithm, width, height, iterations, uint32_t(s), maxPathLength,
                               radiusFactor)
                          .image);
    return out;
}

int tilesDisagreeing(const std::vector<Image>& a, const std::vector<Image>& b, int tile, double k,
                     const std::vector<bool>& mask, int* compared)
{
    const int w = a[0].width, h = a[0].height;
    int bad = 0, count = 0;
    // Mean over the block's unmasked pixels and channels of one image.
    auto blockMean = [&](const Image& img, int bx, int by, int* used) {
        double sum = 0;
        *used = 0;
        for (int y = by * tile; y < std::min(h, (by + 1) * tile); ++y)
            for (int x = bx * tile; x < std::min(w, (bx + 1) * tile); ++x) {
                size_t p = size_t(y) * w + x;
                if (!mask.empty() && !mask[p]) continue;
                ++*used;
                for (int c = 0; c < 3; ++c) sum += img.rgb[3 * p + c];
            }
        return *used ? sum / (3.0 * *used) : 0.0;
    };
    // Mean over seeds and its squared standard error.
    auto stats = [&](const std::vector<Image>& images, int bx, int by, int* used, double* se2) {
        std::vector<double> m;
        for (const Image& img : images) m.push_back(blockMean(img, bx, by, used));
        double mean = 0, var = 0;
        for (double v : m) mean += v / double(m.size());
        for (double v : m) var += (v - mean) * (v - mean) / double(m.size() - 1);
        *se2 = var / double(m.size());
        return mean;
    };
    for (int by = 0; by * tile < h; ++by)
        for (int bx = 0; bx * tile < w; ++bx) {
            int used = 0;
            double seA, seB;
            double ma = stats(a, bx, by, &used, &seA), mb = stats(b, bx, by, &used, &seB);
            if (used * 2 < tile * tile) continue;
            ++count;
            double se = std::sqrt(seA + seB) + 1e-6 * (std::fabs(ma) + std::fabs(mb)) + 1e-9;
            if (std::fabs(ma - mb) > k * se) {
                ++bad;
                ADD_FAILURE() << "block " << bx << "," << by << ": " << ma << " vs " << mb << " (standard error " << se
                              << ", " << std::fabs(ma - mb) / se << " of them)";
            }
        }
    if (compared) *compared = count;
    return bad;
}

void expectConvergeTo(const DeviceInfo& device, const Scene& scene, const std::vector<Image>& reference,
                      std::vector<Algorithm> algorithms, int width, int height, int iterations, int seeds)
{
    for (Algorithm a : algorithms) {
        SCOPED_TRACE(algorithmName(a));
        std::vector<Image> other = renderSeeds(device, scene, a, width, height, iterations, seeds);
        int compared = 0;
        EXPECT_EQ(tilesDisagreeing(other, reference, 8, 5.0, {}, &compared), 0);
        EXPECT_EQ(compared, (width / 8) * (height / 8));
    }
}

void expectSameImageOnEveryDevice(const Scene& scene, Algorithm algorithm, int size, int iterations)
{
    std::vector<DeviceInfo> devices = devicesUnderTest();
    if (devices.size() < 2) GTEST_SKIP() << "only one OpenCL device; install mesa-opencl-icd for rusticl";
    std::vector<Image> first = renderSeeds(devices[0], scene, algorithm, size, size, iterations, 3);
    for (size_t d = 1; d < devices.size(); ++d) {
        SCOPED_TRACE(devices[0].name + " vs " + devices[d].name);
        std::vector<Image> other = renderSeeds(devices[d], scene, algorithm, size, size, iterations, 3);
        EXPECT_EQ(tilesDisagreeing(first, other, 8, 5.0), 0);
        double sameSeed = compareImages(other[0], first[0]).relMse;
        double otherSeed = compareImages(first[1], first[0]).relMse;
        EXPECT_LT(sameSeed, 0.25 * otherSeed) << "same-seed images differ about as much as independent ones";
    }
}

void expectPtBptVcmAgree(const Scene& scene, int ptIterationFactor)
{
    const int size = 32, iterations = 16, seeds = 6;
    DeviceInfo device = devicesUnderTest()[0];
    std::vector<Image> bpt = renderSeeds(device, scene, Algorithm::Bidirectional, size, size, iterations, seeds);
    std::vector<Image> pt =
        renderSeeds(device, scene, Algorithm::PathTracing, size, size, ptIterationFactor * iterations, seeds);
    std::vector<Image> vcm = renderSeeds(device, scene, Algorithm::VertexConnectionMerging, size, size, iterations, seeds);
    EXPECT_EQ(tilesDisagreeing(pt, bpt, 8, 5.0), 0) << "pt";
    EXPECT_EQ(tilesDisagreeing(vcm, bpt, 8, 5.0), 0) << "vcm";
}

double blockMean(const Image& image, int size, int x0, int y0, int block, int c, double* se)
{
    double sum = 0, sq = 0;
    for (int y = y0; y < y0 + block; ++y)
        for (int x = x0; x < x0 + block; ++x) {
            double v = image.rgb[3 * (size_t(y) * size_t(size) + size_t(x)) + size_t(c)];
            sum += v;
            sq += v * v;
        }
    int n = block * block;
    double mean = sum / n;
    *se = std::sqrt(std::max(0.0, sq / n - mean * mean) / n);
    return mean;
}

} // namespace wv::test
