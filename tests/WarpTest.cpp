// The warps of kernels/core/sampling.h against double-precision references
// on the host: sin_cos_pi (a quarter-range polynomial turned by quarter
// turns) and the concentric disk map built on it. A wrong quadrant or wedge
// is off by order 1; the bounds allow a few float roundings.
#include "TestDevices.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace wv {
namespace {

using Float2 = std::array<float, 2>;

template <typename In>
std::vector<Float2> run(DeviceContext& device, const cl::Program& program, const char* kernel,
                        const std::vector<In>& in)
{
    int n = int(in.size());
    cl::Buffer input = uploadBuffer(device, in.data(), in.size() * sizeof(In), "inputs");
    cl::Buffer out = deviceBuffer(device, in.size() * sizeof(Float2), "outputs");
    cl::Kernel k(program, kernel);
    k.setArg(0, input);
    k.setArg(1, n);
    k.setArg(2, out);
    device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(in.size())), cl::NDRange(64));
    std::vector<Float2> result(in.size());
    device.queue.enqueueReadBuffer(out, CL_TRUE, 0, result.size() * sizeof(Float2), result.data());
    return result;
}

// Every multiple of 1/64 in [-4, 4] (the quadrant and octant boundaries
// among them) and random arguments in [-3, 3]: sine and cosine within 4e-7
// of sin(πx) and cos(πx), about three ulps of 1.
TEST(Warps, SinCosPiMatchesLibm)
{
    std::vector<float> x;
    for (int k = -256; k <= 256; ++k) x.push_back(float(k) / 64);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-3, 3);
    for (int i = 0; i < 4096; ++i) x.push_back(u(rng));
    test::onEveryDevice("warp_tests.cl", [&](DeviceContext& device, const cl::Program& program) {
        std::vector<Float2> sc = run(device, program, "sin_cos_pi_values", x);
        double worst = 0;
        for (size_t i = 0; i < x.size(); ++i) {
            double s = std::sin(M_PI * double(x[i])), c = std::cos(M_PI * double(x[i]));
            worst = std::max({worst, std::fabs(sc[i][0] - s), std::fabs(sc[i][1] - c)});
            ASSERT_NEAR(sc[i][0], s, 4e-7) << "sin(pi x) at x = " << x[i];
            ASSERT_NEAR(sc[i][1], c, 4e-7) << "cos(pi x) at x = " << x[i];
        }
        RecordProperty("worst_error", std::to_string(worst));
    });
}

// The concentric map (Shirley & Chiu) in double precision: the x-major
// wedges at angle (π/4)(oy/ox), the others at π/2 - (π/4)(ox/oy).
Float2 diskReference(double u1, double u2)
{
    double ox = 2 * u1 - 1, oy = 2 * u2 - 1;
    if (ox == 0 && oy == 0) return {0, 0};
    double r, theta;
    if (std::fabs(ox) > std::fabs(oy)) {
        r = ox;
        theta = M_PI / 4 * (oy / ox);
    } else {
        r = oy;
        theta = M_PI / 2 - M_PI / 4 * (ox / oy);
    }
    return {float(r * std::cos(theta)), float(r * std::sin(theta))};
}

// A 65 × 65 grid over the unit square (its centre, edges, corners and
// diagonals, where the wedges meet, included): within 1e-6 of the reference.
TEST(Warps, ConcentricDiskMatchesReference)
{
    std::vector<Float2> u;
    for (int i = 0; i <= 64; ++i)
        for (int j = 0; j <= 64; ++j) u.push_back({float(i) / 64, float(j) / 64});
    test::onEveryDevice("warp_tests.cl", [&](DeviceContext& device, const cl::Program& program) {
        std::vector<Float2> d = run(device, program, "disk_points", u);
        for (size_t i = 0; i < u.size(); ++i) {
            Float2 ref = diskReference(u[i][0], u[i][1]);
            ASSERT_NEAR(d[i][0], ref[0], 1e-6) << "u = (" << u[i][0] << ", " << u[i][1] << ")";
            ASSERT_NEAR(d[i][1], ref[1], 1e-6) << "u = (" << u[i][0] << ", " << u[i][1] << ")";
        }
    });
}

} // namespace
} // namespace wv
