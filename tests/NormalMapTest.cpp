// Normal maps (glTF normalTexture): the loader reads the texture, its scale
// and the tangents (TANGENT, or made from the texture coordinates), and the
// kernels shade with the mapped normal. A Lambert quad facing the camera
// under a directional light renders ρ/π · E · (n'·l) exactly (one light, no
// other surface: next-event estimation is the whole image), so a tilted map
// must brighten the quad towards the light it leans to and darken it away,
// on the quad's u axis, its image-up (−v) axis, with mirrored texture
// coordinates and with a TANGENT attribute alike. A flat map changes nothing.
#include "Error.h"
#include "TestDevices.h"
#include "TestQuad.h"
#include "TestRendering.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace wv {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

class NormalMaps : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("wavevcm_normal_maps_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        // 1 × 1 maps (8-bit PNG, stored as data: no sRGB decoding): flat, and
        // leaning 30° towards the texture's +X and +Y.
        const double s = std::sin(kPi / 6), c = std::cos(kPi / 6);
        writeMap("flat.png", 0, 0, 1);
        writeMap("plus_x.png", s, 0, c);
        writeMap("plus_y.png", 0, s, c);
    }
    void TearDown() override { fs::remove_all(dir_); }

    void writeMap(const std::string& name, double x, double y, double z)
    {
        Image map(1, 1);
        map.rgb = {float(0.5 * x + 0.5), float(0.5 * y + 0.5), float(0.5 * z + 0.5)};
        srgbToLinear(map); // writeImage encodes 8-bit files as sRGB: the file then holds these values
        writeImage((dir_ / name).string(), map);
    }

    // A white Lambert quad (test::writeQuad) with normal map `image` (none if
    // empty), mirrored texture coordinates (u along −x) if asked, and TANGENT
    // if `tangents` has one (x, y, z, w) per corner.
    std::string quad(const std::string& name, const std::string& image, bool mirrored = false,
                     std::vector<float> tangents = {}, double scale = 1.0)
    {
        test::QuadFile q;
        q.material = {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
                      {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
        if (!image.empty()) {
            q.images = {image};
            q.material["normalTexture"] = {{"index", 0}, {"scale", scale}};
        }
        if (mirrored) q.uv = {1, 1, 0, 1, 0, 0, 1, 0};
        q.tangents = std::move(tangents);
        return test::writeQuad(dir_, name, q);
    }

    fs::path dir_;
};

// The mapped normal the quad (normal +z) should shade with: the texel as
// stored, 2c − 1, x and y times `scale`, in the frame (tangent, bitangent, +z).
Vec3 mappedNormal(const Scene& s, Vec3 tangent, Vec3 bitangent, double scale = 1.0)
{
    const std::vector<float>& c = s.textures.at(0).image.rgb;
    Vec3 n = tangent * float((2 * c[0] - 1) * scale) + bitangent * float((2 * c[1] - 1) * scale) +
             Vec3(0, 0, 1) * (2 * c[2] - 1);
    return normalize(n);
}

// The quad's mean pixel value (red) under a directional light of irradiance
// π from direction `toLight` (so the value is n'·l for the white Lambert), pt.
double litValue(Scene s, Vec3 toLight)
{
    Light light{};
    light.type = LIGHT_DIRECTIONAL;
    Vec3 d = normalize(toLight) * -1.0f;
    light.direction[0] = d.x, light.direction[1] = d.y, light.direction[2] = d.z;
    for (float& e : light.emission) e = float(kPi);
    s.lights = {light};
    const int size = 16;
    test::Render r = test::render(test::devicesUnderTest()[0], s, Algorithm::PathTracing, size, size, 4, 3);
    EXPECT_EQ(r.nonFinite, 0u);
    double sum = 0;
    for (int p = 0; p < size * size; ++p) sum += r.image.rgb[3 * size_t(p)];
    return sum / (size * size);
}

TEST_F(NormalMaps, LoadWithTangents)
{
    Scene s = loadGltf(quad("standard", "plus_x.png", false, {}, 0.5));
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.materials.at(0).normalTexture, 1);
    EXPECT_FLOAT_EQ(s.materials.at(0).normalScale, 0.5f);
    EXPECT_NEAR(s.textures[0].image.rgb[0], 0.75, 3e-3); // data: not sRGB-decoded
    EXPECT_TRUE(s.features().normalMaps);
    EXPECT_NE(s.features().buildOptions().find("-DHAS_NORMAL_MAPS"), std::string::npos);
    // Made from the UVs: along +u, and w = +1 where cross(n, t) points along −v (+y here).
    ASSERT_EQ(s.tangents.size(), 3 * s.triangleCount());
    for (const auto& t : s.tangents) {
        EXPECT_NEAR(t[0], 1, 1e-6);
        EXPECT_NEAR(t[1], 0, 1e-6);
        EXPECT_NEAR(t[2], 0, 1e-6);
        EXPECT_EQ(t[3], 1.0f);
    }
    // Mirrored: u runs along −x, so cross(n, t) = −y points along +v: w = −1.
    Scene mirrored = loadGltf(quad("mirrored", "plus_x.png", true));
    for (const auto& t : mirrored.tangents) {
        EXPECT_NEAR(t[0], -1, 1e-6);
        EXPECT_EQ(t[3], -1.0f);
    }
    // TANGENT is read as given (here against the UVs, to tell it from a made one).
    Scene given = loadGltf(quad("given", "plus_x.png", false, {0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1}));
    for (const auto& t : given.tangents) {
        EXPECT_NEAR(t[1], 1, 1e-6);
        EXPECT_EQ(t[3], -1.0f);
    }
    // No normal map: no tangents, no kernel flag.
    Scene plain = loadGltf(quad("plain", ""));
    EXPECT_TRUE(plain.tangents.empty());
    EXPECT_FALSE(plain.features().normalMaps);
}

TEST_F(NormalMaps, FlatMapChangesNothing)
{
    Scene flat = loadGltf(quad("flat", "flat.png"));
    Scene plain = loadGltf(quad("plain", ""));
    Vec3 toLight(1, 0.5f, 1);
    double expected = dot(normalize(toLight), Vec3(0, 0, 1));
    EXPECT_NEAR(litValue(plain, toLight), expected, 1e-4);
    // 8-bit 0.5 is 128/255: the "flat" map leans by 0.004 rad.
    EXPECT_NEAR(litValue(flat, toLight), dot(normalize(toLight), mappedNormal(flat, {1, 0, 0}, {0, 1, 0})), 1e-4);
    EXPECT_NEAR(litValue(flat, toLight), expected, 1e-2);
}

TEST_F(NormalMaps, TiltFollowsTheTangentFrame)
{
    const Vec3 fromPlusX(1, 0, 1), fromMinusX(-1, 0, 1), fromPlusY(0, 1, 1), fromMinusY(0, -1, 1);
    struct Case {
        const char* name;
        std::string file;
        Vec3 tangent, bitangent; // of the quad, in world space
    };
    const std::vector<float> givenTangent = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
    const Case cases[] = {
        {"standard, +X", quad("x", "plus_x.png"), {1, 0, 0}, {0, 1, 0}},
        {"standard, +Y", quad("y", "plus_y.png"), {1, 0, 0}, {0, 1, 0}},
        {"mirrored, +X", quad("mx", "plus_x.png", true), {-1, 0, 0}, {0, 1, 0}},
        {"mirrored, +Y", quad("my", "plus_y.png", true), {-1, 0, 0}, {0, 1, 0}},
        {"TANGENT, +X", quad("tx", "plus_x.png", false, givenTangent), {1, 0, 0}, {0, 1, 0}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        Scene s = loadGltf(c.file);
        Vec3 n = mappedNormal(s, c.tangent, c.bitangent);
        ASSERT_GT(length(n - Vec3(0, 0, 1)), 0.4f) << "the map leans by 30 degrees";
        for (Vec3 toLight : {fromPlusX, fromMinusX, fromPlusY, fromMinusY}) {
            double expected = std::max(0.0f, dot(normalize(toLight), n));
            // Exact up to float rounding: next-event estimation from the one light is the whole image.
            EXPECT_NEAR(litValue(s, toLight), expected, 1e-4)
                << "light from (" << toLight.x << ", " << toLight.y << ", " << toLight.z << ")";
        }
    }
}

// Every algorithm converges to the path tracer's image of the tilted map:
// light tracing and connections through the adjoint BSDF of the mapped
// normal, merging through the ratio of the shading to the geometric cosine
// (without it, merging renders the unmapped quad: 0.69 instead of 0.95).
TEST_F(NormalMaps, EveryAlgorithmAgreesWithThePathTracer)
{
    Scene s = loadGltf(quad("x", "plus_x.png"));
    Light light{};
    light.type = LIGHT_DIRECTIONAL;
    Vec3 d = normalize(Vec3(1, 0.3f, 1)) * -1.0f;
    light.direction[0] = d.x, light.direction[1] = d.y, light.direction[2] = d.z;
    for (float& e : light.emission) e = float(kPi);
    s.lights = {light};
    // 16 seeds: the standard errors come from the seeds' spread alone (the
    // path tracer's image has none), and a 5-error bound on 4 blocks × 4
    // algorithms (which share their light paths by seed) needs a good estimate.
    const int size = 16, iterations = 32, seeds = 16;
    DeviceInfo device = test::devicesUnderTest()[0];
    std::vector<Image> reference = test::renderSeeds(device, s, Algorithm::PathTracing, size, size, iterations, seeds);
    test::expectConvergeTo(device, s, reference,
                           {Algorithm::LightTracing, Algorithm::BidirectionalPhotonMapping,
                            Algorithm::VertexConnectionMerging},
                           size, size, iterations, seeds);

    // Merging alone, with a radius large enough to tell: at the default one
    // each pixel sees a light vertex every few hundred iterations, and the
    // check above cannot tell a missing factor from noise. The mean over the
    // pixels more than the radius from the quad's edges (where the light
    // vertices' density is uniform, so the estimate has no kernel bias). 48
    // iterations: bpm's light paths draw independent numbers (core/rng.h),
    // and the mean over the image is what stratified emission would lower
    // most (at 32 iterations its standard error was 0.0175 stratified, 0.020
    // independent).
    const double exact = reference[0].rgb[0]; // every pixel of the path tracer's image: one light, one plane
    const int mergeIterations = 48;
    std::vector<Image> merged = test::renderSeeds(device, s, Algorithm::BidirectionalPhotonMapping, size, size,
                                                  mergeIterations, seeds, 10, 0.02f);
    double mean = 0, sq = 0;
    for (const Image& image : merged) {
        double m = 0;
        for (int y = 2; y < size - 2; ++y)
            for (int x = 2; x < size - 2; ++x) m += image.rgb[3 * size_t(y * size + x)];
        m /= (size - 4) * (size - 4);
        mean += m / seeds;
        sq += m * m / seeds;
    }
    double se = std::sqrt(std::max(0.0, sq - mean * mean) / (seeds - 1));
    EXPECT_NEAR(mean, exact, 5 * se + 1e-3) << "standard error " << se;
    EXPECT_LT(se, 0.02) << "too noisy to tell the mapped quad (0.95) from the unmapped one (0.69)";
}

// A normal-mapped emitter: the map tilts the emitter's shading normal, so
// the cosines at the emitter vertex that convert its densities to area
// measure differ between the shading and the geometric normal. A floor lit
// by the emitter, seen with it: bpt and vcm (emission hits weighted against
// next-event estimation and connections) converge to pt's image.
TEST_F(NormalMaps, MappedEmitterAgreesWithThePathTracer)
{
    test::QuadFile q;
    q.material = {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
                  {"emissiveFactor", {1.0, 1.0, 1.0}},
                  {"normalTexture", {{"index", 0}}},
                  {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
    q.images = {"plus_x.png"};
    Scene s = loadGltf(test::writeQuad(dir_, "emitter", q));
    ASSERT_EQ(s.materials.at(0).normalTexture, 1);
    // A white floor y = -1 in front of the emitter (z in [0, 4]), facing +y.
    s.materials.push_back(test::lambert(0.8f));
    const Vec3 floor[6] = {{-2, -1, 0}, {-2, -1, 4}, {2, -1, 4}, {-2, -1, 0}, {2, -1, 4}, {2, -1, 0}};
    for (int t = 0; t < 2; ++t) {
        for (int k = 0; k < 3; ++k) s.vertices.push_back(floor[3 * t + k]);
        s.triangleMaterial.push_back(int(s.materials.size()) - 1);
        s.uvs.insert(s.uvs.end(), 6, 0.0f);
        s.tangents.insert(s.tangents.end(), 3, std::array<float, 4>{0, 0, 0, 0});
    }
    s.camera.position = {0, 1.5f, 4.5f};
    s.camera.forward = normalize(Vec3(0, -0.5f, 0) - s.camera.position);
    s.camera.up = {0, 1, 0};
    s.camera.yfov = 1.0f;
    const int size = 16, iterations = 32, seeds = 8;
    DeviceInfo device = test::devicesUnderTest()[0];
    std::vector<Image> reference = test::renderSeeds(device, s, Algorithm::PathTracing, size, size, iterations, seeds);
    test::expectConvergeTo(device, s, reference, {Algorithm::Bidirectional, Algorithm::VertexConnectionMerging}, size,
                           size, iterations, seeds);
}

} // namespace
} // namespace wv
