// The sampler (kernels/core/rng.h): at the stratified bounces each sample's
// sequence over iterations is stratified in both of its 2-D pairs at every
// power of two; deeper bounces, and hashed blocks (light paths without
// vertex connection) at every bounce, draw independent numbers; draws are
// uniform and independent across iterations, samples, pairs, bounces and
// blocks.
// All draws are deterministic, so each test passes or fails the same way
// every run; the tolerances say how unlikely a failure of a truly uniform,
// independent generator would be.
#include "TestDevices.h"
#include "render/Renderer.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <vector>

namespace wv {
namespace {

using Draw = std::array<float, 4>; // x, y, z, w

struct Request {
    uint32_t seed = 7, first = 0, iterationStep = 1, firstSample = 0, sampleStep = 0, bounce = 0, block = 0;
    uint32_t hashed = 0; // rng_hashed_uniform4 instead of rng_uniform4
};

std::vector<Draw> draws(DeviceContext& device, const cl::Program& program, Request r, int n)
{
    cl::Buffer out = deviceBuffer(device, size_t(n) * sizeof(Draw), "draws");
    cl::Kernel k(program, "sampler_draws");
    int arg = 0;
    for (uint32_t v : {r.seed, r.first, r.iterationStep, r.firstSample, r.sampleStep, r.bounce, r.block, r.hashed})
        k.setArg(arg++, v);
    k.setArg(arg++, n);
    k.setArg(arg++, out);
    device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(size_t(n))), cl::NDRange(64));
    std::vector<Draw> result(static_cast<size_t>(n));
    device.queue.enqueueReadBuffer(out, CL_TRUE, 0, result.size() * sizeof(Draw), result.data());
    return result;
}

// Whether points [start, start + 2^m) are a (0, m, 2)-net: one point in each
// cell of every 2^a × 2^(m-a) grid.
bool isNet(const std::vector<Draw>& d, int cx, int cy, size_t start, int m)
{
    for (int a = 0; a <= m; ++a) {
        std::set<uint64_t> cells;
        for (size_t i = start; i < start + (size_t(1) << m); ++i) {
            auto x = uint64_t(std::ldexp(double(d[i][cx]), a));
            auto y = uint64_t(std::ldexp(double(d[i][cy]), m - a));
            if (!cells.insert(x << 32 | y).second) return false;
        }
    }
    return true;
}

// Pearson's chi-square of the points' (cx, cy) coordinates over a b × b grid.
// For n uniform, independent points it has b² - 1 degrees of freedom; the
// bound mean + 6 standard deviations is exceeded with probability < 1e-6.
double chiSquare(const std::vector<Draw>& a, int cx, const std::vector<Draw>& b, int cy, int bins)
{
    std::vector<double> count(size_t(bins * bins));
    for (size_t i = 0; i < a.size(); ++i)
        count[size_t(int(a[i][cx] * bins) * bins + int(b[i][cy] * bins))] += 1;
    double expected = double(a.size()) / (bins * bins), chi = 0;
    for (double c : count) chi += (c - expected) * (c - expected) / expected;
    return chi;
}

double chiSquareBound(int bins)
{
    double dof = bins * bins - 1;
    return dof + 6 * std::sqrt(2 * dof);
}

// RNG_STRATIFIED_BOUNCES as the kernels see it.
uint32_t stratifiedBounces(DeviceContext& device, const cl::Program& program)
{
    cl::Buffer out = deviceBuffer(device, sizeof(uint32_t), "stratified bounces");
    cl::Kernel k(program, "sampler_stratified_bounces");
    k.setArg(0, out);
    device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1));
    uint32_t n = 0;
    device.queue.enqueueReadBuffer(out, CL_TRUE, 0, sizeof(n), &n);
    return n;
}

// At each stratified bounce, every run of 2^m iterations from 0 (and the
// second such run) is a net in (y, z) and in (x, w), for several samples and
// blocks; 24-bit floats resolve cells down to 2^-12 × 2^-12.
TEST(Sampler, StratifiedAtEveryPowerOfTwo)
{
    test::onEveryDevice("sampler_tests.cl", [](DeviceContext& device, const cl::Program& program) {
    uint32_t stratified = stratifiedBounces(device, program);
    ASSERT_GE(stratified, 2u) << "the camera or light sample and the first scattering are stratified";
    for (uint32_t bounce = 0; bounce < stratified; ++bounce)
    for (Request r : {Request{7, 0, 1, 0, 0, bounce, 0}, Request{7, 0, 1, 12345, 0, bounce, 1},
                      Request{99, 0, 1, 1u << 20, 0, bounce, 3}}) {
        std::vector<Draw> d = draws(device, program, r, 1 << 13);
        for (int m = 0; m <= 12; ++m)
            for (size_t start : {size_t(0), size_t(1) << m}) {
                EXPECT_TRUE(isNet(d, 1, 2, start, m)) << "(y, z), 2^" << m << " from " << start << ", bounce " << bounce;
                EXPECT_TRUE(isNet(d, 0, 3, start, m)) << "(x, w), 2^" << m << " from " << start << ", bounce " << bounce;
            }
    }
    });
}

// One sample's draws along 65,536 iterations (r and r at the next bounce)
// are uniform in every pair of dimensions, independent of the next bounce's,
// and independent numbers, not a net: 2^8 independent points leave about
// 256/e ≈ 94 of a 16 × 16 grid's cells empty (standard deviation ≈ 5), a
// net none.
void expectIndependent(DeviceContext& device, const cl::Program& program, Request r)
{
    Request next = r;
    next.bounce = r.bounce + 1;
    std::vector<Draw> d = draws(device, program, r, 1 << 16), e = draws(device, program, next, 1 << 16);
    for (int c = 0; c < 4; ++c)
        EXPECT_LT(chiSquare(d, c, e, c, 16), chiSquareBound(16))
            << "dimension " << c << " at bounces " << r.bounce << " and " << r.bounce + 1;
    for (auto [cx, cy] :
         {std::pair{0, 1}, std::pair{1, 2}, std::pair{2, 3}, std::pair{0, 3}, std::pair{0, 2}, std::pair{1, 3}})
        EXPECT_LT(chiSquare(d, cx, d, cy, 16), chiSquareBound(16))
            << "bounce " << r.bounce << ", dimensions " << cx << ", " << cy;
    for (auto [cx, cy] : {std::pair{1, 2}, std::pair{0, 3}}) {
        std::set<uint64_t> cells;
        for (size_t i = 0; i < 256; ++i)
            cells.insert(uint64_t(d[i][cx] * 16) << 32 | uint64_t(d[i][cy] * 16));
        EXPECT_GT(256 - cells.size(), 60u)
            << "bounce " << r.bounce << ": the first 256 draws are stratified in " << cx << ", " << cy;
    }
}

TEST(Sampler, IndependentPastTheStratifiedBounces)
{
    test::onEveryDevice("sampler_tests.cl", [](DeviceContext& device, const cl::Program& program) {
    uint32_t stratified = stratifiedBounces(device, program);
    for (uint32_t bounce : {stratified, stratified + 1, 9u})
        expectIndependent(device, program, Request{7, 0, 1, 4242, 0, bounce, 1});
    });
}

// Hashed blocks (light paths of lt, ppm and bpm) are independent numbers at
// the stratified bounces too.
TEST(Sampler, HashedBlocksIndependentAtEveryBounce)
{
    test::onEveryDevice("sampler_tests.cl", [](DeviceContext& device, const cl::Program& program) {
    for (uint32_t bounce : {0u, 1u})
        expectIndependent(device, program, Request{7, 0, 1, 4242, 0, bounce, 2, 1});
    });
}

// Light paths' emission draws are stratified under vertex connection (bpt,
// vcm: light path p is the one camera sample p connects to) and independent
// under lt, ppm and bpm, with each algorithm's own program options: the
// first 256 iterations' (y, z) are a net, or leave about 94 of the 16 × 16
// cells empty (more than 60, as above).
TEST(Sampler, LightPathsStratifiedOnlyUnderVertexConnection)
{
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        SCOPED_TRACE(info.name);
        DeviceContext device(info);
        for (Algorithm a : {Algorithm::LightTracing, Algorithm::Bidirectional, Algorithm::ProgressivePhotonMapping,
                            Algorithm::BidirectionalPhotonMapping, Algorithm::VertexConnectionMerging}) {
            bool connects = a == Algorithm::Bidirectional || a == Algorithm::VertexConnectionMerging;
            cl::Program program = test::buildTestProgram(device, {test::testKernel("sampler_tests.cl")},
                                                         Renderer::programOptions(a, SceneFeatures{}, 1));
            const int n = 256;
            cl::Buffer out = deviceBuffer(device, n * sizeof(Draw), "light draws");
            cl::Kernel k(program, "sampler_light_draws");
            k.setArg(0, 7u);
            k.setArg(1, 0u);
            k.setArg(2, n);
            k.setArg(3, out);
            device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(n)), cl::NDRange(64));
            std::vector<Draw> d(n);
            device.queue.enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(Draw), d.data());
            std::set<uint64_t> cells;
            for (const Draw& u : d) cells.insert(uint64_t(u[1] * 16) << 32 | uint64_t(u[2] * 16));
            if (connects)
                EXPECT_TRUE(isNet(d, 1, 2, 0, 8)) << algorithmName(a) << ": stratified emission";
            else
                EXPECT_GT(n - int(cells.size()), 60) << algorithmName(a) << ": independent emission";
        }
    }
}

// At one iteration, 65,536 samples' draws are uniform in each pair of
// dimensions, the pairs that are stratified and those that are not, at a
// stratified bounce and a deeper one.
TEST(Sampler, UniformAcrossSamples)
{
    test::onEveryDevice("sampler_tests.cl", [](DeviceContext& device, const cl::Program& program) {
    for (uint32_t bounce : {1u, 2u})
    for (uint32_t iteration : {0u, 5u, 1000u}) {
        Request r{7, iteration, 0, 0, 1, bounce, 0};
        std::vector<Draw> d = draws(device, program, r, 1 << 16);
        for (auto [cx, cy] : {std::pair{0, 1}, std::pair{1, 2}, std::pair{2, 3}, std::pair{0, 3}, std::pair{0, 2}})
            EXPECT_LT(chiSquare(d, cx, d, cy, 16), chiSquareBound(16))
                << "bounce " << bounce << ", iteration " << iteration << ", dimensions " << cx << ", " << cy;
    }
    });
}

// Along one sample's 4,096 iterations, draws of different pairs, blocks and
// bounces are independent: without the index shuffle two pairs' points
// would be a fixed nested permutation of each other and fill only 16 of the
// 256 cells here.
TEST(Sampler, PairsBlocksAndBouncesIndependent)
{
    test::onEveryDevice("sampler_tests.cl", [](DeviceContext& device, const cl::Program& program) {
    const int n = 4096;
    Request base{7, 0, 1, 4242, 0, 1, 0};
    Request otherBlock = base, otherBounce = base, otherSeed = base;
    otherBlock.block = 1;
    otherBounce.bounce = 2;
    otherSeed.seed = 8;
    std::vector<Draw> a = draws(device, program, base, n);
    double bound = chiSquareBound(16);
    EXPECT_LT(chiSquare(a, 1, a, 0, 16), bound) << "y against x (the other pair)";
    EXPECT_LT(chiSquare(a, 2, a, 3, 16), bound) << "z against w (the other pair)";
    for (const Request& other : {otherBlock, otherBounce, otherSeed}) {
        std::vector<Draw> b = draws(device, program, other, n);
        for (int c = 0; c < 4; ++c)
            EXPECT_LT(chiSquare(a, c, b, c, 16), bound)
                << "dimension " << c << " against block " << other.block << ", bounce " << other.bounce
                << ", seed " << other.seed;
    }
    });
}

} // namespace
} // namespace wv
