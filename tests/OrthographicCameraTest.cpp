// glTF's orthographic camera (kernels/lights/camera.h): parallel rays over
// [−ymag·aspect, ymag·aspect] × [−ymag, ymag] of its plane, whose direction
// is a delta, so that no light path connects to it: light tracing refuses
// it, and the bidirectional algorithms weight its technique out.
#include "Error.h"
#include "TestDevices.h"
#include "TestRendering.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

// A Lambert quad [−1, 1]² of albedo 0.5 at z = 0 under a uniform background
// of radiance 1, seen along −z by an orthographic camera of ymag 2 at
// height z.
Scene quadSeenFrom(float z)
{
    Scene s;
    s.path = "orthographic quad";
    s.background = {1, 1, 1};
    s.materials.push_back(test::lambert(0.5f));
    const Vec3 q[6] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    for (const Vec3& v : q) s.vertices.push_back(v);
    s.triangleMaterial = {0, 0};
    s.camera.position = {0, 0, z};
    s.camera.forward = {0, 0, -1};
    s.camera.orthographic = true;
    s.camera.ymag = 2;
    s.cameraFromFile = true;
    return s;
}

// The quad fills the image's middle half in x and y whatever the camera's
// distance: its inner 8×8 pixels show albedo × L = 0.5 (within 5 standard
// errors of the block), the corners the background, exactly 1. From 10×
// as far the image is the same at the same seed (the rays' origins move,
// their hits do not: relMSE below 1e-8, float rounding).
TEST(OrthographicCamera, RaysAreParallel)
{
    const int size = 32, iterations = 8;
    DeviceInfo device = test::devicesUnderTest()[0];
    Image near = test::render(device, quadSeenFrom(3), Algorithm::PathTracing, size, size, iterations, 3).image;
    Image far = test::render(device, quadSeenFrom(30), Algorithm::PathTracing, size, size, iterations, 3).image;
    double sum = 0, sq = 0;
    for (int y = 12; y < 20; ++y)
        for (int x = 12; x < 20; ++x) {
            double v = near.rgb[3 * size_t(y * size + x)];
            sum += v;
            sq += v * v;
        }
    double mean = sum / 64, se = std::sqrt(std::max(0.0, sq / 64 - mean * mean) / 64);
    EXPECT_NEAR(mean, 0.5, 5 * se + 1e-4);
    for (int y : {0, 3, 28, 31})
        for (int x : {0, 3, 28, 31}) EXPECT_FLOAT_EQ(near.rgb[3 * size_t(y * size + x)], 1.0f) << x << ", " << y;
    // Just inside and just outside the quad's edge at x = 8 (pixel 8 starts at x = −1).
    EXPECT_FLOAT_EQ(near.rgb[3 * size_t(16 * size + 7)], 1.0f);
    EXPECT_LT(near.rgb[3 * size_t(16 * size + 8)], 1.0f);
    EXPECT_LT(compareImages(far, near).relMse, 1e-8);
}

// The Cornell box through an orthographic camera: pt, bpt and vcm agree
// (test::expectPtBptVcmAgree).
// Without the light-tracing technique weighted out (its MIS start left as
// for a pinhole), bpt's and vcm's weights would not sum to one; light
// tracing itself is refused with an error that says why.
TEST(OrthographicCamera, EveryAlgorithmAgreesAndLightTracingRefuses)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    scene.camera.orthographic = true;
    scene.camera.ymag = 1.05f;
    scene.camera.position = {0, 1, 3.9f};
    scene.camera.forward = {0, 0, -1};
    scene.camera.up = {0, 1, 0};
    test::expectPtBptVcmAgree(scene, 4); // the box's glass sphere: pt's heavy tail
    try {
        test::render(test::devicesUnderTest()[0], scene, Algorithm::LightTracing, 32, 32, 1, 1);
        ADD_FAILURE() << "lt rendered through an orthographic camera";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("orthographic"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace wv
