// Several devices rendering one image (MultiDeviceRender, `-d 0,2`): each
// takes the next global iteration index, so K devices give the image of one
// running the same iterations. The same device twice (two contexts, the same
// arithmetic) must give it up to the float rounding of the weighted sum;
// PoCL with rusticl draws the same samples with other rounding, so its image
// must be far closer to the one-device image than another seed's is.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/MultiDeviceRender.h"
#include "render/SceneBuffers.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

namespace wv {
namespace {

struct Result {
    Image image;
    std::vector<int> shares;   // iterations per device
    std::vector<int> counts;   // the iterations each callback was given, in call order
    std::vector<int> running;  // runningIterations() after runningImage() in each callback
    Image lastRunning;         // runningImage() at the last callback
};

Result renderOn(const std::vector<DeviceInfo>& infos, const Scene& scene, Algorithm algorithm, int iterations,
                uint32_t seed, IterationSchedule schedule = {},
                VertexConnections connections = VertexConnections::Default)
{
    DeviceContexts contexts(infos);
    RenderSettings s;
    s.algorithm = algorithm;
    s.vertexConnections = connections;
    s.width = 32;
    s.height = 32;
    s.seed = seed;
    s.wavefront = 512;
    MultiDeviceRender render(contexts.pointers, scene, buildBvhs(scene.vertices, infos), s);
    schedule.end = iterations;
    Result r;
    render.run(schedule, 0, [] { return false; }, [&](Renderer& renderer, int done, double) {
        r.counts.push_back(done);
        r.lastRunning = render.runningImage(renderer);
        r.running.push_back(render.runningIterations());
    });
    r.image = render.image();
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

// A CPU device as two pipelines (`--pipelines 2`, the default on PoCL with
// two or more cores): each on its own OpenCL sub-device with its share of the
// compute units and of the memory, together the image of the whole device.
// On a 2-core machine each sub-device has one compute unit, where the queue
// pushes reserve their entries with an atomic per item instead of one per
// work-group (Renderer::deviceOptions): the queues then hold the same slots
// in the same order. bpt with queued vertex connections covers the
// connection queue's reservation of several entries per item.
TEST(MultiDevice, PipelinesOnSubDevicesGiveTheImageOfOne)
{
    DeviceInfo device = test::devicesUnderTest()[0];
    std::vector<DeviceInfo> pipelines = pipelineDevices(device, 2);
    ASSERT_EQ(pipelines.size(), 2u);
    EXPECT_EQ(pipelines[1].pipeline, 1);
    EXPECT_EQ(pipelines[0].globalMemory, device.globalMemory / 2);
    if (defaultPipelines(device) == 2) {
        // Partitioned: the sub-devices hold every compute unit between them.
        EXPECT_EQ(pipelines[0].computeUnits + pipelines[1].computeUnits, device.computeUnits);
        EXPECT_NE(pipelines[0].device(), device.device());
    } else {
        std::printf("[ note ] %s has %u compute unit(s) or no sub-devices: the pipelines share it\n",
                    device.name.c_str(), device.computeUnits);
    }
    EXPECT_EQ(pipelineDevices(device, 1).size(), 1u);
    Scene scene = loadGltf(test::cornellBoxPath());
    struct Case {
        Algorithm algorithm;
        VertexConnections connections;
    };
    for (Case c : {Case{Algorithm::PathTracing, VertexConnections::Default},
                   Case{Algorithm::VertexConnectionMerging, VertexConnections::Default},
                   Case{Algorithm::Bidirectional, VertexConnections::Queued}}) {
        Algorithm a = c.algorithm;
        SCOPED_TRACE(algorithmName(a));
        Result one = renderOn({device}, scene, a, 12, 5, {}, c.connections),
               two = renderOn(pipelines, scene, a, 12, 5, {}, c.connections);
        ASSERT_EQ(two.shares.size(), 2u);
        EXPECT_EQ(two.shares[0] + two.shares[1], 12);
        std::printf("[ shares ] %s: %d + %d iterations\n", algorithmName(a).c_str(), two.shares[0], two.shares[1]);
        EXPECT_LT(compareImages(two.image, one.image).relMse, 1e-10);
        // The running image (--error-log, report) after the last iteration
        // is the final one, and the callbacks counted 1, 2, …, 12.
        EXPECT_EQ(compareImages(two.lastRunning, two.image).rmse, 0.0);
        std::vector<int> expected(12);
        for (int i = 0; i < 12; ++i) expected[size_t(i)] = i + 1;
        EXPECT_EQ(two.counts, expected);
        EXPECT_EQ(two.running, expected) << "each running image holds the iterations finished so far";
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

// The schedules of an MPI job's ranks (host/cluster): rank r of K renders the
// global indices r, r + K, ... below the job's count.
TEST(MultiDevice, ScheduleCountsItsIndices)
{
    EXPECT_EQ((IterationSchedule{0, 1, 16}.count()), 16);
    EXPECT_EQ((IterationSchedule{0, 3, 8}.count()), 3); // 0 3 6
    EXPECT_EQ((IterationSchedule{2, 3, 8}.count()), 2); // 2 5
    EXPECT_EQ((IterationSchedule{3, 4, 3}.count()), 0); // a rank beyond the job's iterations
    EXPECT_EQ((IterationSchedule{1, 2, 0}.count()), -1); // no end (-t)
}

// Two interleaved schedules, summed by count as rank 0 sums the ranks'
// images, give the image of one process rendering every index: the random
// numbers and merge radius follow the global index, not the process. Run
// in pieces (as between checkpoints), a schedule goes on where it stopped.
TEST(MultiDevice, InterleavedSchedulesGiveTheImageOfOneProcess)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    DeviceInfo device = test::devicesUnderTest()[0];
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        Result one = renderOn({device}, scene, a, 7, 5);
        Result even = renderOn({device}, scene, a, 7, 5, IterationSchedule{0, 2});
        Result odd = renderOn({device}, scene, a, 7, 5, IterationSchedule{1, 2});
        ASSERT_EQ(even.shares[0], 4);
        ASSERT_EQ(odd.shares[0], 3);
        Image sum(one.image.width, one.image.height);
        for (size_t i = 0; i < sum.rgb.size(); ++i)
            sum.rgb[i] = float((double(even.image.rgb[i]) * 4 + double(odd.image.rgb[i]) * 3) / 7);
        EXPECT_LT(compareImages(sum, one.image).relMse, 1e-10);
        // The halves are other samples (ranks that all began at index 0 would
        // repeat one another): they differ by noise, not rounding.
        EXPECT_GT(compareImages(odd.image, even.image).relMse, 1e-4);
    }
    // In pieces: 3 iterations, then the rest, equal one run.
    RenderSettings s;
    s.algorithm = Algorithm::PathTracing;
    s.width = s.height = 32;
    s.seed = 5;
    s.wavefront = 512;
    const std::vector<Bvh> trees = buildBvhs(scene.vertices, {device});
    auto context = std::make_unique<DeviceContext>(device);
    MultiDeviceRender pieces({context.get()}, scene, trees, s);
    int stopAfter = 3;
    pieces.run(IterationSchedule{0, 1, 7}, 0, [&] { return pieces.iterations() >= stopAfter; }, nullptr);
    EXPECT_EQ(pieces.iterations(), 3);
    pieces.run(IterationSchedule{0, 1, 7}, 0, [] { return false; }, nullptr);
    EXPECT_EQ(pieces.iterations(), 7);
    EXPECT_LT(compareImages(pieces.image(), renderOn({device}, scene, Algorithm::PathTracing, 7, 5).image).relMse,
              1e-12);
}

// An abandoned iteration leaves the image of the iterations before it.
TEST(MultiDevice, AbandonedIterationLeavesTheImageBeforeIt)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    DeviceInfo device = test::devicesUnderTest()[0];
    RenderSettings s;
    s.algorithm = Algorithm::VertexConnectionMerging;
    s.width = s.height = 32;
    s.seed = 5;
    s.wavefront = 512; // several rounds per phase
    const std::vector<Bvh> trees = buildBvhs(scene.vertices, {device});
    auto context = std::make_unique<DeviceContext>(device);
    MultiDeviceRender render({context.get()}, scene, trees, s);
    int rounds = 0;
    bool abandoning = false;
    render.run(IterationSchedule{0, 1, 2}, 0, [] { return false; }, nullptr);
    render.run(IterationSchedule{0, 1, 3}, 0, [] { return false; }, nullptr, [&] {
        ++rounds;
        return abandoning = rounds >= 3;
    });
    EXPECT_TRUE(abandoning);
    EXPECT_EQ(render.iterations(), 2);
    Result two = renderOn({device}, scene, Algorithm::VertexConnectionMerging, 2, 5);
    // vcm's splats add in thread order: equal up to float rounding (an
    // iteration folded in, or a partial one, would be noise, ~1e-2).
    EXPECT_LT(compareImages(render.image(), two.image).relMse, 1e-12);
    // And the renderer goes on as if it had not begun it.
    render.run(IterationSchedule{0, 1, 3}, 0, [] { return false; }, nullptr);
    Result three = renderOn({device}, scene, Algorithm::VertexConnectionMerging, 3, 5);
    EXPECT_LT(compareImages(render.image(), three.image).relMse, 1e-12);
}

} // namespace
} // namespace wv
