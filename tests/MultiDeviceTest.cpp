// Several devices rendering one image (MultiDeviceRender, `-d 0,2`): each
// takes the next global iteration index, so K devices give the image of one
// running the same iterations. The same device twice (two contexts, the same
// arithmetic) must give it up to the float rounding of the weighted sum;
// PoCL with rusticl draws the same samples with other rounding, so its image
// must be far closer to the one-device image than another seed's is.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/MultiDeviceRender.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

namespace wv {
namespace {

struct Result {
    Image image;
    std::vector<int> shares; // iterations per device
};

Result renderOn(const std::vector<DeviceInfo>& infos, const Scene& scene, Algorithm algorithm, int iterations,
                uint32_t seed)
{
    std::vector<std::unique_ptr<DeviceContext>> contexts;
    std::vector<DeviceContext*> devices;
    for (const DeviceInfo& d : infos) {
        contexts.push_back(std::make_unique<DeviceContext>(d));
        devices.push_back(contexts.back().get());
    }
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = 32;
    s.height = 32;
    s.seed = seed;
    s.wavefront = 512;
    Bvh bvh = buildBvh(scene.vertices);
    MultiDeviceRender render(devices, scene, bvh, s);
    render.run(iterations, 0, [] { return false; }, nullptr);
    Result r{render.image(), {}};
    for (size_t i = 0; i < render.deviceCount(); ++i) r.shares.push_back(render.renderer(i).iterations());
    return r;
}

TEST(MultiDevice, SameDeviceTwiceGivesTheImageOfOne)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    DeviceInfo device = test::devicesUnderTest()[0];
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        Result one = renderOn({device}, scene, a, 12, 5), two = renderOn({device, device}, scene, a, 12, 5);
        ASSERT_EQ(two.shares.size(), 2u);
        EXPECT_EQ(two.shares[0] + two.shares[1], 12);
        std::printf("[ shares ] %s: %d + %d iterations\n", algorithmName(a).c_str(), two.shares[0], two.shares[1]);
        // Per pixel the weighted mean of the two running means in double,
        // rounded to float, against one running mean: ~1e-7 relative.
        EXPECT_LT(compareImages(two.image, one.image).relMse, 1e-10);
    }
}

TEST(MultiDevice, PoclAndRusticlTogetherGiveTheImageOfOne)
{
    std::vector<DeviceInfo> devices = test::devicesUnderTest();
    if (devices.size() < 2) GTEST_SKIP() << "one OpenCL device: nothing to combine";
    Scene scene = loadGltf(test::cornellBoxPath());
    Result one = renderOn({devices[0]}, scene, Algorithm::PathTracing, 8, 5);
    Result both = renderOn({devices[0], devices[1]}, scene, Algorithm::PathTracing, 8, 5);
    Result otherSeed = renderOn({devices[0]}, scene, Algorithm::PathTracing, 8, 6);
    EXPECT_EQ(both.shares[0] + both.shares[1], 8);
    std::printf("[ shares ] %s %d, %s %d iterations\n", devices[0].name.c_str(), both.shares[0],
                devices[1].name.c_str(), both.shares[1]);
    double rounding = compareImages(both.image, one.image).relMse, noise = compareImages(otherSeed.image, one.image).relMse;
    // Same samples: only paths that rounding sends another way differ.
    EXPECT_LT(rounding, 0.05 * noise) << "two devices " << rounding << ", another seed " << noise;
}

} // namespace
} // namespace wv
