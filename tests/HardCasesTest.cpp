// The scenes of scenes/hard/ (scripts/make_hard_scenes.py), which stress
// numerical robustness: every algorithm stays finite (pt and vcm on every
// device), scale and distance from the origin leave the image unchanged, a
// closed box lets no light in, and merge radii far from the scene's scale
// stay finite.
#include "TestDevices.h"
#include "TestRendering.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace wv {
namespace {

const char* const kHardScenes[] = {"scale-tiny", "scale-huge", "far-from-origin", "closed-box",
                                   "degenerate-geometry", "light-transport"};
const Algorithm kAlgorithms[] = {Algorithm::PathTracing,
                                 Algorithm::LightTracing,
                                 Algorithm::Bidirectional,
                                 Algorithm::ProgressivePhotonMapping,
                                 Algorithm::BidirectionalPhotonMapping,
                                 Algorithm::VertexConnectionMerging};

Scene hardScene(const std::string& name)
{
    return loadGltf(std::string(WAVEVCM_SOURCE_DIR) + "/scenes/hard/" + name + ".gltf");
}

// `scene` moved by 1e5 along each axis, camera and lights with it, without
// the loader's move back to the origin.
Scene farFromOrigin(Scene scene)
{
    const Vec3 offset(1e5f, 1e5f, 1e5f);
    for (Vec3& v : scene.vertices) v = v + offset;
    scene.camera.position = scene.camera.position + offset;
    for (Light& light : scene.lights)
        for (int k = 0; k < 3; ++k) light.position[k] += offset[k];
    return scene;
}

// Every pixel finite, and no sample dropped for being NaN or Inf: a dropped
// sample would mean some MIS quantity or pdf overflowed on the way.
void expectFinite(const test::Render& r)
{
    EXPECT_EQ(r.nonFinite, 0u) << "NaN/Inf samples were dropped";
    size_t bad = 0;
    for (float v : r.image.rgb) bad += !std::isfinite(v) || v < 0;
    EXPECT_EQ(bad, 0u) << "non-finite or negative pixels reached the image";
}

TEST(HardCases, EveryAlgorithmStaysFinite)
{
    for (const char* name : kHardScenes) {
        Scene scene = hardScene(name);
        for (const DeviceInfo& device : test::devicesUnderTest())
            for (Algorithm a : kAlgorithms) {
                // Other devices: pt and vcm, whose program has every technique
                // of the others. rusticl compiles each scene's own programs:
                // with empty caches the test took 156 s with all six, 100 s
                // with these two (PoCL alone: 2 s).
                if (!test::isFirstDevice(device) && a != Algorithm::PathTracing &&
                    a != Algorithm::VertexConnectionMerging)
                    continue;
                SCOPED_TRACE(std::string(name) + ", " + algorithmName(a) + ", " + device.name);
                expectFinite(test::render(device, scene, a, 24, 24, 2, 7));
            }
    }
}

// Radiance does not depend on scale, so the box at 1e-4 and at 1e5 units,
// and the unit box 1e5 units away, render the unit box's image: per 8×8
// block, means over 4 seeds within 5 seed-to-seed standard errors (as in the
// algorithm comparisons), on every device. Self-shadowing from offsets too
// small for the coordinates, or light leaking through offsets too large,
// changes whole blocks by far more. pt on every device, and vcm (which also
// merges, with a radius relative to the scene's size; 1e5 units out it
// failed before far scenes were moved to the origin on loading).
// far-from-origin.gltf on the first device only: the loader, on the host,
// moves it back, so the devices see the unit box again.
TEST(HardCases, ScaleAndDistanceFromTheOriginLeaveTheImageUnchanged)
{
    const int size = 32, iterations = 16, seeds = 4;
    Scene unit = loadGltf(test::cornellBoxPath());
    for (const DeviceInfo& device : test::devicesUnderTest())
        for (Algorithm a : {Algorithm::PathTracing, Algorithm::VertexConnectionMerging}) {
            if (a == Algorithm::VertexConnectionMerging && !test::isFirstDevice(device))
                continue; // vcm on the first device only: rusticl takes ~40 s for it
            std::vector<Image> reference = test::renderSeeds(device, unit, a, size, size, iterations, seeds);
            for (const char* name : {"scale-tiny", "scale-huge", "far-from-origin"}) {
                if (std::string(name) == "far-from-origin" && !test::isFirstDevice(device))
                    continue;
                SCOPED_TRACE(std::string(name) + ", " + algorithmName(a) + ", " + device.name);
                std::vector<Image> moved = test::renderSeeds(device, hardScene(name), a, size, size, iterations, seeds);
                EXPECT_EQ(test::tilesDisagreeing(moved, reference, 8, 5.0), 0);
            }
            if (a != Algorithm::PathTracing)
                continue;
            // The loader moves far-from-origin.gltf back to the origin; the
            // same box moved in code stays 1e5 units out, where pt's ray
            // offsets and intersections work on coordinates that resolve
            // only ~0.008.
            SCOPED_TRACE("moved 1e5 in code, " + device.name);
            std::vector<Image> far =
                test::renderSeeds(device, farFromOrigin(unit), a, size, size, iterations, seeds);
            EXPECT_EQ(test::tilesDisagreeing(far, reference, 8, 5.0), 0);
        }
}

// Glass of IOR 1.0 neither reflects nor bends light: a sphere of it in the
// air of the Cornell box leaves the image unchanged (same block test; light
// through it is carried by specular paths instead of shadow rays, noisier
// but unbiased). A Fresnel term or a 1/η² that did not vanish at η = 1, or
// MIS that mishandled the delta transmission, would show. On the first
// device only: the glass code's agreement across devices is
// PathTracer.SameImageOnEveryDevice's (the Cornell box's glass sphere), and
// rusticl took 24 of this test's 29 s.
TEST(HardCases, GlassOfIndexOneIsInvisible)
{
    const int size = 32, iterations = 16, seeds = 6;
    Scene plain = loadGltf(test::cornellBoxPath());
    Scene withSphere = plain;
    withSphere.materials.push_back(test::smoothGlass(1.0f));
    test::addSphere(withSphere, {0, 1.2f, 0}, 0.3f, false, int(withSphere.materials.size()) - 1);
    test::addFlatNormals(withSphere); // the box has vertex normals: the sphere's triangles get their flat ones
    DeviceInfo device = test::devicesUnderTest()[0];
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::Bidirectional, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        std::vector<Image> reference = test::renderSeeds(device, plain, a, size, size, iterations, seeds);
        std::vector<Image> glass = test::renderSeeds(device, withSphere, a, size, size, iterations, seeds);
        EXPECT_EQ(test::tilesDisagreeing(glass, reference, 8, 5.0), 0);
    }
}

// The camera sits inside a closed box of shared-edge triangles; an area
// light, a point light and the background are outside. Every algorithm, on
// every device, must render exactly black: one ray through an edge or a
// vertex, or a light vertex connected through a wall, shows. Merging runs
// with a radius of 1e-5 of the scene's: a merge joins vertices up to r
// apart, so a light vertex on a wall's outer face within r of an edge and a
// camera vertex on the inner face of the other wall at that edge can meet
// (density estimation's known leak: with the default radius 0.003, bpm at
// seeds 17 and 67 of this render lights one pixel, and at 3e-4 none); no
// leak through the geometry depends on r. Every algorithm on the first
// device, pt and vcm (every technique of the others) on the rest, as in
// EveryAlgorithmStaysFinite: lt's, ppm's and bpm's programs for this scene
// were rusticl builds of ~15 s each that no other test shares.
TEST(HardCases, ClosedBoxLetsNoLightIn)
{
    Scene scene = hardScene("closed-box");
    for (const DeviceInfo& device : test::devicesUnderTest())
        for (Algorithm a : kAlgorithms) {
            if (!test::isFirstDevice(device) && a != Algorithm::PathTracing &&
                a != Algorithm::VertexConnectionMerging)
                continue;
            SCOPED_TRACE(algorithmName(a) + ", " + device.name);
            test::Render r = test::render(device, scene, a, 32, 32, 4, 3, 10, 1e-5f);
            double sum = 0;
            for (float v : r.image.rgb) sum += v;
            EXPECT_EQ(sum, 0.0);
            EXPECT_EQ(r.nonFinite, 0u);
        }
}

// Merge radii 1e-7 and 10 times the scene's size: the merging weights and
// kernel normalisation (1 / (π r²)) stay finite on every device, and the
// image is not black (the camera sees the light directly).
TEST(HardCases, ExtremeMergeRadiiStayFinite)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    for (const DeviceInfo& device : test::devicesUnderTest())
        for (float radiusFactor : {1e-7f, 10.0f})
            for (Algorithm a : {Algorithm::ProgressivePhotonMapping, Algorithm::BidirectionalPhotonMapping,
                                Algorithm::VertexConnectionMerging}) {
                SCOPED_TRACE(algorithmName(a) + ", radius factor " + std::to_string(radiusFactor) + ", " +
                             device.name);
                test::Render r = test::render(device, scene, a, 24, 24, 2, 5, 10, radiusFactor);
                expectFinite(r);
                double sum = 0;
                for (float v : r.image.rgb) sum += v;
                EXPECT_GT(sum, 0.0) << "black image";
            }
}

// Emission of FLT_MAX (finite, but its products overflow to Inf): samples
// that come out NaN or Inf are dropped and counted by accumulate, and the
// image stays finite, in every algorithm on every device. A NaN that reached
// the hash grid or a pixel index would crash or corrupt the image instead.
// It is the Cornell box's own light that overflows (1e38 there left every
// sample finite): the scene keeps the box's features, so the test builds no
// programs of its own (~5 s each cold, one per algorithm and device).
TEST(HardCases, OverflowingSamplesAreCountedNotWritten)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    scene.path = "Cornell box with an overflowing emitter";
    int emitters = 0;
    for (Material& m : scene.materials)
        if (m.emission[0] + m.emission[1] + m.emission[2] > 0) {
            for (float& e : m.emission) e = std::numeric_limits<float>::max();
            ++emitters;
        }
    ASSERT_GT(emitters, 0);
    for (const DeviceInfo& device : test::devicesUnderTest())
        for (Algorithm a : kAlgorithms) {
            SCOPED_TRACE(algorithmName(a) + ", " + device.name);
            test::Render r = test::render(device, scene, a, 16, 16, 2, 1);
            EXPECT_GT(r.nonFinite, 0u) << "the overflowing samples were not counted";
            for (float v : r.image.rgb) ASSERT_TRUE(std::isfinite(v));
        }
}

} // namespace
} // namespace wv
