// KHR_materials_volume absorption (kernels/materials/volume.h): light that
// crosses length t inside a refracting solid keeps
// attenuationColor^(t / attenuationDistance) of itself, on every kind of
// path segment, so that every algorithm renders the same image.
#include "TestDevices.h"
#include "TestRendering.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cmath>

namespace wv {
namespace {

const float kColor[3] = {0.5f, 0.25f, 0.8f};

// Glass of index `ior` and roughness `roughness` (GGX lobes above 0) whose
// solid keeps kColor per `distance` crossed.
Material absorbingGlass(float ior, float roughness, float distance)
{
    Material m = test::smoothGlass(ior);
    if (roughness > 0) {
        m.roughness = roughness;
        m.lobes = LOBE_GGX_REFLECTION | LOBE_GGX_TRANSMISSION;
    }
    m.thinWalled = 0;
    m.attenuationDistance = distance;
    for (int c = 0; c < 3; ++c) m.attenuationColor[c] = kColor[c];
    return m;
}

// An axis-aligned box, its triangles counter-clockwise seen from outside.
void addBox(Scene& s, Vec3 lo, Vec3 hi, int material)
{
    auto corner = [&](int i) { return Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z); };
    // Each face's corners in counter-clockwise order seen from outside.
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : faces)
        for (int t : {1, 2}) { // the fan (0, 1, 2), (0, 2, 3)
            for (int k : {0, t, t + 1}) s.vertices.push_back(corner(f[k]));
            s.triangleMaterial.push_back(material);
        }
}

// Through a box of index-1 glass (which neither reflects nor bends light) 2
// deep, against a uniform white background, every camera ray keeps kColor²
// (attenuationDistance 1): exactly, up to the rays' slant (at most 0.035
// rad here, so paths 1.0006× longer and kColor² 0.2 % lower in green's
// 0.25 channel at worst), since these all-specular paths are sampled by
// the camera path alone. Every algorithm that renders what the camera sees
// through specular surfaces (not lt).
TEST(Absorption, GlassOfIndexOneKeepsBeerLambertsFraction)
{
    Scene scene;
    scene.path = "absorbing box";
    scene.background = {1, 1, 1};
    scene.materials.push_back(absorbingGlass(1.0f, 0.0f, 1.0f));
    addBox(scene, {-1, -1, -4}, {1, 1, -2}, 0);
    scene.camera.position = {0, 0, 0};
    scene.camera.forward = {0, 0, -1};
    scene.camera.yfov = 0.05f;
    ASSERT_NE(scene.features().buildOptions().find("HAS_VOLUME_ABSORPTION"), std::string::npos);
    DeviceInfo device = test::devicesUnderTest()[0];
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::Bidirectional, Algorithm::ProgressivePhotonMapping,
                        Algorithm::BidirectionalPhotonMapping, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        test::Render r = test::render(device, scene, a, 16, 16, 2, 1);
        EXPECT_EQ(r.nonFinite, 0u);
        size_t pixels = r.image.rgb.size() / 3;
        for (int c = 0; c < 3; ++c) {
            double mean = 0;
            for (size_t p = 0; p < pixels; ++p) mean += r.image.rgb[3 * p + size_t(c)] / double(pixels);
            double expected = double(kColor[c]) * kColor[c];
            EXPECT_NEAR(mean, expected, 0.003 * expected) << "channel " << c;
        }
    }
}

// The Cornell box with a rough absorbing glass sphere (clear of its two
// spheres), and a point light at the sphere's centre if `lightInside`.
Scene boxWithAbsorbingSphere(bool lightInside)
{
    const Vec3 centre(0.0f, 1.3f, 1.0f);
    Scene scene = loadGltf(test::cornellBoxPath());
    scene.materials.push_back(absorbingGlass(1.5f, 0.55f, 0.3f));
    test::addSphere(scene, centre, 0.6f, false, int(scene.materials.size()) - 1);
    test::addFlatNormals(scene); // the box has vertex normals: the sphere's triangles get their flat ones
    if (lightInside) {
        Light light{};
        light.type = LIGHT_POINT;
        for (int c = 0; c < 3; ++c) {
            light.position[c] = centre[c];
            light.emission[c] = 2.0f;
        }
        scene.lights.push_back(light);
    }
    return scene;
}

// pt, bpt and vcm agree (test::expectPtBptVcmAgree). pt reaches the light
// through the rough glass rarely and with a heavy tail (next-event estimation
// from the sphere's surface, or BSDF sampling): 8× the iterations, for the
// seed-to-seed spread to measure its error.
void expectAgreement(const Scene& scene) { test::expectPtBptVcmAgree(scene, 8); }

// Light seen through the sphere crosses it: bpt and vcm connect a camera
// vertex on its surface to a light vertex on its far side, across it; pt
// extends its camera path through it. Leaving the connections' absorption
// out fails.
TEST(Absorption, EveryAlgorithmAgreesThroughAbsorbingGlass) { expectAgreement(boxWithAbsorbingSphere(false)); }

// A point light inside the sphere: its light leaves along segments inside
// of every kind (light paths to the inner surface, next-event shadow rays
// from the outer surface, connections across). Leaving next-event
// estimation's absorption out (pt's or the bidirectional one) fails.
TEST(Absorption, EveryAlgorithmAgreesAroundALightInsideAbsorbingGlass) { expectAgreement(boxWithAbsorbingSphere(true)); }

} // namespace
} // namespace wv
