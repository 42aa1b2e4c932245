// Vertex connection through the connection queue (connect_vertices queues a
// shadow ray per camera vertex-light vertex pair, trace_connections traces
// them) against the per-path loop that traces them inline: the same seeds
// draw the same paths and evaluate the same contributions, so the images may
// differ only by the order of float adds (the queue's are atomic, in any
// order). Tolerance per 8×8 block: 1e-5 relative, about a hundred float
// roundings of the block's sum, where a lost or doubled connection changes a
// block by its whole contribution (percents). Cornell box and caustics scene
// (glass: light paths whose delta vertices are not stored, so the queue's
// per-path bound exceeds what is used), 32×32 with 256 path slots, so that
// every phase runs many rounds, and room for 700 light vertices (and as
// many queued connections), so that vcm's light paths come in batches.
// Queued with rounds enqueued ahead too: trace_connections is then launched
// over the queue's length and finds the round's count on the device.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "render/SceneBuffers.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wv {
namespace {

struct Rendered {
    Image image;
    uint64_t traced = 0; // trace_connections' work-items
};

Rendered renderWith(const DeviceInfo& info, const Scene& scene, const Bvh& bvh, Algorithm algorithm,
                    VertexConnections connections, int roundsAhead = 0)
{
    DeviceContext device(info, true);
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = s.height = 32;
    s.seed = 5;
    s.wavefront = 256;
    s.maxLightVertices = 700;
    s.vertexConnections = connections;
    s.roundsAhead = roundsAhead;
    Renderer renderer(device, scene, bvh, s);
    EXPECT_EQ(renderer.connectionQueue(), connections == VertexConnections::Queued);
    for (int i = 0; i < 2; ++i) renderer.iterate();
    Rendered r{renderer.image()};
    auto k = renderer.kernelStats().find("trace_connections");
    if (k != renderer.kernelStats().end()) r.traced = k->second.items;
    return r;
}

// Per 8×8 block and channel: |a − b| within 1e-5 of the block's sum.
int blocksDiffering(const Image& a, const Image& b)
{
    int differing = 0;
    for (int by = 0; by < a.height; by += 8)
        for (int bx = 0; bx < a.width; bx += 8)
            for (int c = 0; c < 3; ++c) {
                double sa = 0, sb = 0;
                for (int y = by; y < by + 8; ++y)
                    for (int x = bx; x < bx + 8; ++x) {
                        size_t i = 3 * (size_t(y) * a.width + x) + c;
                        sa += a.rgb[i];
                        sb += b.rgb[i];
                    }
                if (!(std::fabs(sa - sb) <= 1e-5 * std::fabs(sa) + 1e-12)) ++differing;
            }
    return differing;
}

// The Cornell box on every device, the caustics scene (GGX lobes, smooth
// normals) on the first only: each queued program is a cold compile no
// other test shares, and this test was the second longest of a CI run.
// On the other devices vcm alone: bpt's program is vcm's (the same build
// options; vcm merges by its radius), so bpt there only repeated renders.
TEST(ConnectionQueue, GivesTheImageOfTracingInline)
{
    for (std::string path : {test::cornellBoxPath(), std::string(WAVEVCM_SOURCE_DIR) + "/scenes/caustics.gltf"}) {
        SCOPED_TRACE(path);
        Scene scene = loadGltf(path);
        bool cornellBox = path == test::cornellBoxPath();
        for (const DeviceInfo& info : test::devicesUnderTest()) {
            if (!cornellBox && !test::isFirstDevice(info))
                continue;
            SCOPED_TRACE(info.name);
            // The tree this device's renders get, so that its inline program is theirs.
            Bvh bvh = buildBvh(scene.vertices, trianglePacketWidth(info));
            for (Algorithm a : {Algorithm::Bidirectional, Algorithm::VertexConnectionMerging}) {
                if (a == Algorithm::Bidirectional && !test::isFirstDevice(info))
                    continue;
                SCOPED_TRACE(algorithmName(a));
                Rendered inlined = renderWith(info, scene, bvh, a, VertexConnections::Inline);
                Rendered queued = renderWith(info, scene, bvh, a, VertexConnections::Queued);
                EXPECT_EQ(inlined.traced, 0u);
                EXPECT_GT(queued.traced, 0u);
                double sum = 0;
                for (float v : inlined.image.rgb) sum += v;
                EXPECT_GT(sum, 0.0);
                EXPECT_EQ(blocksDiffering(queued.image, inlined.image), 0);
                Rendered ahead = renderWith(info, scene, bvh, a, VertexConnections::Queued, 2);
                EXPECT_EQ(blocksDiffering(ahead.image, inlined.image), 0);
            }
        }
    }
}

} // namespace
} // namespace wv
