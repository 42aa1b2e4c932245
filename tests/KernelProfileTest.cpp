// render --profile's per-kernel device times (KernelProfile): every kernel an
// iteration runs is there, the hash grid's build among them, and nothing is
// recorded on a queue without profiling.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

TEST(KernelProfile, CountsEveryKernelOfAnIterationTheHashGridsToo)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    RenderSettings s;
    s.algorithm = Algorithm::VertexConnectionMerging;
    s.width = s.height = 32;
    s.seed = 1;
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        SCOPED_TRACE(info.name);
        {
            DeviceContext device(info, true);
            Renderer renderer(device, scene, bvh, s);
            renderer.iterate();
            const auto& stats = renderer.kernelStats();
            for (const char* kernel : {"plan_round", "generate_light", "generate", "extend", "shade_light",
                                       "connect_splat", "grid_count", "scan_chunks", "scan_totals", "scan_add",
                                       "grid_scatter", "merge", "connect_vertices", "shade_bidirectional", "connect",
                                       "accumulate"}) {
                SCOPED_TRACE(kernel);
                auto k = stats.find(kernel);
                ASSERT_NE(k, stats.end());
                EXPECT_GT(k->second.items, 0u);
            }
            // Both passes of the grid's build go over the stored light
            // vertices; the chunk totals are scanned by one work-item.
            EXPECT_EQ(stats.at("grid_count").items, stats.at("grid_scatter").items);
            EXPECT_EQ(stats.at("scan_totals").items, 1u);
            double seconds = 0;
            for (const auto& [name, kernel] : stats) seconds += kernel.seconds;
            EXPECT_GT(seconds, 0.0);
        }
        DeviceContext device(info);
        Renderer renderer(device, scene, bvh, s);
        renderer.iterate();
        EXPECT_TRUE(renderer.kernelStats().empty());
    }
}

} // namespace
} // namespace wv
