// The queue manager's rounds (Renderer::runPhase). With --rounds-ahead 0 the
// host reads the counters after every round and sizes the next round's
// launches by them; with N > 0 it keeps N rounds enqueued, launches over
// upper bounds and leaves the plan to plan_round on the device. Both run the
// same rounds on the same slots and samples, so they must give the same
// image (up to the order of float atomic adds: splats and merges) and count
// the same rays. A wavefront of 256 paths for 1024 pixels makes every phase
// regenerate slots over several rounds, and room for 700 light vertices
// splits vcm's light paths into batches: several phases per iteration.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

struct Rendered {
    Image image;
    uint64_t rays = 0;
};

Rendered renderWith(DeviceContext& device, const Scene& scene, const Bvh& bvh, Algorithm algorithm, int roundsAhead)
{
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = s.height = 32;
    s.seed = 3;
    s.wavefront = 256;
    s.roundsAhead = roundsAhead;
    s.maxLightVertices = 700;
    Renderer renderer(device, scene, bvh, s);
    EXPECT_EQ(renderer.roundsAhead(), roundsAhead);
    for (int i = 0; i < 2; ++i) renderer.iterate();
    if (algorithm == Algorithm::VertexConnectionMerging) EXPECT_LT(renderer.lightPathBatch(), 32 * 32);
    return {renderer.image(), renderer.raysTraced()};
}

TEST(Rounds, EnqueuedAheadGiveTheImageAndRaysOfWaitingForEach)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        DeviceContext device(info);
        SCOPED_TRACE(info.name);
        for (Algorithm a : {Algorithm::EyeLight, Algorithm::PathTracing, Algorithm::LightTracing,
                            Algorithm::VertexConnectionMerging}) {
            // Other devices: pt and vcm, whose phases (camera paths, and
            // light paths in batches) are those of el and lt too.
            if (!test::isFirstDevice(info) && a != Algorithm::PathTracing && a != Algorithm::VertexConnectionMerging)
                continue;
            SCOPED_TRACE(algorithmName(a));
            Rendered waiting = renderWith(device, scene, bvh, a, 0);
            // Eye light traces the primary rays alone: the counter is exact.
            if (a == Algorithm::EyeLight)
                EXPECT_EQ(waiting.rays, 2u * 32 * 32);
            else
                EXPECT_GT(waiting.rays, 2u * 32 * 32);
            for (int ahead : {1, 2, 3}) {
                SCOPED_TRACE("rounds ahead " + std::to_string(ahead));
                Rendered r = renderWith(device, scene, bvh, a, ahead);
                EXPECT_EQ(r.rays, waiting.rays);
                EXPECT_LT(compareImages(r.image, waiting.image).relMse, 1e-10);
            }
        }
    }
}

} // namespace
} // namespace wv
