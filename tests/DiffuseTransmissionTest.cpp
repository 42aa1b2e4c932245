// KHR_materials_diffuse_transmission (kernels/materials/bsdf.h): Lambert
// through a thin wall, and into and out of an absorbing solid, rendered
// alike by algorithms that weight their techniques differently.
// tests/BsdfTest.cpp checks the lobe itself (sampling, pdfs, reciprocity,
// energy), tests/MisTest.cpp its MIS weights, tests/GltfLoaderTest.cpp and
// tests/TextureTest.cpp what the loader reads.
#include "TestDevices.h"
#include "TestRendering.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

// scenes/cornell-box.gltf's materials, in the file's order.
enum CornellMaterial { White, Red, Green, Light, Mirror, Glass };

// The Cornell box with a hollow paper lantern for the mirror sphere (a thin
// wall that reflects and transmits diffusely under a rough specular layer)
// and a wax ball for the glass one: a solid that light enters and leaves
// only diffusely, absorbing on the way (KHR_materials_volume), with a rough
// specular layer that reflects totally inside beyond the critical angle.
Scene translucentCornellBox()
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Material& lantern = scene.materials.at(Mirror);
    Material& wax = scene.materials.at(Glass);
    EXPECT_EQ(lantern.lobes, LOBE_DELTA_REFLECTION);
    EXPECT_EQ(wax.lobes, LOBE_DELTA_REFLECTION | LOBE_DELTA_TRANSMISSION);
    EXPECT_EQ(wax.thinWalled, 0);
    for (Material* m : {&lantern, &wax}) {
        m->metallic = 0;
        m->transmission = 0;
        m->roughness = 0.5f;
        m->specular = 1;
        m->lobes = LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_DIFFUSE_TRANSMISSION;
    }
    lantern.thinWalled = 1;
    lantern.diffuseTransmission = 0.6f;
    const float paper[3] = {0.9f, 0.8f, 0.6f}, base[3] = {0.9f, 0.9f, 0.8f}, tint[3] = {1.0f, 0.7f, 0.5f};
    for (int c = 0; c < 3; ++c) {
        lantern.baseColor[c] = paper[c];
        lantern.diffuseTransmissionColor[c] = paper[c];
        wax.baseColor[c] = base[c];
        wax.diffuseTransmissionColor[c] = 1;
        wax.attenuationColor[c] = tint[c];
    }
    wax.diffuseTransmission = 0.8f;
    wax.attenuationDistance = 0.3f;
    return scene;
}

// pt, bpt and vcm agree (test::expectPtBptVcmAgree; pt with 8× the
// iterations, as for the layered box). A reverse pdf that differed between
// the techniques (the far side's lobe probabilities taken with the near
// side's index) shifts blocks by 5.5–10 standard errors. What the model
// itself says — refraction's η², which cancels on a path that enters the
// ball and leaves it, and the critical angle inside — every technique sees
// alike: tests/BsdfTest.cpp checks those (reciprocity, energy).
TEST(DiffuseTransmission, EveryAlgorithmAgreesOnALanternAndAWaxBall)
{
    test::expectPtBptVcmAgree(translucentCornellBox(), 8);
}

} // namespace
} // namespace wv
