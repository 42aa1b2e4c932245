// The layers over a glTF material's lobes (kernels/materials/bsdf.h):
// KHR_materials_clearcoat's coat, rough or smooth, on opaque surfaces and on a
// refracting solid, and KHR_materials_sheen's fibres (materials/sheen.h),
// rendered alike by algorithms that weight their techniques differently.
// tests/BsdfTest.cpp checks the BSDF itself (sampling, pdfs, reciprocity,
// energy, the sheen's albedo table), tests/MisTest.cpp its MIS weights,
// tests/TextureTest.cpp the layers' textures.
#include "TestDevices.h"
#include "TestRendering.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

// scenes/cornell-box.gltf's materials, in the file's order.
enum CornellMaterial { White, Red, Green, Light, Mirror, Glass };

void addCoat(Material& m, float weight, float roughness)
{
    m.clearcoat = weight;
    m.clearcoatRoughness = roughness;
    m.lobes |= roughness * roughness < 1e-3f ? LOBE_DELTA_COAT : LOBE_GGX_COAT;
}

void addSheen(Material& m, Vec3 colour, float roughness)
{
    for (int c = 0; c < 3; ++c) m.sheenColor[c] = colour[c];
    m.sheenRoughness = roughness;
    m.lobes |= LOBE_SHEEN;
}

// The Cornell box with its surfaces layered: the green wall under a rough
// coat of weight 0.5 (a GGX coat over Lambert); the red wall under a sheen;
// the mirror sphere made a rough metal under a sheen and a smooth coat (a
// delta coat over a GGX lobe); the glass sphere made rough glass under a
// rough coat (outside only: from inside the solid the coat is crossed, not
// seen).
Scene layeredCornellBox()
{
    Scene scene = loadGltf(test::cornellBoxPath());
    Material& red = scene.materials.at(Red);
    Material& green = scene.materials.at(Green);
    Material& mirror = scene.materials.at(Mirror);
    Material& glass = scene.materials.at(Glass);
    EXPECT_EQ(mirror.lobes, LOBE_DELTA_REFLECTION);
    EXPECT_EQ(glass.lobes, LOBE_DELTA_REFLECTION | LOBE_DELTA_TRANSMISSION);
    addCoat(green, 0.5f, 0.5f);
    addSheen(red, {0.2f, 0.5f, 0.9f}, 0.4f);
    mirror.roughness = 0.4f;
    mirror.lobes = LOBE_GGX_REFLECTION;
    addSheen(mirror, {0.6f, 0.6f, 0.6f}, 0.7f);
    addCoat(mirror, 0.8f, 0.0f);
    glass.roughness = 0.3f;
    glass.lobes = LOBE_GGX_REFLECTION | LOBE_GGX_TRANSMISSION;
    addCoat(glass, 1.0f, 0.2f);
    return scene;
}

// pt, bpt and vcm agree (test::expectPtBptVcmAgree). pt sees the light
// through the rough glass with a heavy tail, as in
// tests/AbsorptionTest.cpp: 8× the iterations. A layer whose reverse pdf
// or probability differed between the techniques, or a layer's factor at
// one direction left out (a BSDF that is not reciprocal), would shift a
// block by far more.
TEST(MaterialLayers, EveryAlgorithmAgreesOnCoatsAndSheen)
{
    test::expectPtBptVcmAgree(layeredCornellBox(), 8);
}

} // namespace
} // namespace wv
