// glTF doubleSided on an emitter: the material emits from both faces. A
// horizontal emissive quad halfway between a floor and a ceiling (camera
// level with it, looking along +x) then lights both alike, so the image is
// its own upside-down mirror; every algorithm, whose next-event estimation,
// emission sampling and emission densities all see the second face, renders
// what pt does.
#include "TestDevices.h"
#include "TestRendering.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

void addQuad(Scene& s, Vec3 a, Vec3 b, Vec3 c, Vec3 d, int material) // a b c d counter-clockwise seen from the front
{
    for (Vec3 v : {a, b, c, a, c, d}) s.vertices.push_back(v);
    s.triangleMaterial.push_back(material);
    s.triangleMaterial.push_back(material);
}

Scene emitterBetweenFloorAndCeiling(bool doubleSided)
{
    Scene s;
    s.path = doubleSided ? "double-sided emitter" : "one-sided emitter";
    s.materials = {test::lambert(0.5f), test::lambert(0.0f, 6.0f)};
    s.materials[1].doubleSided = doubleSided ? 1 : 0;
    addQuad(s, {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, 0);             // floor, facing +y
    addQuad(s, {-3, 2, -3}, {3, 2, -3}, {3, 2, 3}, {-3, 2, 3}, 0);             // ceiling, facing −y
    addQuad(s, {-0.4f, 1, -0.4f}, {-0.4f, 1, 0.4f}, {0.4f, 1, 0.4f}, {0.4f, 1, -0.4f}, 1); // front face up
    s.camera.position = {-2.9f, 1, 0};
    s.camera.forward = {1, 0, 0};
    s.camera.up = {0, 1, 0};
    s.camera.yfov = 1.2f;
    return s;
}

std::vector<Image> upsideDown(std::vector<Image> images)
{
    for (Image& im : images) {
        Image flipped = im;
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x)
                for (int c = 0; c < 3; ++c)
                    flipped.rgb[(size_t(y) * im.width + x) * 3 + c] =
                        im.rgb[(size_t(im.height - 1 - y) * im.width + x) * 3 + c];
        im = flipped;
    }
    return images;
}

const int kWidth = 32, kHeight = 24, kIterations = 16, kSeeds = 8;

// Per 8×8 block within 5 seed-to-seed standard errors (test::tilesDisagreeing):
// the floor and the ceiling receive the same light. One-sided (emitting
// upwards), the floor gets only what the ceiling reflects, a small fraction
// (measured 0.12 of the ceiling's), which the second half checks: the image
// is then far from its mirror, so the comparison can fail.
TEST(DoubleSidedEmitter, LightsBothSidesAlike)
{
    DeviceInfo device = test::devicesUnderTest()[0];
    std::vector<Image> two = test::renderSeeds(device, emitterBetweenFloorAndCeiling(true), Algorithm::PathTracing,
                                               kWidth, kHeight, kIterations, kSeeds);
    int compared = 0;
    EXPECT_EQ(test::tilesDisagreeing(two, upsideDown(two), 8, 5.0, {}, &compared), 0);
    EXPECT_EQ(compared, (kWidth / 8) * (kHeight / 8));

    std::vector<Image> one = test::renderSeeds(device, emitterBetweenFloorAndCeiling(false), Algorithm::PathTracing,
                                               kWidth, kHeight, kIterations, kSeeds);
    double top = 0, bottom = 0;
    for (const Image& im : one)
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth * 3; ++x) (y < kHeight / 2 ? top : bottom) += im.rgb[size_t(y) * kWidth * 3 + x];
    EXPECT_LT(bottom, 0.5 * top) << "one-sided (emitting upwards), the floor (the image's bottom) is lit only indirectly";
}

TEST(DoubleSidedEmitter, EveryAlgorithmAgreesWithThePathTracer)
{
    DeviceInfo device = test::devicesUnderTest()[0];
    Scene scene = emitterBetweenFloorAndCeiling(true);
    std::vector<Image> pt = test::renderSeeds(device, scene, Algorithm::PathTracing, kWidth, kHeight, kIterations, kSeeds);
    test::expectConvergeTo(device, scene, pt,
                           {Algorithm::LightTracing, Algorithm::Bidirectional, Algorithm::VertexConnectionMerging},
                           kWidth, kHeight, kIterations, kSeeds);
}

} // namespace
} // namespace wv
