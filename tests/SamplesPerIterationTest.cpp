// Several camera samples per pixel in one iteration (pt and el,
// RenderSettings::samplesPerIteration): sample k of iteration i draws the
// random numbers of the pixel's sample i·K + k, and accumulate folds the K
// samples into the running mean in that order, so N iterations of K samples
// must give exactly the image of N·K iterations of one, on every device. A
// wavefront of 256 slots for 32 × 32 pixels makes each iteration's passes
// share slots: a freed slot takes the next sample, whichever pass it is in.
// The Cornell box with a background light has every way a camera sample
// adds radiance (emission hits, next-event estimation, escapes); technique
// images are kept too, since accumulate folds them per sample as well.
#include "Error.h"
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

struct Rendered {
    Image image;
    std::array<Image, 3> techniques;
};

Rendered renderWith(DeviceContext& device, const Scene& scene, const Bvh& bvh, Algorithm algorithm, int perIteration,
                    int iterations)
{
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = s.height = 32;
    s.seed = 5;
    s.wavefront = 256;
    s.samplesPerIteration = perIteration;
    s.techniques = true;
    Renderer renderer(device, scene, bvh, s);
    for (int i = 0; i < iterations; ++i) renderer.iterate();
    EXPECT_EQ(renderer.iterations(), iterations);
    return {renderer.image(), renderer.techniqueImages()};
}

TEST(SamplesPerIteration, GiveTheImageOfOneSampleEach)
{
    Scene scene = loadGltf(std::string(WAVEVCM_SOURCE_DIR) + "/scenes/cornell-box-background.gltf");
    Bvh bvh = buildBvh(scene.vertices);
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        DeviceContext device(info);
        SCOPED_TRACE(info.name);
        for (Algorithm a : {Algorithm::EyeLight, Algorithm::PathTracing}) {
            SCOPED_TRACE(algorithmName(a));
            Rendered one = renderWith(device, scene, bvh, a, 1, 6);
            for (int k : {2, 3}) {
                SCOPED_TRACE(std::to_string(k) + " samples per iteration");
                Rendered several = renderWith(device, scene, bvh, a, k, 6 / k);
                EXPECT_EQ(compareImages(several.image, one.image).rmse, 0.0);
                for (int f = 0; f < 3; ++f)
                    EXPECT_EQ(compareImages(several.techniques[f], one.techniques[f]).rmse, 0.0) << "family " << f;
            }
            // Not the same samples: another image (the comparison can fail).
            if (a == Algorithm::PathTracing)
                EXPECT_GT(compareImages(renderWith(device, scene, bvh, a, 2, 2).image, one.image).rmse, 0.0);
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
