// Environment maps (--environment): the background's radiance from an
// equirectangular image, importance-sampled (kernels/lights/environment.h).
// Each test compares two estimators of one image per 8×8 block within 5
// seed-to-seed standard errors (test::tilesDisagreeing), a tolerance a
// correct pair exceeds by chance with probability ~1e-6 per block. A density
// 10 % too high fails the constant-map test (tried); the sampler's frame and
// its agreement with the lookup are tested in LightTest.cpp, against closed
// forms.
#include "TestDevices.h"
#include "TestRendering.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wv {
namespace {

// A diffuse floor and sphere under the open sky, seen from above.
Scene openScene()
{
    Scene s;
    s.path = "floor and sphere under an environment map";
    s.materials = {test::lambert(0.5f), test::lambert(0.8f)};
    for (Vec3 v : {Vec3(-2, 0, -2), Vec3(-2, 0, 2), Vec3(2, 0, 2), Vec3(-2, 0, -2), Vec3(2, 0, 2), Vec3(2, 0, -2)})
        s.vertices.push_back(v);
    s.triangleMaterial = {0, 0};
    test::addSphere(s, {0, 0.5f, 0}, 0.5f, false, 1, 12, 24);
    s.camera.position = {0, 2.5f, 3};
    s.camera.forward = normalize(Vec3(0, -2.2f, -3));
    s.camera.yfov = 0.9f;
    return s;
}

// A 32 × 16 sky: blue above, darker below the horizon, and a sun of 4
// texels at 40° elevation that outshines the rest; turned by 70°, so a map
// read the wrong way round puts the sun's light elsewhere.
EnvironmentMap skyMap()
{
    EnvironmentMap m;
    m.path = "test sky";
    m.image = Image(32, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            float* c = &m.image.rgb[3 * size_t(y * 32 + x)];
            bool sky = y < 8;
            c[0] = sky ? 0.3f : 0.15f;
            c[1] = sky ? 0.45f : 0.12f;
            c[2] = sky ? 0.9f : 0.1f;
            if ((y == 4 || y == 5) && (x == 9 || x == 10))
                c[0] = c[1] = c[2] = 60.0f;
        }
    m.rotation = 70;
    return m;
}

TEST(Environment, ConstantMapIsTheUniformBackground)
{
    DeviceInfo device = test::devicesUnderTest()[0];
    const int w = 32, h = 24, iterations = 16, seeds = 6;
    Scene uniform = openScene();
    uniform.background = {0.6f, 0.54f, 0.48f};
    Scene mapped = openScene();
    mapped.environment.path = "constant map";
    mapped.environment.image = Image(16, 8);
    for (size_t i = 0; i < mapped.environment.image.rgb.size(); ++i)
        mapped.environment.image.rgb[i] = 0.5f - 0.05f * float(i % 3); // × 1.2: 0.6, 0.54, 0.48
    mapped.environment.strength = 1.2f;
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        std::vector<Image> u = test::renderSeeds(device, uniform, a, w, h, iterations, seeds);
        std::vector<Image> m = test::renderSeeds(device, mapped, a, w, h, iterations, seeds);
        int compared = 0;
        EXPECT_EQ(test::tilesDisagreeing(m, u, 8, 5.0, {}, &compared), 0);
        EXPECT_EQ(compared, (w / 8) * (h / 8));
    }
}

TEST(Environment, EveryAlgorithmConvergesToOneImage)
{
    DeviceInfo device = test::devicesUnderTest()[0];
    const int w = 32, h = 24, iterations = 16, seeds = 8;
    Scene scene = openScene();
    scene.environment = skyMap();
    std::vector<Image> pt = test::renderSeeds(device, scene, Algorithm::PathTracing, w, h, iterations, seeds);
    double mean = 0;
    for (const Image& i : pt)
        for (float v : i.rgb) mean += v / double(i.rgb.size() * pt.size());
    ASSERT_GT(mean, 0.05) << "the sky should light the scene";
    test::expectConvergeTo(device, scene, pt, {Algorithm::Bidirectional, Algorithm::VertexConnectionMerging}, w, h,
                           iterations, seeds);
}

// A furnace: a convex Lambert surface of albedo a under a constant
// environment of radiance L reflects a·L everywhere (it never sees itself).
// The camera sees nothing but the sphere. pt and vcm; the mean over the
// image within 5 standard errors (a false alarm ~6e-7), which must be below
// 1 % of a·L so that a 2 % bias would show.
TEST(Environment, FurnaceInAConstantEnvironment)
{
    const float albedo = 0.6f, L = 0.75f;
    Scene scene;
    scene.path = "sphere in a constant environment";
    scene.materials = {test::lambert(albedo)};
    test::addSphere(scene, {0, 0, 0}, 1.0f, false, 0);
    scene.camera.position = {0, 0, 1.6f};
    scene.camera.forward = {0, 0, -1};
    scene.camera.yfov = 0.5f;
    scene.environment.path = "constant map";
    scene.environment.image = Image(8, 4);
    for (float& v : scene.environment.image.rgb) v = L;
    DeviceInfo device = test::devicesUnderTest()[0];
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        test::expectMean(test::render(device, scene, a, 32, 32, 16, 3), albedo * L, 0.01);
    }
}

// The same image on PoCL and rusticl under an environment map (same seeds,
// same samples), as for every other light.
TEST(Environment, SameImageOnEveryDevice)
{
    Scene scene = openScene();
    scene.environment = skyMap();
    test::expectSameImageOnEveryDevice(scene, Algorithm::PathTracing, 32, 8);
    test::expectSameImageOnEveryDevice(scene, Algorithm::VertexConnectionMerging, 32, 8);
}

} // namespace
} // namespace wv
