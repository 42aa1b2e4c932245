// Several camera samples per pixel in one iteration (pt and el,
// RenderSettings::samplesPerIteration): sample k of iteration i draws the
// random numbers of the pixel's sample i·K + k, and accumulate folds the K
// samples into the running mean in that order, so N iterations of K samples
// must give exactly the image of N·K iterations of one, on every device. A
// wavefront of 256 slots for 32 × 32 pixels makes each iteration's passes
// share slots: a freed slot takes the next sample, whichever pass it is in.
#include "Error.h"
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

Image renderWith(DeviceContext& device, const Scene& scene, const Bvh& bvh, Algorithm algorithm, int perIteration,
                 int iterations)
{
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = s.height = 32;
    s.seed = 5;
    s.wavefront = 256;
    s.samplesPerIteration = perIteration;
    Renderer renderer(device, scene, bvh, s);
    for (int i = 0; i < iterations; ++i) renderer.iterate();
    EXPECT_EQ(renderer.iterations(), iterations);
    return renderer.image();
}

TEST(SamplesPerIteration, GiveTheImageOfOneSampleEach)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        DeviceContext device(info);
        SCOPED_TRACE(info.name);
        for (Algorithm a : {Algorithm::EyeLight, Algorithm::PathTracing}) {
            SCOPED_TRACE(algorithmName(a));
            Image one = renderWith(device, scene, bvh, a, 1, 6);
            for (int k : {2, 3}) {
                SCOPED_TRACE(std::to_string(k) + " samples per iteration");
                Image several = renderWith(device, scene, bvh, a, k, 6 / k);
                EXPECT_EQ(compareImages(several, one).rmse, 0.0);
            }
            // Not the same samples: another image (the comparison can fail).
            if (a == Algorithm::PathTracing)
                EXPECT_GT(compareImages(renderWith(device, scene, bvh, a, 2, 2), one).rmse, 0.0);
        }
    }
}

TEST(SamplesPerIteration, OnlyForTheUnidirectionalAlgorithms)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    DeviceContext device(test::devicesUnderTest()[0]);
    RenderSettings s;
    s.width = s.height = 16;
    s.samplesPerIteration = 2;
    for (Algorithm a : {Algorithm::LightTracing, Algorithm::Bidirectional, Algorithm::VertexConnectionMerging}) {
        s.algorithm = a;
        EXPECT_THROW({ Renderer r(device, scene, bvh, s); }, Error) << algorithmName(a);
    }
}

} // namespace
} // namespace wv
