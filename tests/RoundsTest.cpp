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
#include "render/SceneBuffers.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace wv {
namespace {

struct Rendered {
    Image image;
    uint64_t rays = 0;
};

Rendered renderWith(DeviceContext& device, const Scene& scene, const Bvh& bvh, Algorithm algorithm, int roundsAhead,
                    int wavefront = 256, VertexConnections connections = VertexConnections::Default)
{
    RenderSettings s;
    s.algorithm = algorithm;
    s.vertexConnections = connections;
    s.width = s.height = 32;
    s.seed = 3;
    s.wavefront = wavefront;
    s.roundsAhead = roundsAhead;
    s.maxLightVertices = 700;
    Renderer renderer(device, scene, bvh, s);
    EXPECT_EQ(renderer.roundsAhead(), roundsAhead);
    for (int i = 0; i < 2; ++i) renderer.iterate();
    if (algorithm == Algorithm::VertexConnectionMerging) EXPECT_LT(renderer.lightPathBatch(), 32 * 32);
    return {renderer.image(), renderer.raysTraced()};
}

// The same rays, and the same image up to the order of float atomic adds.
void expectSameRender(const Rendered& a, const Rendered& b)
{
    EXPECT_EQ(a.rays, b.rays);
    EXPECT_LT(compareImages(a.image, b.image).relMse, 1e-10);
}

TEST(Rounds, EnqueuedAheadGiveTheImageAndRaysOfWaitingForEach)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        DeviceContext device(info);
        SCOPED_TRACE(info.name);
        // The tree this device's renders get, so that its programs are theirs.
        Bvh bvh = buildBvh(scene.vertices, trianglePacketWidth(info));
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
                expectSameRender(r, waiting);
            }
        }
    }
}

// A path's state moves to a new slot every round (kernels/transport/
// path_state.h: slot i of the other region for hit-queue entry i, new paths
// after the hits' places), and what its shade kernel does not rewrite is
// carried along (store_continuation and its callers). How many paths share a
// wavefront changes which slots they take: with all 1024 paths at once, or 256
// or 192 of them in rounds that start new paths as others end, the image must
// be the same up to the order of float adds, and so must the rays (new paths
// put at the continuing ones' places instead: relMSE 0.002-0.2).
TEST(Rounds, ImageDoesNotDependOnTheWavefront)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    DeviceContext device(test::devicesUnderTest()[0]);
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::LightTracing, Algorithm::Bidirectional,
                        Algorithm::ProgressivePhotonMapping, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        Rendered all = renderWith(device, scene, bvh, a, 0, 32 * 32);
        for (int wavefront : {256, 192}) {
            SCOPED_TRACE("wavefront " + std::to_string(wavefront));
            Rendered r = renderWith(device, scene, bvh, a, 0, wavefront);
            expectSameRender(r, all);
        }
    }
}

// What a kernel reads must have been written this render: a field that a path's
// move to a new slot forgets to carry (store_continuation, the shade kernels)
// is read from whatever the other region held. Every device buffer starting as
// 0x00 bytes or as 0xFF bytes (WAVEVCM_POISON_BUFFERS; NaN floats, -1 ints)
// must then give the same image and rays. (Not against buffers left as
// allocated: small ones come back from the heap holding an earlier render's
// state, this test's other fill included.) Both ways of vertex connection:
// the queued one reserves its entries by the light path's count of stored
// vertices (in pathFlags). Dropped, the carry of pathFlags fails it (camera
// paths under ppm; light paths with queued connections), which RoundsTest's
// other tests and the cross-algorithm ones miss.
TEST(Rounds, ImageDoesNotDependOnWhatBuffersHeldBefore)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    DeviceContext device(test::devicesUnderTest()[0]);
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::LightTracing, Algorithm::Bidirectional,
                        Algorithm::ProgressivePhotonMapping, Algorithm::BidirectionalPhotonMapping,
                        Algorithm::VertexConnectionMerging}) {
        bool connecting = a == Algorithm::Bidirectional || a == Algorithm::VertexConnectionMerging;
        for (VertexConnections c : {VertexConnections::Inline, VertexConnections::Queued}) {
            if (c == VertexConnections::Queued && !connecting) continue;
            SCOPED_TRACE(algorithmName(a) + (c == VertexConnections::Queued ? " queued" : ""));
            ::setenv("WAVEVCM_POISON_BUFFERS", "0x00", 1);
            Rendered zeros = renderWith(device, scene, bvh, a, 0, 256, c);
            ::setenv("WAVEVCM_POISON_BUFFERS", "0xff", 1);
            Rendered ones = renderWith(device, scene, bvh, a, 0, 256, c);
            ::unsetenv("WAVEVCM_POISON_BUFFERS");
            expectSameRender(ones, zeros);
        }
    }
}

} // namespace
} // namespace wv
