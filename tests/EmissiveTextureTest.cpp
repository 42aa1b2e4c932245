// Emissive textures: emission is emissiveFactor × the texture (sRGB-decoded)
// at the point, wherever emission is evaluated — emission hits, next-event
// estimation, light sub-paths — and textured emitters are selected by the
// texture's mean. A quad seen head-on shows each texel where the bilinear
// lookup is constant; an emitter with a one-texel texture of colour c renders
// the same image as an untextured one of factor c under pt, lt and vcm (which
// has every technique), at the same seed (any technique that missed the texture would see 1/c).
#include "Error.h"
#include "TestDevices.h"
#include "TestQuad.h"
#include "TestRendering.h"
#include "bvh/Bvh.h"
#include "render/LightTable.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <array>
#include <filesystem>
#include <unistd.h>

namespace wv {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

class EmissiveTextures : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("wavevcm_emissive_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        Image four(2, 2); // red, green / blue, grey (linear; writeImage encodes sRGB)
        four.rgb = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5f, 0.5f, 0.5f};
        writeImage((dir_ / "four.png").string(), four);
        Image one(1, 1);
        one.rgb = {0.8f, 0.4f, 0.2f};
        writeImage((dir_ / "one.png").string(), one);
        Image half(2, 1); // white, black: the left half of the quad emits, fading out towards the middle
        half.rgb = {1, 1, 1, 0, 0, 0};
        writeImage((dir_ / "half.png").string(), half);
        Image redGreen(2, 1); // red, green
        redGreen.rgb = {1, 0, 0, 0, 1, 0};
        writeImage((dir_ / "redgreen.png").string(), redGreen);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // A black quad (test::writeQuad) emitting `factor`, times texture `image` if given.
    std::string emitter(const std::string& name, const std::string& image, std::array<float, 3> factor)
    {
        test::QuadFile q;
        q.material = {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"baseColorFactor", {0, 0, 0, 1}}}},
                      {"emissiveFactor", factor},
                      {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
        if (!image.empty()) {
            q.images = {image};
            q.sampler = {{"wrapS", 33071}, {"wrapT", 33071}};
            q.material["emissiveTexture"] = {{"index", 0}};
        }
        return test::writeQuad(dir_, name, q);
    }

    fs::path dir_;
};

// A white floor y = -1 before the emitter (z in [0, 4]), facing +y, and a
// camera that sees both.
void addFloor(Scene& s)
{
    s.materials.push_back(test::lambert(0.8f));
    const Vec3 floor[6] = {{-2, -1, 0}, {-2, -1, 4}, {2, -1, 4}, {-2, -1, 0}, {2, -1, 4}, {2, -1, 0}};
    for (int t = 0; t < 2; ++t) {
        for (int k = 0; k < 3; ++k) s.vertices.push_back(floor[3 * t + k]);
        s.triangleMaterial.push_back(int(s.materials.size()) - 1);
        if (!s.uvs.empty()) s.uvs.insert(s.uvs.end(), 6, 0.0f);
    }
    s.camera.position = {0, 1.5f, 4.5f};
    s.camera.forward = normalize(Vec3(0, -0.5f, 0) - s.camera.position);
    s.camera.up = {0, 1, 0};
    s.camera.yfov = 1.0f;
}

TEST_F(EmissiveTextures, LoadAndShowTheirTexels)
{
    Scene s = loadGltf(emitter("four", "four.png", {2, 2, 2}));
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.materials.at(0).emissiveTexture, 1);
    EXPECT_NEAR(s.textures[0].image.rgb[3 * 3], 0.5, 3e-3); // sRGB-encoded in the file, decoded on loading
    EXPECT_TRUE(s.features().emissiveTextures);
    EXPECT_NE(s.features().buildOptions().find("-DHAS_EMISSIVE_TEXTURES"), std::string::npos);
    EXPECT_FALSE(loadGltf(emitter("plain", "", {2, 2, 2})).features().emissiveTextures);

    const int size = 32, block = 8; // the corner blocks: u, v < 1/4 or > 3/4, one texel each
    test::Render r = test::render(test::devicesUnderTest()[0], s, Algorithm::PathTracing, size, size, 4, 1);
    for (int corner = 0; corner < 4; ++corner) {
        int x0 = (corner % 2) * (size - block), y0 = (corner / 2) * (size - block);
        for (int y = y0; y < y0 + block; ++y)
            for (int x = x0; x < x0 + block; ++x)
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(r.image.rgb[3 * size_t(y * size + x) + size_t(c)],
                                2 * s.textures[0].image.rgb[3 * size_t(corner) + size_t(c)], 1e-4)
                        << "corner " << corner << " pixel " << x << "," << y << " channel " << c;
    }
}

TEST_F(EmissiveTextures, EveryTechniqueReadsTheTexel)
{
    Scene textured = loadGltf(emitter("textured", "one.png", {1, 1, 1}));
    ASSERT_EQ(textured.textures.size(), 1u);
    const std::vector<float>& c = textured.textures[0].image.rgb; // the texel, decoded
    Scene plain = loadGltf(emitter("plain", "", {c[0], c[1], c[2]}));
    addFloor(textured);
    addFloor(plain);
    const int size = 16;
    DeviceInfo device = test::devicesUnderTest()[0];
    // vcm has every technique of bpt and bpm; each algorithm costs a kernel build per scene.
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::LightTracing, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        test::Render t = test::render(device, textured, a, size, size, 8, 4);
        test::Render p = test::render(device, plain, a, size, size, 8, 4);
        double sum = 0;
        for (size_t i = 0; i < t.image.rgb.size(); ++i) {
            // Same seed, same samples: equal up to float rounding.
            EXPECT_NEAR(t.image.rgb[i], p.image.rgb[i], 1e-4 * (1 + std::fabs(p.image.rgb[i]))) << "value " << i;
            sum += p.image.rgb[i];
        }
        EXPECT_GT(sum, 0.0) << "the floor must be lit";
    }
}

// The selection probabilities of an emissive quad's two triangles, by scene
// triangle: 1 is the top-left one, corners (-1, -1), (1, 1), (-1, 1).
std::array<float, 2> selectionOfTriangles(const std::string& file)
{
    Scene s = loadGltf(file);
    EXPECT_EQ(s.triangleCount(), 2u);
    Bvh bvh = buildBvh(s.vertices);
    LightTable table = buildLightTable(s, bvh);
    EXPECT_EQ(table.lights.size(), 2u);
    std::array<float, 2> pmf{};
    for (const Light& l : table.lights) pmf[bvh.triangleOrder[size_t(l.triangle)] % 2] = l.pmf;
    return pmf;
}

// Light selection by power counts the texture: of the quad's two triangles,
// the top-left one holds most of the emitting (left) half. Over it u has
// density 2(1 − u) and the texture is 1 for u < 1/4, 1.5 − 2u up to 3/4, 0
// beyond: mean 0.7292; the other triangle's is 1 − that (the texture is
// antisymmetric about the quad's centre), so that is also its share of the
// power. The light table estimates the mean from 16 points (within 0.03
// here); untextured, each triangle would get 1/2.
TEST_F(EmissiveTextures, SelectionFollowsTheTexturesPower)
{
    std::array<float, 2> pmf = selectionOfTriangles(emitter("half", "half.png", {1, 1, 1}));
    EXPECT_NEAR(pmf[0] + pmf[1], 1.0f, 1e-6);
    EXPECT_NEAR(pmf[1], 0.7292f, 0.03f);
}

// The power is that of factor × texel, not lum(factor) × lum(texel): a green
// factor over a red-to-green ramp (the same ramp as above in the green
// channel, its complement in red) emits only where the texture is green, so
// the top-left triangle's share is 1 − 0.7292 = 0.2708. Weighing the
// factor's and the texture's luminances apart would give it 0.376.
TEST_F(EmissiveTextures, SelectionWeighsFactorTimesTexel)
{
    std::array<float, 2> pmf = selectionOfTriangles(emitter("colour", "redgreen.png", {0, 1, 0}));
    EXPECT_NEAR(pmf[1], 0.2708f, 0.03f);
}

} // namespace
} // namespace wv
