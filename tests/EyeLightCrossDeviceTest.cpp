// `-a el` on every OpenCL implementation present gives the same image. The
// sample positions come from the counter-based generator, so the devices
// trace the same rays; what may differ is float rounding inside
// implementation-defined functions (sqrt, division, normalize: OpenCL allows
// a few ULPs), which moves pixel values by ~1e-6, and where a ray grazes a
// silhouette such a difference can flip one sample between two surfaces.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wv {
namespace {

Image renderEyeLight(const DeviceInfo& info, const Scene& scene, const Bvh& bvh, int iterations)
{
    DeviceContext device(info);
    RenderSettings s;
    s.algorithm = Algorithm::EyeLight;
    s.width = 160;
    s.height = 120;
    s.seed = 42;
    s.wavefront = 4096; // several wavefronts per iteration
    Renderer renderer(device, scene, bvh, s);
    for (int i = 0; i < iterations; ++i) renderer.iterate();
    EXPECT_EQ(renderer.nonFiniteCount(), 0u);
    return renderer.image();
}

TEST(EyeLight, SameImageOnEveryDevice)
{
    std::vector<DeviceInfo> devices = test::devicesUnderTest();
    if (devices.size() < 2) GTEST_SKIP() << "only one OpenCL device; install mesa-opencl-icd for rusticl";
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    const int iterations = 8;
    Image reference = renderEyeLight(devices[0], scene, bvh, iterations);

    // The image is not trivial: most pixels see a surface at a non-grazing angle.
    double sum = 0;
    for (float v : reference.rgb) sum += v;
    ASSERT_GT(sum / double(reference.rgb.size()), 0.3);

    for (size_t d = 1; d < devices.size(); ++d) {
        SCOPED_TRACE(devices[0].name + " vs " + devices[d].name);
        Image other = renderEyeLight(devices[d], scene, bvh, iterations);
        ASSERT_EQ(other.rgb.size(), reference.rgb.size());
        // A flipped sample changes a pixel by at most 1/iterations; rounding
        // alone by ~1e-6. Allow 1e-4 per pixel for rounding, and flips in at
        // most 0.5 % of the pixels (silhouette pixels are ~3 % of this image).
        size_t pixels = reference.rgb.size() / 3, flipped = 0;
        double maxRoundingDiff = 0;
        for (size_t p = 0; p < pixels; ++p) {
            double diff = 0;
            for (int c = 0; c < 3; ++c) diff = std::max(diff, double(std::fabs(other.rgb[3 * p + c] - reference.rgb[3 * p + c])));
            if (diff > 1e-4) ++flipped;
            else maxRoundingDiff = std::max(maxRoundingDiff, diff);
        }
        EXPECT_LE(double(flipped) / double(pixels), 0.005) << flipped << " pixels differ by more than 1e-4";
        ImageDifference diff = compareImages(other, reference);
        EXPECT_LT(diff.rmse, 2e-3);
        EXPECT_NEAR(diff.meanRatio, 1.0, 1e-3);
        std::printf("[ %s ] pixels differing > 1e-4: %zu of %zu; max difference below that: %.3g; rmse %.3g\n",
                    devices[d].name.c_str(), flipped, pixels, maxRoundingDiff, diff.rmse);
    }
}

// Different seeds give different samples (the test above would be vacuous if
// the jitter did nothing), and the same seed gives the same image.
TEST(EyeLight, SeedControlsTheSamples)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Bvh bvh = buildBvh(scene.vertices);
    DeviceInfo info = test::devicesUnderTest()[0];
    auto render = [&](uint32_t seed) {
        DeviceContext device(info);
        RenderSettings s;
        s.width = 64;
        s.height = 48;
        s.seed = seed;
        Renderer renderer(device, scene, bvh, s);
        renderer.iterate();
        return renderer.image();
    };
    Image a = render(1), b = render(1), c = render(2);
    EXPECT_EQ(a.rgb, b.rgb);
    EXPECT_NE(a.rgb, c.rgb);
}

} // namespace
} // namespace wv
