// The BVH and its traversal against brute force, on every OpenCL device:
// closest hits must be bit-identical to testing every triangle with the same
// triangle routine (the traversal may only skip what cannot be hit), and
// any-hit occlusion must agree with the closest hit for every segment length.
// Ray sets include rays through shared edges and vertices, axis-parallel rays
// and rays starting on surfaces.
#include "../kernels/interface/queue_ids.h"
#include "TestDevices.h"
#include "Error.h"
#include "bvh/Bvh.h"
#include "render/KernelBindings.h"
#include "render/SceneBuffers.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>

namespace wv {
namespace {

using Float4 = std::array<float, 4>;

struct RaySet {
    std::vector<Float4> origins, directions; // directions[i][3] = tMax
    void add(Vec3 o, Vec3 d, float tMax = INFINITY)
    {
        origins.push_back({o.x, o.y, o.z, 0});
        directions.push_back({d.x, d.y, d.z, tMax});
    }
    size_t size() const { return origins.size(); }
};

// A closed cube [-1,1]^3, each face an n × n grid of quads: many shared edges
// and vertices, all on axis-aligned planes.
std::vector<Vec3> tessellatedCube(int n)
{
    std::vector<Vec3> v;
    for (int axis = 0; axis < 3; ++axis)
        for (float side : {-1.0f, 1.0f})
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    auto corner = [&](int a, int b) {
                        Vec3 p;
                        p[axis] = side;
                        p[(axis + 1) % 3] = -1.0f + 2.0f * float(a) / float(n);
                        p[(axis + 2) % 3] = -1.0f + 2.0f * float(b) / float(n);
                        return p;
                    };
                    Vec3 p00 = corner(i, j), p10 = corner(i + 1, j), p01 = corner(i, j + 1), p11 = corner(i + 1, j + 1);
                    for (Vec3 p : {p00, p10, p11, p00, p11, p01}) v.push_back(p);
                }
    return v;
}

Vec3 randomDirection(std::mt19937& rng)
{
    std::normal_distribution<float> g;
    Vec3 d;
    do d = Vec3(g(rng), g(rng), g(rng));
    while (length(d) < 1e-3f);
    return normalize(d);
}

struct Hits {
    std::vector<float> t;
    std::vector<int> triangle;
};

class Tracer {
public:
    // The tree and the brute-force reference in packets `packetWidth` wide.
    Tracer(const DeviceInfo& info, const Scene& scene, int packetWidth)
        : device_(info), bvh_(buildBvh(scene.vertices, packetWidth)),
          buffers_(device_, scene, bvh_, buildLightTable(scene, bvh_)),
          program_(test::buildTestProgram(device_, {"stages/extend.cl", test::testKernel("trace_tests.cl")},
                                          "-DTRIANGLE_PACKET_WIDTH=" + std::to_string(packetWidth))),
          allTriangleCount_(0)
    {
        // Every triangle in BVH order, for the brute-force reference.
        auto upload = [&](auto all) {
            appendPackets(scene.vertices, bvh_.triangleOrder, 0, uint32_t(scene.triangleCount()), all);
            allTriangleCount_ = all.size();
            allTriangles_ = uploadBuffer(device_, all.data(), all.size() * sizeof(all[0]), "all triangles");
        };
        if (packetWidth == 4) upload(std::vector<TrianglePacket4>());
        else upload(std::vector<TrianglePacket8>());
    }

    const Bvh& bvh() const { return bvh_; }

    Hits closest(const RaySet& rays) { return run(rays, "extend"); }
    Hits bruteForce(const RaySet& rays) { return run(rays, "brute_force_closest"); }

    std::vector<int> occluded(const RaySet& rays)
    {
        Inputs in(device_, rays);
        cl::Buffer occluded = deviceBuffer(device_, rays.size() * 4, "occlusion");
        cl::Kernel k(program_, "any_hit");
        setArgs(k, buffers_.nodes, buffers_.trianglePackets, in.origins, in.directions, int(rays.size()), occluded);
        device_.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(rays.size())), cl::NDRange(64));
        std::vector<int> out(rays.size());
        device_.queue.enqueueReadBuffer(occluded, CL_TRUE, 0, out.size() * 4, out.data());
        return out;
    }

    // Rays from points on BVH-ordered triangles, offset by the production rule.
    Hits spawned(const std::vector<int>& sources, const std::vector<std::array<float, 2>>& bary,
                 const std::vector<Float4>& directions)
    {
        size_t n = sources.size();
        cl::Buffer src = uploadBuffer(device_, sources.data(), n * 4, "sources");
        cl::Buffer b = uploadBuffer(device_, bary.data(), n * 8, "barycentrics");
        cl::Buffer d = uploadBuffer(device_, directions.data(), n * 16, "directions");
        cl::Buffer t = deviceBuffer(device_, n * 4, "t"), tri = deviceBuffer(device_, n * 4, "tri");
        cl::Kernel k(program_, "spawn_and_trace");
        setArgs(k, buffers_.nodes, buffers_.trianglePackets, buffers_.triVertices, src, b, d, int(n), t, tri);
        device_.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(n)), cl::NDRange(64));
        return read(t, tri, n);
    }

    // The scene triangle index of BVH position i.
    uint32_t sceneTriangle(int i) const { return bvh_.triangleOrder[i]; }

private:
    struct Inputs {
        cl::Buffer origins, directions, items, counters;
        Inputs(DeviceContext& dev, const RaySet& rays)
        {
            size_t n = rays.size();
            origins = uploadBuffer(dev, rays.origins.data(), n * 16, "origins");
            directions = uploadBuffer(dev, rays.directions.data(), n * 16, "directions");
            // The extend kernel's ray queue RAYS(0) holds every ray.
            std::vector<int> all(QUEUE_COUNT * n, 0);
            for (size_t i = 0; i < n; ++i) all[QUEUE_RAYS(0) * n + i] = int(i);
            items = uploadBuffer(dev, all.data(), all.size() * 4, "queue");
            std::vector<int> c(COUNTER_INDEX(COUNTER_COUNT), 0);
            c[COUNTER_INDEX(QUEUE_RAYS(0))] = int(n);
            counters = uploadBuffer(dev, c.data(), c.size() * sizeof(int), "counters");
        }
    };

    template <typename... Args> static void setArgs(cl::Kernel& k, const Args&... args)
    {
        int i = 0;
        (k.setArg(i++, args), ...);
    }

    Hits read(const cl::Buffer& t, const cl::Buffer& tri, size_t n)
    {
        Hits h;
        h.t.resize(n);
        h.triangle.resize(n);
        device_.queue.enqueueReadBuffer(t, CL_TRUE, 0, n * 4, h.t.data());
        device_.queue.enqueueReadBuffer(tri, CL_TRUE, 0, n * 4, h.triangle.data());
        return h;
    }

    Hits run(const RaySet& rays, const std::string& kernel)
    {
        Inputs in(device_, rays);
        size_t n = rays.size();
        cl::Buffer t = deviceBuffer(device_, n * 4, "t"), tri = deviceBuffer(device_, n * 4, "tri"),
                   bary = deviceBuffer(device_, n * 8, "bary");
        cl::Kernel k(program_, kernel.c_str());
        if (kernel == "extend") {
            KernelBuffers b;
            buffers_.bind(b);
            b.queueItems = in.items;
            b.queueCounters = in.counters;
            b.rayOrigins = in.origins;
            b.rayDirections = in.directions;
            b.hitT = t;
            b.hitTriangle = tri;
            b.hitBary = bary;
            LaunchParams params{};
            params.capacity = int(n);
            params.rayQueue = QUEUE_RAYS(0);
            bindBuffers(k, b);
            setLaunchParams(k, params);
        } else
            setArgs(k, allTriangles_, int(allTriangleCount_), in.origins, in.directions, int(n), t, tri);
        device_.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(n)), cl::NDRange(64));
        return read(t, tri, n);
    }

    DeviceContext device_;
    Bvh bvh_;
    SceneBuffers buffers_;
    cl::Program program_;
    cl::Buffer allTriangles_;
    size_t allTriangleCount_;
};

// Closest hits equal brute force bit for bit; where two triangles tie at the
// same t (a shared edge), either may be reported.
void expectSameClosestHits(const Hits& bvh, const Hits& brute, const char* what)
{
    ASSERT_EQ(bvh.t.size(), brute.t.size());
    int mismatches = 0;
    for (size_t i = 0; i < bvh.t.size(); ++i) {
        bool same = (bvh.triangle[i] < 0) == (brute.triangle[i] < 0) &&
                    (bvh.triangle[i] < 0 || bvh.t[i] == brute.t[i]);
        if (!same && ++mismatches <= 5)
            ADD_FAILURE() << what << " ray " << i << ": BVH hit triangle " << bvh.triangle[i] << " at t=" << bvh.t[i]
                          << ", brute force triangle " << brute.triangle[i] << " at t=" << brute.t[i];
    }
    EXPECT_EQ(mismatches, 0) << what;
}

RaySet randomRays(const Bounds& b, int count, std::mt19937& rng)
{
    RaySet rays;
    Vec3 e = b.extent();
    std::uniform_real_distribution<float> u(-0.25f, 1.25f);
    for (int i = 0; i < count; ++i) {
        Vec3 o = b.lo + Vec3(e.x * u(rng), e.y * u(rng), e.z * u(rng));
        rays.add(o, randomDirection(rng));
    }
    return rays;
}

// Rays through the cube's grid vertices and edge midpoints: from random
// points inside (a closed mesh must be hit: watertightness), from outside,
// and axis-parallel along and across the faces.
RaySet edgeAndVertexRays(const std::vector<Vec3>& v, std::mt19937& rng)
{
    RaySet rays;
    std::uniform_real_distribution<float> inside(-0.9f, 0.9f);
    for (size_t t = 0; t + 2 < v.size(); t += 3 * 7) { // a spread subset of triangles
        for (int k = 0; k < 3; ++k) {
            Vec3 targets[2] = {v[t + k], (v[t + k] + v[t + (k + 1) % 3]) * 0.5f};
            for (Vec3 target : targets) {
                Vec3 o(inside(rng), inside(rng), inside(rng));
                rays.add(o, normalize(target - o));
                rays.add(target * 3.0f, normalize(target - target * 3.0f)); // from outside, towards the centre
                for (int axis = 0; axis < 3; ++axis) {
                    Vec3 d(0, 0, 0);
                    d[axis] = 1;
                    rays.add(target - d * 5.0f, d);  // axis-parallel through the point
                }
            }
        }
    }
    return rays;
}

// Rays starting exactly on surfaces (no offset), in random directions.
RaySet surfaceRays(const std::vector<Vec3>& v, int count, std::mt19937& rng)
{
    RaySet rays;
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::uniform_int_distribution<size_t> pick(0, v.size() / 3 - 1);
    for (int i = 0; i < count; ++i) {
        size_t t = pick(rng);
        float a = u(rng), b = u(rng);
        if (a + b > 1) { a = 1 - a; b = 1 - b; }
        Vec3 p = v[3 * t] * (1 - a - b) + v[3 * t + 1] * a + v[3 * t + 2] * b;
        rays.add(p, randomDirection(rng));
    }
    return rays;
}

// On every device, with packets of four and of eight triangles (each
// device's tests take four lanes at a time, or eight where it has AVX). The
// brute force runs once per device, in packets of eight: a triangle's t does
// not depend on the packet it is tested in, and the brute force over 130K
// triangles took 24 s a packet width on llvmpipe. Devices after the first
// check every otherDeviceStride-th ray only.
void checkAgainstBruteForce(const Scene& scene, const RaySet& allRays, const char* what, size_t otherDeviceStride = 1)
{
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        RaySet rays;
        size_t stride = test::isFirstDevice(info) ? 1 : otherDeviceStride;
        for (size_t i = 0; i < allRays.size(); i += stride) {
            rays.origins.push_back(allRays.origins[i]);
            rays.directions.push_back(allRays.directions[i]);
        }
        Hits brute;
        for (int packetWidth : {8, 4}) {
            SCOPED_TRACE(info.name + " (" + info.platformName + "), packets of " + std::to_string(packetWidth));
            Tracer tracer(info, scene, packetWidth);
            if (brute.t.empty()) brute = tracer.bruteForce(rays);
            expectSameClosestHits(tracer.closest(rays), brute, what);

            // Any hit with the segment ending one ULP before the closest hit
            // must find nothing; ending just after it, must find something.
            // "Just after" is 1e-5 × the scene's size: the triangle test's t
            // carries an absolute error of a few ULPs of the vertex coordinates
            // (Woop et al. 2013, §4), the box test's a relative one, so a box
            // may be culled when the segment ends within that error of a hit.
            float slack = 1e-5f * length(scene.bounds().extent());
            RaySet shorter = rays, longer = rays;
            for (size_t i = 0; i < rays.size(); ++i) {
                float t = brute.triangle[i] >= 0 ? brute.t[i] : 1e30f;
                shorter.directions[i][3] = std::nextafter(t, 0.0f);
                longer.directions[i][3] = t + slack;
            }
            std::vector<int> before = tracer.occluded(shorter), after = tracer.occluded(longer);
            int wrong = 0;
            for (size_t i = 0; i < rays.size(); ++i) {
                bool hits = brute.triangle[i] >= 0;
                wrong += before[i] != 0;
                wrong += after[i] != int(hits);
            }
            EXPECT_EQ(wrong, 0) << what << ": occlusion disagrees with the closest hit";
        }
    }
}

// Checks the wide tree from its root: every node reached once, every child
// box inside its parent's and exactly the box of the triangles below it (a
// loose box is still correct, but rays that miss the triangles enter it),
// empty slots never hit, every BVH position in exactly one leaf
// lane with the right vertices inside its box, and no traversal needing more
// than stackBudget entries (by default what the kernels' stack holds).
// Returns the failures.
int checkStructure(const Bvh& bvh, const std::vector<Vec3>& v, int stackBudget = BVH_STACK_SIZE - 1)
{
    int failures = 0;
    auto fail = [&](const std::string& what) {
        if (++failures <= 10) ADD_FAILURE() << what;
    };
    size_t triangles = v.size() / 3;
    std::vector<int> seen(triangles, 0), nodeSeen(bvh.nodes.size(), 0), packetSeen(bvh.packetCount(), 0);
    // Returns the stack entries a traversal from node n can hold (one visit
    // pushes children - 1 more than it pops); *below gets the box of the
    // triangles under n.
    std::function<int(int, Bounds*)> visit = [&](int n, Bounds* below) -> int {
        if (n < 0 || size_t(n) >= bvh.nodes.size()) { fail("node index " + std::to_string(n) + " out of range"); return 0; }
        if (nodeSeen[n]++) { fail("node " + std::to_string(n) + " reached twice"); return 0; }
        const BvhNode& node = bvh.nodes[n];
        int children = 0, deepest = 0;
        for (int c = 0; c < BVH_WIDTH; ++c) {
            Bounds box;
            box.lo = Vec3(node.bounds[0][c], node.bounds[1][c], node.bounds[2][c]);
            box.hi = Vec3(node.bounds[3][c], node.bounds[4][c], node.bounds[5][c]);
            if (!(box.lo.x <= box.hi.x)) { // empty slot: lo = +inf, hi = -inf on every axis
                for (int a = 0; a < 3; ++a)
                    if (!(node.bounds[a][c] == INFINITY && node.bounds[3 + a][c] == -INFINITY))
                        fail("node " + std::to_string(n) + " slot " + std::to_string(c) + " neither a box nor empty");
                continue;
            }
            ++children;
            auto inside = [&](Vec3 p) {
                for (int a = 0; a < 3; ++a)
                    if (!(p[a] >= box.lo[a] && p[a] <= box.hi[a])) return false;
                return true;
            };
            int code = node.child[c];
            Bounds under;
            auto checkTight = [&] {
                bool same = true;
                for (int a = 0; a < 3; ++a) same = same && under.lo[a] == box.lo[a] && under.hi[a] == box.hi[a];
                if (!same)
                    fail("node " + std::to_string(n) + " slot " + std::to_string(c) +
                         ": its box is not its triangles' box");
                below->extend(under);
            };
            if (code >= 0) {
                if (size_t(code) < bvh.nodes.size()) {
                    const BvhNode& child = bvh.nodes[code];
                    for (int g = 0; g < BVH_WIDTH; ++g)
                        if (child.bounds[0][g] <= child.bounds[3][g] &&
                            !(inside(Vec3(child.bounds[0][g], child.bounds[1][g], child.bounds[2][g])) &&
                              inside(Vec3(child.bounds[3][g], child.bounds[4][g], child.bounds[5][g]))))
                            fail("a child of node " + std::to_string(code) + " outside its parent's box");
                }
                deepest = std::max(deepest, visit(code, &under));
                checkTight();
                continue;
            }
            int first = (~code) >> 3, packets = ((~code) & 7) + 1;
            for (int p = first; p < first + packets; ++p) {
                if (p >= int(bvh.packetCount())) { fail("packet index out of range"); break; }
                if (packetSeen[p]++) fail("packet " + std::to_string(p) + " in two leaves");
                std::visit(
                    [&](const auto& all) {
                        const auto& packet = all[p];
                        for (int lane = 0; lane < bvh.packetWidth(); ++lane) {
                            int pos = packet.triangle[lane];
                            if (pos < 0) continue;
                            if (size_t(pos) >= triangles) { fail("triangle index out of range"); continue; }
                            seen[pos]++;
                            uint32_t t = bvh.triangleOrder[pos];
                            for (int k = 0; k < 3; ++k) {
                                Vec3 vertex(packet.v[k][0][lane], packet.v[k][1][lane], packet.v[k][2][lane]);
                                if (!(vertex.x == v[3 * t + k].x && vertex.y == v[3 * t + k].y &&
                                      vertex.z == v[3 * t + k].z))
                                    fail("packet vertex differs from the scene's");
                                if (!inside(vertex)) fail("triangle " + std::to_string(t) + " outside its leaf's box");
                                under.extend(vertex);
                            }
                        }
                    },
                    bvh.packets);
            }
            checkTight();
        }
        if (children == 0) fail("node " + std::to_string(n) + " has no children");
        return children - 1 + deepest;
    };
    Bounds all;
    int stack = visit(0, &all);
    if (stack > stackBudget)
        fail("a traversal can hold " + std::to_string(stack) + " stack entries, above the budget of " +
             std::to_string(stackBudget));
    for (size_t n = 0; n < bvh.nodes.size(); ++n)
        if (!nodeSeen[n]) fail("node " + std::to_string(n) + " unreachable");
    for (size_t i = 0; i < triangles; ++i)
        if (seen[i] != 1) fail("BVH position " + std::to_string(i) + " in " + std::to_string(seen[i]) + " leaf lanes");
    std::vector<uint32_t> order = bvh.triangleOrder;
    std::sort(order.begin(), order.end());
    for (size_t i = 0; i < triangles; ++i)
        if (order[i] != i) { fail("triangleOrder is not a permutation"); break; }
    return failures;
}

// Random triangles (3,600 vertices, and 300,000: splits of 16,384 triangles or
// more near the root build their subtrees on threads, whose node lists are then
// spliced together) plus identical ones; and the degenerate inputs: all
// triangles identical, all in one plane, a single triangle, tiny and huge scales.
TEST(Bvh, StructureIsValid)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-10, 10);
    auto randomTriangles = [&](int vertices, float scale) {
        std::vector<Vec3> v;
        for (int i = 0; i < vertices; ++i) v.push_back(Vec3(u(rng), u(rng), u(rng)) * scale);
        return v;
    };
    std::vector<std::pair<std::string, std::vector<Vec3>>> inputs;
    for (int randomVertices : {3000, 300000}) {
        std::vector<Vec3> v = randomTriangles(randomVertices, 1);
        // Plus many identical triangles: centroids coincide and SAH cannot split.
        for (int i = 0; i < 600; ++i) v.push_back(Vec3(float(i % 3), 0, 0));
        inputs.push_back({std::to_string(randomVertices) + " random vertices", v});
    }
    std::vector<Vec3> identical, planar;
    for (int i = 0; i < 3000; ++i) identical.push_back(Vec3(float(i % 3), float(i % 3 == 1), 0));
    for (int i = 0; i < 30000; ++i) planar.push_back(Vec3(u(rng), u(rng), 2.5f));
    inputs.push_back({"identical triangles", identical});
    inputs.push_back({"planar triangles", planar});
    inputs.push_back({"one triangle", {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}});
    inputs.push_back({"scale 1e-4", randomTriangles(30000, 1e-5f)});
    inputs.push_back({"scale 1e5", randomTriangles(30000, 1e4f)});
    // Triangles of sizes from 1 to 4^39 (boxes whose float surface area
    // overflows) beside a cluster of small ones.
    std::vector<Vec3> scales = randomTriangles(3000, 0.01f);
    for (int i = 0; i < 40; ++i) {
        float s = std::ldexp(1.0f, 2 * i);
        for (Vec3 q : {Vec3(2, 0, 0), Vec3(2.5f, 0.5f, 0), Vec3(2, 0.5f, 0.5f)}) scales.push_back(q * s);
    }
    inputs.push_back({"sizes from 1 to 4^39", scales});
    for (const auto& [what, v] : inputs) {
        Bvh four = buildBvh(v, 4), eight = buildBvh(v, 8);
        {
            SCOPED_TRACE(what + ", packets of four");
            EXPECT_EQ(checkStructure(four, v), 0);
        }
        {
            SCOPED_TRACE(what + ", packets of eight");
            EXPECT_EQ(checkStructure(eight, v), 0);
        }
        // One binary tree serves both widths: the BVH-ordered triangle arrays
        // and the light table are the same for either.
        EXPECT_EQ(four.triangleOrder, eight.triangleOrder) << what;
    }
}

// checkStructure on a tree, its failure reports intercepted.
int silentStructureFailures(const Bvh& bvh, const std::vector<Vec3>& v, int stackBudget = BVH_STACK_SIZE - 1)
{
    ::testing::TestPartResultArray reports;
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &reports);
    return checkStructure(bvh, v, stackBudget);
}

// The check fails on a broken tree: a packet vertex moved, a triangle in two
// leaf lanes (and so another in none), a child box shrunk.
TEST(Bvh, StructureCheckDetectsBrokenTrees)
{
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-10, 10);
    std::vector<Vec3> v;
    for (int i = 0; i < 3000; ++i) v.push_back(Vec3(u(rng), u(rng), u(rng)));
    const Bvh good = buildBvh(v, 8);
    ASSERT_GT(good.packetCount(), 6u);
    EXPECT_EQ(silentStructureFailures(good, v), 0);
    Bvh moved = good, duplicated = good, shrunk = good, loose = good;
    std::get<LargeArray<TrianglePacket8>>(moved.packets)[3].v[1][0][0] += 100.0f;
    auto& packets = std::get<LargeArray<TrianglePacket8>>(duplicated.packets);
    packets[5].triangle[0] = packets[6].triangle[0];
    shrunk.nodes[0].bounds[3][0] = shrunk.nodes[0].bounds[0][0]; // child 0's box flat on x
    int leafNode = int(loose.nodes.size()) - 1; // the last node: interior children only point forward
    loose.nodes[leafNode].bounds[3][0] += 1e-3f; // child 0's box grown on x: still contains, no longer tight
    EXPECT_GT(silentStructureFailures(moved, v), 0);
    EXPECT_GT(silentStructureFailures(duplicated, v), 0);
    EXPECT_GT(silentStructureFailures(shrunk, v), 0);
    EXPECT_GT(silentStructureFailures(loose, v), 0);
}

// The collapse's stack bound (Bvh.cpp, Collapser). With the whole stack no
// test scene reaches the fallback to a binary node's two children, so the
// build is given a budget of only its binary tree's height: the eight-child
// nodes the cost model plans need more than that (checked), and the collapse
// must fall back wherever they would not fit. The tree must stay valid
// within that budget, on one core (1,000 triangles) and with subtrees
// collapsed on threads (100,000), and a budget below the height is refused.
TEST(Bvh, CollapseFitsAStackBudgetOfTheBinaryHeight)
{
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-10, 10);
    for (int vertices : {3000, 300000}) {
        SCOPED_TRACE(std::to_string(vertices) + " random vertices");
        std::vector<Vec3> v;
        for (int i = 0; i < vertices; ++i) v.push_back(Vec3(u(rng), u(rng), u(rng)));
        const Bvh planned = buildBvh(v);
        int height = planned.binaryHeight;
        ASSERT_GT(height, 4);
        EXPECT_GT(silentStructureFailures(planned, v, height), 0) << "the planned tree fits the small budget anyway";
        for (int budget : {height, height + 3}) {
            SCOPED_TRACE("budget " + std::to_string(budget));
            Bvh bvh = buildBvh(v, 8, budget);
            EXPECT_EQ(checkStructure(bvh, v, budget), 0);
            EXPECT_GT(bvh.nodes.size(), planned.nodes.size()) << "no binary nodes taken";
        }
        EXPECT_THROW(buildBvh(v, 8, height - 1), Error);
    }
}

TEST(Bvh, CornellBoxMatchesBruteForce)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    std::mt19937 rng(1);
    RaySet rays = randomRays(scene.bounds(), 20000, rng);
    RaySet onSurface = surfaceRays(scene.vertices, 5000, rng);
    rays.origins.insert(rays.origins.end(), onSurface.origins.begin(), onSurface.origins.end());
    rays.directions.insert(rays.directions.end(), onSurface.directions.begin(), onSurface.directions.end());
    checkAgainstBruteForce(scene, rays, "Cornell box");
}

// A UV sphere of 2 · segments · (rings - 1) triangles.
std::vector<Vec3> uvSphere(Vec3 centre, float radius, int segments, int rings)
{
    auto p = [&](int ring, int segment) {
        float theta = float(M_PI) * float(ring) / float(rings), phi = 2.0f * float(M_PI) * float(segment) / float(segments);
        return centre + Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)) * radius;
    };
    std::vector<Vec3> v;
    for (int r = 0; r < rings; ++r)
        for (int g = 0; g < segments; ++g) {
            if (r > 0) for (Vec3 q : {p(r, g), p(r, g + 1), p(r + 1, g)}) v.push_back(q);
            if (r < rings - 1) for (Vec3 q : {p(r, g + 1), p(r + 1, g + 1), p(r + 1, g)}) v.push_back(q);
        }
    return v;
}

// The wide tree's nodes are mostly full: on this tessellated sphere the
// least-cost collapse gives 6.9 children per node, where taking the largest
// child's children until a node has eight (the collapse before it) gave 4.8
// (3.9 on the 130K box, where half its nodes had two children, both leaves).
TEST(Bvh, WideNodesAreMostlyFull)
{
    Bvh bvh = buildBvh(uvSphere(Vec3(0, 0, 0), 1.0f, 128, 64));
    size_t children = 0;
    for (const BvhNode& node : bvh.nodes)
        for (int i = 0; i < BVH_WIDTH; ++i) children += node.bounds[0][i] <= node.bounds[3][i];
    EXPECT_GE(double(children) / double(bvh.nodes.size()), 5.5) << bvh.nodes.size() << " nodes";
}

// The benchmarks' size of scene: two spheres of 65K triangles each and a
// tessellated box around them (130K triangles); random rays, rays from the
// surfaces, and rays at the spheres' vertices.
TEST(Bvh, LargeSceneMatchesBruteForce)
{
    std::vector<Vec3> v = tessellatedCube(4);
    for (Vec3& q : v) q = q * 2.0f;
    const size_t boxVertices = v.size();
    for (Vec3 q : uvSphere(Vec3(-0.5f, -0.3f, 0.2f), 0.8f, 256, 128)) v.push_back(q);
    for (Vec3 q : uvSphere(Vec3(0.7f, 0.4f, -0.3f), 0.6f, 256, 128)) v.push_back(q);
    ASSERT_GT(v.size() / 3, 130000u);
    Scene scene = test::sceneFromTriangles(v);
    std::mt19937 rng(4);
    RaySet rays = randomRays(scene.bounds(), 3000, rng);
    RaySet onSurface = surfaceRays(scene.vertices, 1000, rng);
    rays.origins.insert(rays.origins.end(), onSurface.origins.begin(), onSurface.origins.end());
    rays.directions.insert(rays.directions.end(), onSurface.directions.begin(), onSurface.directions.end());
    std::uniform_real_distribution<float> inside(-1.5f, 1.5f);
    for (size_t t = boxVertices; t < v.size(); t += 3 * 977) { // at sphere vertices, from inside the box
        Vec3 o(inside(rng), inside(rng), inside(rng));
        rays.add(o, normalize(v[t] - o));
    }
    // Every fourth ray on devices after the first: with every ray, rusticl's
    // part of this test took ~30 s of a cold CI run.
    checkAgainstBruteForce(scene, rays, "130K-triangle scene", 4);
}

TEST(Bvh, SharedEdgesAndVerticesMatchBruteForceAndAreWatertight)
{
    std::vector<Vec3> cube = tessellatedCube(8);
    Scene scene = test::sceneFromTriangles(cube);
    std::mt19937 rng(2);
    RaySet rays = edgeAndVertexRays(cube, rng);
    checkAgainstBruteForce(scene, rays, "tessellated cube");

    // Every ray from strictly inside a closed mesh hits it.
    RaySet fromInside;
    std::uniform_real_distribution<float> inside(-0.9f, 0.9f);
    for (size_t i = 0; i < rays.size(); ++i)
        if (std::fabs(rays.origins[i][0]) < 1 && std::fabs(rays.origins[i][1]) < 1 && std::fabs(rays.origins[i][2]) < 1) {
            fromInside.origins.push_back(rays.origins[i]);
            fromInside.directions.push_back(rays.directions[i]);
        }
    ASSERT_GT(fromInside.size(), 100u);
    for (const DeviceInfo& info : test::devicesUnderTest())
    for (int packetWidth : {4, 8}) {
        SCOPED_TRACE(info.name + ", packets of " + std::to_string(packetWidth));
        Hits h = Tracer(info, scene, packetWidth).closest(fromInside);
        int misses = 0;
        for (int tri : h.triangle) misses += tri < 0;
        EXPECT_EQ(misses, 0) << "rays escaped a closed mesh through an edge or vertex";
    }
}

// Rays leaving the surface of a convex closed mesh, offset by spawn_ray: going
// outwards they must escape, going inwards they must hit another face, never
// the one they start on, at scene scales from 1e-4 to 1e5, far from the
// origin, and with faces on the planes x, y, z = 0 (where the hit point's
// error bound, and so the offset, is zero).
TEST(Bvh, SpawnedRaysNeverSelfIntersect)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    struct Placement { float scale; float shift; };
    for (Placement place : {Placement{1e-4f, 0}, Placement{1, 0}, Placement{1e5f, 0}, Placement{1, 1e5f}, Placement{1, 1}}) {
        std::vector<Vec3> cube = tessellatedCube(2);
        for (Vec3& p : cube) p = p * place.scale + Vec3(place.shift, place.shift, place.shift);
        Scene scene = test::sceneFromTriangles(cube);
        for (const DeviceInfo& info : test::devicesUnderTest()) {
            SCOPED_TRACE(info.name + " scale " + std::to_string(place.scale) + " shift " + std::to_string(place.shift));
            Tracer tracer(info, scene, trianglePacketWidth(info));
            std::vector<int> sources;
            std::vector<std::array<float, 2>> bary;
            std::vector<Float4> dirs;
            std::vector<bool> outward;
            int triangles = int(scene.triangleCount());
            for (int i = 0; i < 4000; ++i) {
                int tri = i % triangles;
                uint32_t t = tracer.sceneTriangle(tri);
                Vec3 n = normalize(cross(cube[3 * t + 1] - cube[3 * t], cube[3 * t + 2] - cube[3 * t]));
                // Face normals of tessellatedCube point outwards or inwards depending on
                // the face; orient by the face's position instead.
                Vec3 centre = (cube[3 * t] + cube[3 * t + 1] + cube[3 * t + 2]) * (1.0f / 3.0f) -
                              Vec3(place.shift, place.shift, place.shift);
                if (dot(n, centre) < 0) n = -n;
                // Barycentrics >= 0.1 keep points >= 0.1 × scale inside the faces
                // (quads of side 1 × scale), beyond the float rounding of a point
                // 1e5 from the origin (~0.01), so every start point is on the cube.
                float a = u(rng), b = u(rng);
                if (a + b > 1) { a = 1 - a; b = 1 - b; }
                a = 0.1f + 0.7f * a;
                b = 0.1f + 0.7f * b;
                Vec3 d = randomDirection(rng);
                // Keep directions at least ~1 degree away from the surface plane.
                if (std::fabs(dot(d, n)) < 0.02f) d = normalize(d + n * 0.05f);
                sources.push_back(tri);
                bary.push_back({a, b});
                dirs.push_back({d.x, d.y, d.z, 0});
                outward.push_back(dot(d, n) > 0);
            }
            Hits h = tracer.spawned(sources, bary, dirs);
            int selfHits = 0, escapedInwards = 0, hitOutwards = 0;
            for (size_t i = 0; i < sources.size(); ++i) {
                if (outward[i]) hitOutwards += h.triangle[i] >= 0;
                else if (h.triangle[i] < 0) escapedInwards++;
                else if (h.triangle[i] == sources[i]) selfHits++;
            }
            EXPECT_EQ(selfHits, 0);
            EXPECT_EQ(escapedInwards, 0);
            EXPECT_EQ(hitOutwards, 0);
        }
    }
}

} // namespace
} // namespace wv
