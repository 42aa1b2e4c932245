// Several samples per pixel in one iteration (RenderSettings::
// samplesPerIteration): sample k of iteration i draws the random numbers of
// the pixel's sample i·K + k, and accumulate folds the K samples into the
// running mean in that order, so for pt and el N iterations of K samples must
// give exactly the image of N·K iterations of one, on every device. lt and
// bpt trace K light paths per pixel, pass k's drawing the numbers of the
// pixel's light path i·K + k and connecting to pass k's camera paths, so
// they must give that image too, up to the order of float adds (splats land
// in any order, and the iteration's splats are folded in with pass 0):
// relMSE under 1e-10, where a wrong pairing or weight is noise-sized (1e-2).
// Merging (ppm, bpm, vcm) merges with all K passes' light vertices: another
// estimator of the same image. ppm and bpm are compared block by block
// within 5 seed-to-seed standard errors (6 seeds a side), at a fixed radius
// (alpha 1) large enough (0.05 of the scene) for a normalization off by K to
// stand out: with merging alone both estimate the same blurred image (vcm's
// weights between merging and connection change with η = π r² K P, and with
// them how much of that blur its image has). A wavefront of 256 slots for 32 × 32 pixels makes each
// iteration's passes share slots: a freed slot takes the next sample,
// whichever pass it is in. The Cornell box with a background light has
// every way a camera sample adds radiance (emission hits, next-event
// estimation, escapes); technique images are kept too, since accumulate
// folds them per sample as well.
#include "TestDevices.h"
#include "TestRendering.h"
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
                    int iterations, uint32_t seed = 5, float radiusFactor = 0.003f, float radiusAlpha = 0.75f,
                    VertexConnections connections = VertexConnections::Default, size_t maxLightVertices = 0)
{
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = s.height = 32;
    s.seed = seed;
    s.wavefront = 256;
    s.samplesPerIteration = perIteration;
    s.techniques = true;
    s.radiusFactor = radiusFactor;
    s.radiusAlpha = radiusAlpha;
    s.vertexConnections = connections;
    s.maxLightVertices = maxLightVertices;
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

TEST(SamplesPerIteration, LightTracingAndBidirectionalGiveTheImageOfOneSampleEach)
{
    Scene scene = loadGltf(std::string(WAVEVCM_SOURCE_DIR) + "/scenes/cornell-box-background.gltf");
    Bvh bvh = buildBvh(scene.vertices);
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        DeviceContext device(info);
        SCOPED_TRACE(info.name);
        for (Algorithm a : {Algorithm::LightTracing, Algorithm::Bidirectional}) {
            SCOPED_TRACE(algorithmName(a));
            Rendered one = renderWith(device, scene, bvh, a, 1, 4);
            Rendered two = renderWith(device, scene, bvh, a, 2, 2);
            EXPECT_LT(compareImages(two.image, one.image).relMse, 1e-10);
            for (int f = 0; f < 3; ++f)
                EXPECT_LT(compareImages(two.techniques[f], one.techniques[f]).relMse, 1e-10) << "family " << f;
            // Other samples: another image (the comparison can fail).
            EXPECT_GT(compareImages(renderWith(device, scene, bvh, a, 2, 1).image, one.image).relMse, 1e-6);
        }
        // bpt's connections queued (trace_connections adds to the sample's
        // entry), and light paths in batches of what 700 vertices hold: on
        // the first device (ConnectionQueue.GivesTheImageOfTracingInline runs
        // queued connections on every device; this program, on rusticl, would
        // be compiled for this test alone).
        if (!test::isFirstDevice(info))
            continue;
        Rendered one = renderWith(device, scene, bvh, Algorithm::Bidirectional, 1, 4);
        Rendered two = renderWith(device, scene, bvh, Algorithm::Bidirectional, 2, 2, 5, 0.003f, 0.75f,
                                  VertexConnections::Queued, 700);
        EXPECT_LT(compareImages(two.image, one.image).relMse, 1e-8) << "queued, in batches";
    }
}

TEST(SamplesPerIteration, MergingConvergesToTheImageOfOneSampleEach)
{
    Scene scene = loadGltf(std::string(WAVEVCM_SOURCE_DIR) + "/scenes/cornell-box-background.gltf");
    Bvh bvh = buildBvh(scene.vertices);
    DeviceContext device(test::devicesUnderTest()[0]);
    for (Algorithm a : {Algorithm::ProgressivePhotonMapping, Algorithm::BidirectionalPhotonMapping}) {
        SCOPED_TRACE(algorithmName(a));
        std::vector<Image> one, two;
        for (uint32_t seed = 1; seed <= 6; ++seed) {
            one.push_back(renderWith(device, scene, bvh, a, 1, 8, seed, 0.05f, 1.0f).image);
            two.push_back(renderWith(device, scene, bvh, a, 2, 4, seed + 100, 0.05f, 1.0f).image);
        }
        int compared = 0;
        EXPECT_EQ(test::tilesDisagreeing(two, one, 8, 5.0, {}, &compared), 0);
        EXPECT_EQ(compared, 16);
    }
}

} // namespace
} // namespace wv
