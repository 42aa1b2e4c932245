// Alpha (glTF alphaMode): the loader reads the mode, the cutoff, the base
// colour's alpha factor and the texture's alpha channel, and rays honour it.
// A cut-out screen (MASK: its left half transparent) in front of a floor,
// under a slanting directional light, at path length 2 (direct light only:
// every pixel is exact): the camera sees the floor through the hole (closest
// hit), the floor is lit where the light passes through the hole or beside
// the screen and dark in the opaque half's shadow (any hit). A BLEND screen
// of alpha 0.3 before a uniform background shows 0.3 of itself. Every
// algorithm converges to the path tracer's image of both.
#include "Error.h"
#include "TestDevices.h"
#include "TestQuad.h"
#include "TestRendering.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace wv {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

class Alpha : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("wavevcm_alpha_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        // 2 × 2, white; alpha 0 in the left column, 1 in the right.
        Image cutout(2, 2);
        cutout.rgb.assign(12, 1.0f);
        cutout.alpha = {0, 1, 0, 1};
        writeImage((dir_ / "cutout.png").string(), cutout);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // A white Lambert screen (test::writeQuad) with alphaMode `mode`.
    std::string screen(const std::string& name, const std::string& mode, bool textured, double alphaFactor = 1.0,
                       double grey = 1.0)
    {
        test::QuadFile q;
        json pbr = {{"metallicFactor", 0.0}, {"baseColorFactor", {grey, grey, grey, alphaFactor}}};
        if (textured) {
            pbr["baseColorTexture"] = {{"index", 0}};
            q.images = {"cutout.png"};
            q.sampler = {{"wrapS", 33071}, {"wrapT", 33071}};
        }
        q.material = {{"pbrMetallicRoughness", pbr},
                      {"alphaMode", mode},
                      {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
        return test::writeQuad(dir_, name, q);
    }

    fs::path dir_;
};

// Adds a white Lambert floor [-3, 3]² at z = -1 facing +z, and a directional
// light of irradiance π from direction (1, 0, 1) (a lit white Lambert then
// shows cos 45°).
void addFloorAndLight(Scene& s)
{
    s.materials.push_back(test::lambert(1.0f));
    int material = int(s.materials.size()) - 1;
    const Vec3 corners[4] = {{-3, -3, -1}, {3, -3, -1}, {3, 3, -1}, {-3, 3, -1}};
    for (int tri : {0, 1}) {
        const int k[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int i = 0; i < 3; ++i) s.vertices.push_back(corners[k[tri][i]]);
        s.triangleMaterial.push_back(material);
        if (!s.uvs.empty()) s.uvs.insert(s.uvs.end(), 6, 0.0f);
    }
    Light light{};
    light.type = LIGHT_DIRECTIONAL;
    Vec3 d = normalize(Vec3(-1, 0, -1));
    light.direction[0] = d.x, light.direction[1] = d.y, light.direction[2] = d.z;
    for (float& e : light.emission) e = float(kPi);
    s.lights = {light};
}

TEST_F(Alpha, Load)
{
    Scene mask = loadGltf(screen("mask", "MASK", true, 0.8));
    const Material& m = mask.materials.at(0);
    EXPECT_EQ(m.alphaMode, ALPHA_MASK);
    EXPECT_FLOAT_EQ(m.alphaCutoff, 0.5f); // glTF's default
    EXPECT_FLOAT_EQ(m.baseColorAlpha, 0.8f);
    ASSERT_EQ(mask.textures.size(), 1u);
    ASSERT_EQ(mask.textures[0].image.alpha.size(), 4u);
    EXPECT_FLOAT_EQ(mask.textures[0].image.alpha[0], 0.0f);
    EXPECT_FLOAT_EQ(mask.textures[0].image.alpha[1], 1.0f);
    EXPECT_TRUE(mask.features().alphaTest);
    EXPECT_NE(mask.features().buildOptions().find("-DHAS_ALPHA_TEST"), std::string::npos);
    EXPECT_EQ(loadGltf(screen("blend", "BLEND", false)).materials.at(0).alphaMode, ALPHA_BLEND);
    Scene opaque = loadGltf(screen("opaque", "OPAQUE", true));
    EXPECT_EQ(opaque.materials.at(0).alphaMode, ALPHA_OPAQUE);
    EXPECT_FALSE(opaque.features().alphaTest);
    try {
        loadGltf(screen("bad", "SOMETIMES", false));
        ADD_FAILURE() << "an unknown alphaMode must be an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.gltf"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("SOMETIMES"), std::string::npos) << e.what();
    }
}

TEST_F(Alpha, MaskCutsOutForCameraAndShadowRays)
{
    Scene s = loadGltf(screen("mask", "MASK", true));
    addFloorAndLight(s);
    const int size = 16;
    const double lit = std::cos(kPi / 4);
    test::Render r = test::render(test::devicesUnderTest()[0], s, Algorithm::PathTracing, size, size, 4, 1, 2);
    EXPECT_EQ(r.nonFinite, 0u);
    // Column x covers the screen's x in [-1 + x/8, -1 + (x+1)/8], the floor behind it 4/3 of that.
    auto expected = [&](int column) -> double {
        if (column <= 1) return lit; // the floor, lit through the hole (x_floor < -1)
        if (column <= 7) return 0;   // the floor in the opaque half's shadow
        return lit;                  // the opaque half itself
    };
    for (int y = 4; y < 12; ++y) // rows whose floor points' shadow rays meet the screen
        for (int x : {0, 1, 3, 4, 5, 6, 9, 10, 11, 12, 13, 14})
            EXPECT_NEAR(r.image.rgb[3 * size_t(y * size + x)], expected(x), 1e-4) << "pixel " << x << "," << y;
}

TEST_F(Alpha, BlendShowsItsAlphaOfTheSurface)
{
    const double alpha = 0.3, grey = 0.5;
    Scene s = loadGltf(screen("blend", "BLEND", false, alpha, grey));
    s.background = {1, 1, 1};
    const int size = 16, iterations = 64;
    test::Render r = test::render(test::devicesUnderTest()[0], s, Algorithm::PathTracing, size, size, iterations, 1);
    // Each sample is the surface (grey × background) with probability alpha, else the background.
    double mean = 0;
    for (int p = 0; p < size * size; ++p) mean += r.image.rgb[3 * size_t(p)] / (size * size);
    double expected = alpha * grey + (1 - alpha);
    double se = (1 - grey) * std::sqrt(alpha * (1 - alpha) / (double(size * size) * iterations));
    EXPECT_NEAR(mean, expected, 5 * se) << "standard error " << se;
}

TEST_F(Alpha, EveryAlgorithmAgreesWithThePathTracer)
{
    Scene mask = loadGltf(screen("mask", "MASK", true));
    addFloorAndLight(mask);
    Scene blend = loadGltf(screen("blend", "BLEND", false, 0.3, 0.5));
    addFloorAndLight(blend);
    const int size = 16, iterations = 32, seeds = 8;
    DeviceInfo device = test::devicesUnderTest()[0];
    for (const Scene* s : {&mask, &blend}) {
        SCOPED_TRACE(s == &mask ? "MASK" : "BLEND");
        std::vector<Image> reference =
            test::renderSeeds(device, *s, Algorithm::PathTracing, size, size, iterations, seeds);
        test::expectConvergeTo(device, *s, reference,
                               {Algorithm::LightTracing, Algorithm::Bidirectional, Algorithm::VertexConnectionMerging},
                               size, size, iterations, seeds);
    }
}

} // namespace
} // namespace wv
