// The hash grid built on the device against brute force, on every device:
// every light vertex within r of a query point is found, exactly once, and
// none outside, for clustered and spread vertices, negative coordinates, and
// grids with far fewer buckets than cells (hash collisions).
#include "TestDevices.h"
#include "render/HashGrid.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <array>
#include <random>

namespace wv {
namespace {

struct Case {
    const char* what;
    int vertices;
    float spread; // vertices uniform in [-spread, spread]^3, half of them in a small cluster
    float radius;
};

// The grid built from the light-vertex buffer as each algorithm stores it:
// LightVertex records under vertex connection (bpt, vcm), merging's own
// MergeVertex records with merging only (ppm, bpm).
void checkCase(const DeviceInfo& info, const Case& c, bool vertexConnection)
{
    SCOPED_TRACE(std::string(c.what) + (vertexConnection ? ", LightVertex records" : ", MergeVertex records") +
                 " on " + info.name);
    DeviceContext device(info);
    cl::Program program = test::buildTestProgram(device, {"stages/hash_grid.cl", test::testKernel("grid_tests.cl")},
                                                 vertexConnection ? "-DVERTEX_CONNECTION" : "");
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-c.spread, c.spread), cluster(-3 * c.radius, 3 * c.radius);
    std::vector<LightVertex> lightVertices(vertexConnection ? size_t(c.vertices) : 0);
    std::vector<MergeVertex> mergeVertices(vertexConnection ? 0 : size_t(c.vertices));
    std::vector<Vec3> positions;
    for (int i = 0; i < c.vertices; ++i) {
        Vec3 p = i % 2 ? Vec3(u(rng), u(rng), u(rng)) : Vec3(0.3f, -0.7f, 0.1f) + Vec3(cluster(rng), cluster(rng), cluster(rng));
        // The grid copies pathLength: the query kernel sums it as the vertex's index.
        if (vertexConnection) {
            lightVertices[i] = LightVertex{};
            for (int a = 0; a < 3; ++a) lightVertices[i].surface.position[a] = p[a];
            lightVertices[i].pathLength = i;
        } else {
            mergeVertices[i] = MergeVertex{};
            for (int a = 0; a < 3; ++a) mergeVertices[i].position[a] = p[a];
            mergeVertices[i].pathLength = i;
        }
        positions.push_back(p);
    }
    // Queries: near vertices (within ~r), and anywhere.
    std::vector<std::array<float, 4>> queries;
    std::uniform_real_distribution<float> jitter(-c.radius, c.radius);
    for (int q = 0; q < 4000; ++q) {
        Vec3 x = q % 2 ? positions[size_t(q) % positions.size()] + Vec3(jitter(rng), jitter(rng), jitter(rng))
                       : Vec3(u(rng), u(rng), u(rng));
        queries.push_back({x.x, x.y, x.z, 0});
    }
    cl::Buffer vertexBuffer =
        vertexConnection
            ? uploadBuffer(device, lightVertices.data(), lightVertices.size() * sizeof(LightVertex), "vertices")
            : uploadBuffer(device, mergeVertices.data(), mergeVertices.size() * sizeof(MergeVertex), "vertices");
    HashGrid grid(device, program);
    grid.reserve(size_t(c.vertices));
    grid.build(vertexBuffer, c.vertices, c.radius);

    size_t n = queries.size();
    cl::Buffer queryBuffer = uploadBuffer(device, queries.data(), n * 16, "queries");
    cl::Buffer found = deviceBuffer(device, n * 4, "found"), sums = deviceBuffer(device, n * 8, "sums");
    cl::Kernel k(program, "grid_query");
    int arg = 0;
    k.setArg(arg++, vertexBuffer);
    k.setArg(arg++, grid.bucketStarts());
    k.setArg(arg++, grid.bucketVertices());
    k.setArg(arg++, grid.buckets());
    k.setArg(arg++, c.radius);
    k.setArg(arg++, queryBuffer);
    k.setArg(arg++, int(n));
    k.setArg(arg++, found);
    k.setArg(arg++, sums);
    device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(n)), cl::NDRange(64));
    std::vector<int> counts(n);
    std::vector<int64_t> indexSums(n);
    device.queue.enqueueReadBuffer(found, CL_TRUE, 0, n * 4, counts.data());
    device.queue.enqueueReadBuffer(sums, CL_TRUE, 0, n * 8, indexSums.data());

    int wrong = 0, nonEmpty = 0;
    for (size_t q = 0; q < n; ++q) {
        // Brute force with the kernel's own float arithmetic: d = p − x, |d|² ≤ r².
        int expected = 0;
        int64_t expectedSum = 0;
        for (int i = 0; i < c.vertices; ++i) {
            float dx = positions[i].x - queries[q][0], dy = positions[i].y - queries[q][1], dz = positions[i].z - queries[q][2];
            if (dx * dx + dy * dy + dz * dz <= c.radius * c.radius) {
                ++expected;
                expectedSum += i;
            }
        }
        nonEmpty += expected > 0;
        if ((counts[q] != expected || indexSums[q] != expectedSum) && ++wrong <= 5)
            ADD_FAILURE() << "query " << q << ": grid found " << counts[q] << " (index sum " << indexSums[q]
                          << "), brute force " << expected << " (" << expectedSum << ")";
    }
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(nonEmpty, int(n) / 10) << "the test must exercise non-empty queries";
}

TEST(HashGrid, RangeQueriesMatchBruteForce)
{
    const Case cases[] = {
        {"many vertices, small radius", 100000, 1.0f, 0.01f},
        {"few vertices, large radius", 3000, 1.0f, 0.2f},
        {"far from the origin, negative coordinates", 20000, 1e4f, 20.0f},
        // 1024 buckets for ~10^9 cells: neighbouring cells share buckets, which
        // must not be visited twice.
        {"hash collisions", 1000, 1.0f, 0.001f},
    };
    for (const DeviceInfo& info : test::devicesUnderTest())
        for (const Case& c : cases)
            for (bool vertexConnection : {true, false}) checkCase(info, c, vertexConnection);
}

} // namespace
} // namespace wv
