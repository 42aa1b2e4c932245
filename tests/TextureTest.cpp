// Base-colour textures: a glTF file with a PNG texture loads (sRGB decoded
// to linear, sampler wrap modes, TEXCOORD_0 per triangle corner), and a
// textured Lambert quad that fills the image under a uniform background of
// radiance L renders each texel's colour × L where the clamped bilinear
// lookup is constant (the image's corner blocks), in the right corners.
#include "Error.h"
#include "TestDevices.h"
#include "TestQuad.h"
#include "TestRendering.h"
#include "render/SceneBuffers.h"
#include "scene/GltfLoader.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <unistd.h>

namespace wv {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// A 2 × 2 texture, linear RGB, row 0 first: red, green / blue, grey 0.5.
const float kTexels[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5f, 0.5f, 0.5f}};

class Textures : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("wavevcm_textures_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        Image texture(2, 2);
        for (int t = 0; t < 4; ++t)
            for (int c = 0; c < 3; ++c) texture.rgb[3 * size_t(t) + size_t(c)] = kTexels[t][c];
        writeImage((dir_ / "texture.png").string(), texture); // 8-bit, sRGB-encoded
        // Metallic-roughness data (0 and 1 survive the sRGB encoding exactly):
        // roughness (G) 1 everywhere, metallic (B) 0 in the left column, 1 in the right.
        Image mr(2, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) {
                mr.rgb[3 * size_t(2 * y + x) + 1] = 1;
                mr.rgb[3 * size_t(2 * y + x) + 2] = float(x);
            }
        writeImage((dir_ / "mr.png").string(), mr);
        // Transmission data: R 0 in the left column, 1 in the right.
        Image transmission(2, 2);
        for (int y = 0; y < 2; ++y) transmission.rgb[3 * size_t(2 * y + 1)] = 1;
        writeImage((dir_ / "transmission.png").string(), transmission);
        // Clear-coat data: R (weight) 0 in the left column, 1 in the right; G
        // (roughness) 1 in the top row, 0 in the bottom one.
        Image coat(2, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) {
                coat.rgb[3 * size_t(2 * y + x)] = float(x);
                coat.rgb[3 * size_t(2 * y + x) + 1] = float(1 - y);
            }
        writeImage((dir_ / "coat.png").string(), coat);
        // Alpha data (the sheen's roughness): 1 in the left column, 64/255 in the right.
        Image alpha(2, 2);
        alpha.alpha = {1, 64 / 255.0f, 1, 64 / 255.0f};
        writeImage((dir_ / "alpha.png").string(), alpha);
        // Anisotropy data: RG directions (1, −1) in the left column, (1, 1)
        // in the right; B (strength) 1 in the top row, 0 in the bottom one.
        Image anisotropy(2, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) {
                anisotropy.rgb[3 * size_t(2 * y + x)] = 1;
                anisotropy.rgb[3 * size_t(2 * y + x) + 1] = float(x);
                anisotropy.rgb[3 * size_t(2 * y + x) + 2] = float(1 - y);
            }
        writeImage((dir_ / "anisotropy.png").string(), anisotropy);
        Image diagonal(1, 1); // the direction (1, −1) at strength 1 everywhere
        diagonal.rgb = {1, 0, 1};
        writeImage((dir_ / "diagonal.png").string(), diagonal);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // The quad of test::writeQuad, its texture's (0, 0) at the top left (−1, 1).
    std::string writeQuad(const std::string& name, json textureInfo, const json& sampler, bool uvs = true)
    {
        return writeQuadWith(name, {{"baseColorTexture", textureInfo}, {"metallicFactor", 0.0}}, sampler, uvs);
    }

    // The same with the material's pbrMetallicRoughness given whole; texture
    // 0 is texture.png, texture 1 mr.png, texture 2 transmission.png, texture 3 coat.png,
    // texture 4 alpha.png, texture 5 anisotropy.png, texture 6 diagonal.png; more
    // material extensions (KHR_materials_*) in `extensions`.
    std::string writeQuadWith(const std::string& name, const json& pbr, const json& sampler, bool uvs = true,
                              json extensions = json::object())
    {
        test::QuadFile quad;
        // Pure Lambert (no specular layer) unless `extensions` says otherwise:
        // under a uniform background it reflects base colour × L.
        if (!extensions.contains("KHR_materials_specular"))
            extensions["KHR_materials_specular"] = {{"specularFactor", 0.0}};
        quad.material = {{"pbrMetallicRoughness", pbr}, {"extensions", extensions}};
        quad.extensionsUsed = {"KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_clearcoat",
                               "KHR_materials_sheen", "KHR_materials_diffuse_transmission",
                               "KHR_materials_anisotropy"};
        quad.images = {"texture.png", "mr.png", "transmission.png", "coat.png", "alpha.png", "anisotropy.png",
                       "diagonal.png"};
        quad.sampler = sampler;
        quad.uvs = uvs;
        return test::writeQuad(dir_, name, quad);
    }

    // A layer's two textures over its untextured factors: a black quad whose
    // only lobe is the layer's (`lobes`), under a uniform white background,
    // the layer of extension `name` (its factor `factor` set to 1 or
    // 64/255), coloured by coat.png through `colourTexture` and scaled by
    // alpha.png through `factorTexture`: expectCoatPngColours against the
    // untextured quad of factor 1, expectAlphaPngColumns against those of
    // factor 1 and 64/255. `pbr` is the quad's pbrMetallicRoughness, `other`
    // more extensions.
    void expectLayerTextures(const char* name, const json& pbr, const json& other, const char* factor,
                             const char* colourTexture, const char* factorTexture, uint32_t lobes);

    fs::path dir_;
};

bool anyWarningContains(const Scene& s, const std::string& text)
{
    for (const std::string& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

using test::blockMean;

// Each corner block × block of a size × size image shows texel
// texelAtCorner[corner] of `texture` (corners: top left, top right, bottom
// left, bottom right) times L, within 5 standard errors of the block's mean.
void expectCornersShow(const Image& image, int size, int block, const Texture& texture, float L,
                       std::array<int, 4> texelAtCorner)
{
    for (int corner = 0; corner < 4; ++corner) {
        int x0 = (corner % 2) * (size - block), y0 = (corner / 2) * (size - block);
        for (int c = 0; c < 3; ++c) {
            double se, mean = blockMean(image, size, x0, y0, block, c, &se);
            double expected = L * texture.image.rgb[3 * size_t(texelAtCorner[size_t(corner)]) + size_t(c)];
            // 5 standard errors of the block's mean, and float rounding
            EXPECT_NEAR(mean, expected, 5 * se + 1e-4) << "corner " << corner << " channel " << c;
        }
    }
}

TEST_F(Textures, LoadDecodedWithWrapModesAndCoordinates)
{
    Scene s = loadGltf(writeQuad("quad", {{"index", 0}}, {{"wrapS", 33071}, {"wrapT", 33648}}));
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    ASSERT_EQ(t.image.width, 2);
    ASSERT_EQ(t.image.height, 2);
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) // 8-bit sRGB: within a code of 0.5 after decoding
            EXPECT_NEAR(t.image.rgb[3 * size_t(i) + size_t(c)], kTexels[i][c], 3e-3) << i << " " << c;
    EXPECT_EQ(t.wrapS, WRAP_CLAMP);
    EXPECT_EQ(t.wrapT, WRAP_MIRROR);
    EXPECT_EQ(s.materials.at(0).baseColorTexture, 1);
    EXPECT_TRUE(s.features().textures);
    ASSERT_EQ(s.uvs.size(), 6 * s.triangleCount());
    EXPECT_FLOAT_EQ(s.uvs[0], 0.0f); // corner (−1, −1) of the first triangle: uv (0, 1)
    EXPECT_FLOAT_EQ(s.uvs[1], 1.0f);

    // TEXCOORD_1 is read where a texture asks for it (here the file has none:
    // a warning, and (0, 0)); TEXCOORD_2 is not: the factor alone, with a warning.
    Scene second = loadGltf(writeQuad("texcoord1", {{"index", 0}, {"texCoord", 1}}, json::object()));
    ASSERT_EQ(second.textures.size(), 1u);
    EXPECT_EQ(second.textures[0].texCoord, 1);
    EXPECT_EQ(second.uvs1.size(), 6 * second.triangleCount());
    EXPECT_TRUE(second.features().texCoord1);
    EXPECT_TRUE(anyWarningContains(second, "without TEXCOORD_1"));
    EXPECT_TRUE(s.uvs1.empty()) << "no texture reads TEXCOORD_1: the set is dropped";
    Scene third = loadGltf(writeQuad("texcoord2", {{"index", 0}, {"texCoord", 2}}, json::object()));
    EXPECT_TRUE(third.textures.empty());
    EXPECT_EQ(third.materials.at(0).baseColorTexture, 0);
    EXPECT_TRUE(anyWarningContains(third, "only TEXCOORD_0 and TEXCOORD_1"));

    // An image that is not there: the factor alone, with a warning naming it.
    fs::rename(dir_ / "texture.png", dir_ / "moved.png");
    Scene missing = loadGltf(writeQuad("missing", {{"index", 0}}, json::object()));
    EXPECT_TRUE(missing.textures.empty());
    EXPECT_TRUE(anyWarningContains(missing, "the material's factor is used"));
    fs::rename(dir_ / "moved.png", dir_ / "texture.png");

    // A textured material without TEXCOORD_0: a warning.
    EXPECT_TRUE(anyWarningContains(loadGltf(writeQuad("nouv", {{"index", 0}}, json::object(), false)),
                                   "without TEXCOORD_0"));
}

// Every wrap mode on each axis (glTF's REPEAT, CLAMP_TO_EDGE and
// MIRRORED_REPEAT), by the production lookup in a test kernel against a
// reference written from the sampler's definition in double: a 3 × 2 texture
// (unequal sides catch swapped axes) of distinct texels, looked up inside,
// just outside, far outside [0, 1] and on texel centres and edges. Float
// rounding of u·width bounds the difference (1e-5 here).
TEST(TextureLookup, EveryWrapModeMatchesItsDefinition)
{
    const int w = 3, h = 2;
    std::vector<std::array<float, 4>> texels;
    for (int t = 0; t < w * h; ++t) texels.push_back({float(t), float(t * t) / 8, 1.0f / (t + 1), float(t % 2)});
    auto wrap = [](int i, int n, int mode) {
        if (mode == WRAP_CLAMP) return std::min(std::max(i, 0), n - 1);
        int period = mode == WRAP_MIRROR ? 2 * n : n;
        int m = ((i % period) + period) % period;
        return mode == WRAP_MIRROR && m >= n ? 2 * n - 1 - m : m;
    };
    auto reference = [&](double u, double v, int wrapS, int wrapT, int c) {
        double x = u * w - 0.5, y = v * h - 0.5, fx = std::floor(x), fy = std::floor(y), ax = x - fx, ay = y - fy;
        auto at = [&](int i, int j) { return double(texels[size_t(wrap(j, h, wrapT) * w + wrap(i, w, wrapS))][size_t(c)]); };
        int i = int(fx), j = int(fy);
        return (1 - ay) * ((1 - ax) * at(i, j) + ax * at(i + 1, j)) + ay * ((1 - ax) * at(i, j + 1) + ax * at(i + 1, j + 1));
    };
    std::vector<std::array<float, 2>> uvs;
    for (float u : {0.0f, 0.1f, 1.0f / 6, 0.5f, 0.9f, 1.0f, 1.05f, -0.05f, -0.4f, 1.7f, 2.3f, -3.2f, 7.9f})
        for (float v : {0.0f, 0.25f, 0.6f, 1.0f, -0.3f, 1.3f, -2.6f, 5.1f}) uvs.push_back({u, v});

    DeviceContext device(test::devicesUnderTest()[0]);
    cl::Program program = test::buildTestProgram(device, {test::testKernel("texture_tests.cl")}, "-DSCENE_LOBES=1u");
    cl::Buffer texelBuffer = uploadBuffer(device, texels.data(), texels.size() * 16, "texels");
    cl::Buffer uvBuffer = uploadBuffer(device, uvs.data(), uvs.size() * 8, "uvs");
    cl::Buffer out = deviceBuffer(device, uvs.size() * 16, "lookups");
    for (int wrapS : {WRAP_REPEAT, WRAP_CLAMP, WRAP_MIRROR})
        for (int wrapT : {WRAP_REPEAT, WRAP_CLAMP, WRAP_MIRROR}) {
            SCOPED_TRACE("wrapS " + std::to_string(wrapS) + ", wrapT " + std::to_string(wrapT));
            TextureInfo info{};
            info.width = w;
            info.height = h;
            info.wrapS = wrapS;
            info.wrapT = wrapT;
            info.uvTransform[0] = info.uvTransform[4] = 1;
            cl::Buffer infoBuffer = uploadBuffer(device, &info, sizeof info, "texture");
            cl::Kernel kernel(program, "texture_lookups");
            kernel.setArg(0, texelBuffer);
            kernel.setArg(1, infoBuffer);
            kernel.setArg(2, uvBuffer);
            kernel.setArg(3, int(uvs.size()));
            kernel.setArg(4, out);
            device.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(test::launchSize(uvs.size())),
                                              cl::NDRange(64));
            std::vector<std::array<float, 4>> got(uvs.size());
            device.queue.enqueueReadBuffer(out, CL_TRUE, 0, got.size() * 16, got.data());
            for (size_t k = 0; k < uvs.size(); ++k)
                for (int c = 0; c < 4; ++c)
                    EXPECT_NEAR(got[k][size_t(c)], reference(uvs[k][0], uvs[k][1], wrapS, wrapT, c), 1e-5)
                        << "uv (" << uvs[k][0] << ", " << uvs[k][1] << ") channel " << c;
        }
}

TEST_F(Textures, TexelsRenderWhereTheyLie)
{
    Scene s = loadGltf(writeQuad("render", {{"index", 0}}, {{"wrapS", 33071}, {"wrapT", 33071}}));
    const float L = 0.8f;
    s.background = {L, L, L};
    const int size = 32, block = 8; // u < 1/4 or > 3/4 (and v): the clamped lookup is one texel there
    DeviceInfo device = test::devicesUnderTest()[0];
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        test::Render r = test::render(device, s, a, size, size, 32, 5);
        EXPECT_EQ(r.nonFinite, 0u);
        expectCornersShow(r.image, size, block, s.textures[0], L, {0, 1, 2, 3});
    }
}

// KHR_texture_transform (uv' = offset + R(rotation) · (scale ∘ uv), R
// counter-clockwise, as the extension's matrix): a quarter turn with offset
// (1, 0) maps the quad's corners (u, v) to (1 − v, u), so the texels move a
// corner round: top left shows texel (1, 0) green, top right (1, 1) grey,
// bottom left (0, 0) red, bottom right (0, 1) blue. A turn the other way or
// no transform puts other colours there.
TEST_F(Textures, TextureTransformMovesTheTexels)
{
    json turn = {{"index", 0},
                 {"extensions", {{"KHR_texture_transform", {{"rotation", M_PI / 2}, {"offset", {1.0, 0.0}}}}}}};
    Scene s = loadGltf(writeQuad("transform", turn, {{"wrapS", 33071}, {"wrapT", 33071}}));
    ASSERT_EQ(s.textures.size(), 1u);
    const std::array<float, 6>& m = s.textures[0].uvTransform;
    EXPECT_NEAR(m[0], 0, 1e-6);
    EXPECT_NEAR(m[1], -1, 1e-6);
    EXPECT_NEAR(m[2], 1, 1e-6);
    EXPECT_NEAR(m[3], 1, 1e-6);
    EXPECT_NEAR(m[4], 0, 1e-6);
    EXPECT_NEAR(m[5], 0, 1e-6);

    const float L = 0.8f;
    s.background = {L, L, L};
    const int size = 32, block = 8;
    test::Render r = test::render(test::devicesUnderTest()[0], s, Algorithm::PathTracing, size, size, 32, 5);
    expectCornersShow(r.image, size, block, s.textures[0], L, {1, 3, 0, 2});
}

// A metallic-roughness texture: metallic 0 in the left column (a white
// Lambert there, no specular layer: exactly L under a uniform background L)
// and 1 in the right (a rough white metal, as the same quad untextured with
// metallic 1 renders it); the data texture is read without sRGB decoding,
// and the quad keeps a diffuse lobe though its metallicFactor is 1.
TEST_F(Textures, MetallicRoughnessTextureSelectsTheLobes)
{
    json clamp = {{"wrapS", 33071}, {"wrapT", 33071}};
    Scene textured = loadGltf(writeQuadWith(
        "mr", {{"metallicRoughnessTexture", {{"index", 1}}}, {"metallicFactor", 1.0}, {"roughnessFactor", 1.0}}, clamp));
    ASSERT_EQ(textured.textures.size(), 1u);
    EXPECT_EQ(textured.materials.at(0).metallicRoughnessTexture, 1);
    EXPECT_FLOAT_EQ(textured.textures[0].image.rgb[3 * 1 + 2], 1.0f); // B of texel (1, 0), as stored
    EXPECT_TRUE(textured.materials.at(0).lobes & LOBE_DIFFUSE);
    Scene metal = loadGltf(writeQuadWith("metal", {{"metallicFactor", 1.0}, {"roughnessFactor", 1.0}}, clamp));
    const float L = 0.8f;
    textured.background = metal.background = {L, L, L};
    const int size = 32, block = 8, iterations = 32;
    DeviceInfo device = test::devicesUnderTest()[0];
    test::Render t = test::render(device, textured, Algorithm::PathTracing, size, size, iterations, 5);
    test::Render m = test::render(device, metal, Algorithm::PathTracing, size, size, iterations, 6);
    for (int y0 : {0, size - block}) { // the red channel: the quad is white
        double seT, seM;
        double left = blockMean(t.image, size, 0, y0, block, 0, &seT);
        EXPECT_NEAR(left, L, 5 * seT + 1e-4) << "dielectric column, row " << y0;
        double right = blockMean(t.image, size, size - block, y0, block, 0, &seT);
        double reference = blockMean(m.image, size, size - block, y0, block, 0, &seM);
        EXPECT_NEAR(right, reference, 5 * std::sqrt(seT * seT + seM * seM) + 1e-4) << "metal column, row " << y0;
        EXPECT_LT(reference, 0.98 * L) << "a rough metal loses energy: the two columns must differ";
    }
}

// EXT_texture_webp: a texture whose extension names a WebP image reads that
// image (OpenImageIO decodes it), not its PNG fallback `source`: a uniform
// 4 × 2 WebP against the 2 × 2 PNG. A lossy WebP keeps a uniform colour
// within a few 8-bit codes (0.03 after sRGB decoding, with the codes' 2.2
// power against the sRGB curve). An extension without
// an integer source is an error naming it.
TEST_F(Textures, WebpImageReplacesItsFallback)
{
    const float colour[3] = {0.5f, 0.25f, 0.75f};
    { // writeImage writes no WebP: OpenImageIO directly, 8-bit sRGB codes
        std::vector<unsigned char> codes(4 * 2 * 3);
        for (size_t i = 0; i < codes.size(); ++i)
            codes[i] = (unsigned char)std::lround(255 * std::pow(colour[i % 3], 1 / 2.2));
        auto out = OIIO::ImageOutput::create((dir_ / "texture.webp").string());
        ASSERT_TRUE(out) << "OpenImageIO writes no WebP here";
        ASSERT_TRUE(out->open((dir_ / "texture.webp").string(), OIIO::ImageSpec(4, 2, 3, OIIO::TypeDesc::UINT8)));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, codes.data()));
        out->close();
    }
    auto withWebp = [&](const std::string& name, const json& extension) {
        std::string path = writeQuad(name, {{"index", 0}}, json::object());
        json g = json::parse(std::ifstream(path));
        g["images"].push_back({{"uri", "texture.webp"}});
        json e = extension;
        if (e["source"].is_null()) e["source"] = g["images"].size() - 1; // the WebP image
        g["textures"][0]["extensions"]["EXT_texture_webp"] = e;
        g["extensionsUsed"].push_back("EXT_texture_webp");
        std::ofstream(path) << g.dump();
        return path;
    };
    Scene s = loadGltf(withWebp("webp", json::object()));
    for (const std::string& w : s.warnings) ADD_FAILURE() << w;
    ASSERT_EQ(s.textures.size(), 1u);
    const Texture& t = s.textures[0];
    EXPECT_EQ(t.image.width, 4);
    EXPECT_EQ(t.image.height, 2);
    // The sRGB curve against the 2.2 power the codes were made with: within 0.01.
    for (size_t i = 0; i < t.image.rgb.size(); ++i) EXPECT_NEAR(t.image.rgb[i], colour[i % 3], 0.03) << i;
    EXPECT_FALSE(anyWarningContains(s, "EXT_texture_webp"));
    try {
        loadGltf(withWebp("webp-bad", {{"source", "texture.webp"}}));
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("EXT_texture_webp needs an integer source"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("webp-bad.gltf"), std::string::npos) << e.what();
    }
}

// A transmission texture (KHR_materials_transmission's transmissionTexture,
// R times transmissionFactor): a smooth thin-walled grey quad before an
// emitter, seen head-on. Where the texture is 0 (left) the quad is the
// opaque Lambert of transmission 0, dark (lit only from behind); where it is
// 1 (right), the transmitting quad of factor 1, showing the emitter. At the
// same seed each side renders as the untextured quad does.
TEST_F(Textures, TransmissionTextureScalesTransmission)
{
    json clamp = {{"wrapS", 33071}, {"wrapT", 33071}};
    json pbr = {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.0}};
    auto quad = [&](const std::string& name, double factor, bool textured) {
        json transmission = {{"transmissionFactor", factor}};
        if (textured) transmission["transmissionTexture"] = {{"index", 2}};
        Scene s = loadGltf(writeQuadWith(name, pbr, clamp, true, {{"KHR_materials_transmission", transmission}}));
        // An emitter of radiance 1 behind the quad, facing it.
        s.materials.push_back(test::lambert(0.0f, 1.0f));
        const Vec3 e[6] = {{-2, -2, -1}, {2, -2, -1}, {2, 2, -1}, {-2, -2, -1}, {2, 2, -1}, {-2, 2, -1}};
        for (int t = 0; t < 2; ++t) {
            for (int k = 0; k < 3; ++k) s.vertices.push_back(e[3 * t + k]);
            s.triangleMaterial.push_back(int(s.materials.size()) - 1);
            if (!s.uvs.empty()) s.uvs.insert(s.uvs.end(), 6, 0.0f);
        }
        return s;
    };
    Scene textured = quad("transmission", 1.0, true);
    ASSERT_EQ(textured.materials.at(0).transmissionTexture, 1);
    EXPECT_TRUE(textured.materials.at(0).lobes & LOBE_DIFFUSE) << "transmission may fall to 0: diffuse is needed";
    Scene clear = quad("clear", 1.0, false), opaque = quad("opaque", 0.0, false);
    const int size = 32, block = 8, iterations = 16;
    DeviceInfo device = test::devicesUnderTest()[0];
    test::Render t = test::render(device, textured, Algorithm::PathTracing, size, size, iterations, 5);
    test::Render c = test::render(device, clear, Algorithm::PathTracing, size, size, iterations, 5);
    test::Render o = test::render(device, opaque, Algorithm::PathTracing, size, size, iterations, 5);
    for (int y0 : {0, size - block}) {
        double se, left = blockMean(t.image, size, 0, y0, block, 0, &se);
        double right = blockMean(t.image, size, size - block, y0, block, 0, &se);
        double opaqueLeft = blockMean(o.image, size, 0, y0, block, 0, &se);
        double clearRight = blockMean(c.image, size, size - block, y0, block, 0, &se);
        EXPECT_NEAR(left, opaqueLeft, 1e-3 * (1 + opaqueLeft)) << "row " << y0;
        EXPECT_NEAR(right, clearRight, 1e-3 * (1 + clearRight)) << "row " << y0;
        EXPECT_GT(clearRight, 0.3) << "the emitter shows through the clear quad";
        EXPECT_LT(opaqueLeft, 0.05) << "the opaque quad is lit only from behind";
    }
}

// A black quad's layer coloured by coat.png (corners green, yellow, black,
// red) against the same layer white: each channel of each corner block is 0
// or the white layer's at the same seed (the same lobe, picked with
// probability 1, and the same random numbers: 1e-3 relative).
void expectCoatPngColours(const Image& coloured, const Image& white, int size, int block)
{
    double se;
    const int right = size - block, bottom = size - block;
    const std::array<std::array<int, 2>, 4> corners{{{0, 0}, {right, 0}, {0, bottom}, {right, bottom}}};
    const bool keeps[4][3] = {{false, true, false}, {true, true, false}, {false, false, false}, {true, false, false}};
    for (int k = 0; k < 4; ++k)
        for (int ch = 0; ch < 3; ++ch) {
            double got = blockMean(coloured, size, corners[k][0], corners[k][1], block, ch, &se);
            double w = blockMean(white, size, corners[k][0], corners[k][1], block, ch, &se);
            EXPECT_GT(w, 0.02) << "the white layer reflects the background";
            EXPECT_NEAR(got, keeps[k][ch] ? w : 0.0, 1e-3 * w) << "corner " << k << " channel " << ch;
        }
}

// A layer's factor scaled by alpha.png (1 left, 64/255 right): the left
// column is the untextured layer of factor 1 (`full`), the right the one of
// factor 64/255 (`reduced`), at the same seed (1e-3 relative); the two
// differ by more than 20 %, so that the check means something.
void expectAlphaPngColumns(const Image& textured, const Image& full, const Image& reduced, int size, int block)
{
    double se;
    const int right = size - block;
    for (int y0 : {0, size - block}) {
        double fullLeft = blockMean(full, size, 0, y0, block, 1, &se);
        double reducedRight = blockMean(reduced, size, right, y0, block, 1, &se);
        EXPECT_NEAR(blockMean(textured, size, 0, y0, block, 1, &se), fullLeft, 1e-3 * fullLeft) << "row " << y0;
        EXPECT_NEAR(blockMean(textured, size, right, y0, block, 1, &se), reducedRight, 1e-3 * reducedRight)
            << "row " << y0;
        EXPECT_GT(std::abs(fullLeft - blockMean(reduced, size, 0, y0, block, 1, &se)), 0.2 * fullLeft)
            << "the two factors must differ";
    }
}

// The clear coat's textures (KHR_materials_clearcoat): R of
// clearcoatTexture times clearcoatFactor, G of clearcoatRoughnessTexture
// times clearcoatRoughnessFactor. A black quad (only the coat reflects) with
// both factors 1 and coat.png as both textures, lit by an emitter off to the
// side, out of the mirror direction, and nothing else. Where the weight is 0
// (left) the quad is black. Top right (weight 1, roughness 1), the rough
// coat glows as the untextured coat of the same factors does at the same
// seed (the same lobes and random numbers: 1e-3 relative); bottom right
// (roughness 0) the coat is a mirror, which shows the black surroundings.
TEST_F(Textures, ClearcoatTexturesScaleWeightAndRoughness)
{
    json clamp = {{"wrapS", 33071}, {"wrapT", 33071}};
    json pbr = {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}};
    auto quad = [&](const std::string& name, bool textured) {
        json coat = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 1.0}};
        if (textured) coat["clearcoatTexture"] = coat["clearcoatRoughnessTexture"] = {{"index", 3}};
        Scene s = loadGltf(writeQuadWith(name, pbr, clamp, true, {{"KHR_materials_clearcoat", coat}}));
        // A two-sided emitter of radiance 20 in the plane x = 3, beside the
        // camera's view (which sees the quad [−1, 1]² from z = 3 and no more).
        Material light = test::lambert(0.0f, 20.0f);
        light.doubleSided = 1;
        s.materials.push_back(light);
        const Vec3 e[6] = {{3, -2, 0.2f}, {3, 2, 0.2f}, {3, 2, 3}, {3, -2, 0.2f}, {3, 2, 3}, {3, -2, 3}};
        for (int t = 0; t < 2; ++t) {
            for (int k = 0; k < 3; ++k) s.vertices.push_back(e[3 * t + k]);
            s.triangleMaterial.push_back(int(s.materials.size()) - 1);
            if (!s.uvs.empty()) s.uvs.insert(s.uvs.end(), 6, 0.0f);
        }
        s.background = {0, 0, 0};
        return s;
    };
    Scene textured = quad("coat-textured", true), plain = quad("coat-plain", false);
    const Material& m = textured.materials.at(0);
    ASSERT_EQ(m.clearcoatTexture, 1);
    ASSERT_EQ(m.clearcoatRoughnessTexture, 1); // the same image, read as data once
    EXPECT_EQ(m.lobes, LOBE_GGX_COAT) << "black base: the coat alone, rough by its factor";
    const int size = 32, block = 8, iterations = 32;
    DeviceInfo device = test::devicesUnderTest()[0];
    test::Render t = test::render(device, textured, Algorithm::PathTracing, size, size, iterations, 7);
    test::Render p = test::render(device, plain, Algorithm::PathTracing, size, size, iterations, 7);
    double se;
    double glow = blockMean(p.image, size, size - block, 0, block, 0, &se);
    EXPECT_GT(glow, 0.02) << "the rough coat reflects the emitter";
    EXPECT_NEAR(blockMean(t.image, size, size - block, 0, block, 0, &se), glow, 1e-3 * glow) << "top right";
    EXPECT_LT(blockMean(t.image, size, size - block, size - block, block, 0, &se), 0.02 * glow) << "bottom right";
    EXPECT_EQ(blockMean(t.image, size, 0, 0, block, 0, &se), 0.0) << "top left";
    EXPECT_EQ(blockMean(t.image, size, 0, size - block, block, 0, &se), 0.0) << "bottom left";
}

// The sheen's textures (KHR_materials_sheen): sheenColorTexture's RGB
// (sRGB-decoded) times sheenColorFactor, sheenRoughnessTexture's alpha times
// sheenRoughnessFactor, on a black quad (only the sheen reflects).
TEST_F(Textures, SheenTexturesScaleColourAndRoughness)
{
    json pbr = {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}};
    json sheen = {{"KHR_materials_sheen", {{"sheenColorFactor", {1, 1, 1}}}}};
    expectLayerTextures("KHR_materials_sheen", pbr, sheen, "sheenRoughnessFactor", "sheenColorTexture",
                        "sheenRoughnessTexture", LOBE_SHEEN);
}

// KHR_materials_specular's textures: specularTexture's alpha times
// specularFactor, specularColorTexture's RGB (sRGB-decoded) times
// specularColorFactor, on a black rough dielectric quad (only the specular
// layer reflects).
TEST_F(Textures, SpecularTexturesScaleFactorAndColour)
{
    json pbr = {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}};
    expectLayerTextures("KHR_materials_specular", pbr, json::object(), "specularFactor",
                        "specularColorTexture", "specularTexture", LOBE_GGX_REFLECTION);
}

// KHR_materials_diffuse_transmission's textures: diffuseTransmissionTexture's
// alpha times diffuseTransmissionFactor, diffuseTransmissionColorTexture's
// RGB (sRGB-decoded) times diffuseTransmissionColorFactor, on a quad that
// only transmits (black base colour, no specular layer): the background
// shows through it.
TEST_F(Textures, DiffuseTransmissionTexturesScaleFactorAndColour)
{
    json pbr = {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}};
    json noLayer = {{"KHR_materials_specular", {{"specularFactor", 0.0}}}};
    expectLayerTextures("KHR_materials_diffuse_transmission", pbr, noLayer, "diffuseTransmissionFactor",
                        "diffuseTransmissionColorTexture", "diffuseTransmissionTexture", LOBE_DIFFUSE_TRANSMISSION);
}

void Textures::expectLayerTextures(const char* name, const json& pbr, const json& other, const char* factor,
                                   const char* colourTexture, const char* factorTexture, uint32_t lobes)
{
    json clamp = {{"wrapS", 33071}, {"wrapT", 33071}};
    auto quad = [&](const std::string& file, float value, const char* texture, int index) {
        json extensions = other;
        json& layer = extensions[name];
        layer[factor] = value;
        if (texture) layer[texture] = {{"index", index}};
        Scene s = loadGltf(writeQuadWith(file, pbr, clamp, true, extensions));
        s.background = {1, 1, 1};
        return s;
    };
    const int size = 32, block = 8, iterations = 16;
    DeviceInfo device = test::devicesUnderTest()[0];
    auto render = [&](const Scene& s) { return test::render(device, s, Algorithm::PathTracing, size, size, iterations, 9).image; };
    Scene coloured = quad("coloured", 1.0f, colourTexture, 3), scaled = quad("scaled", 1.0f, factorTexture, 4);
    EXPECT_EQ(coloured.materials.at(0).lobes, lobes);
    Image c = render(coloured), w = render(scaled), full = render(quad("full", 1.0f, nullptr, 0)),
          reduced = render(quad("reduced", 64 / 255.0f, nullptr, 0));
    expectCoatPngColours(c, full, size, block);
    expectAlphaPngColumns(w, full, reduced, size, block);
}

// A brushed metal quad (KHR_materials_anisotropy: roughness 0.2, strength 1,
// the given rotation, the anisotropy texture or none) under a point light
// beside the camera, against black: the highlight is the light's reflection,
// stretched along the anisotropy's direction. Its tangents come from the
// UVs (u along +x), so the bitangent cross(n, t)·w is +y.
Scene brushedQuad(const std::string& path)
{
    Scene s = loadGltf(path);
    Light light{};
    light.type = LIGHT_POINT;
    light.position[2] = 3;
    for (float& e : light.emission) e = 4;
    s.lights.push_back(light);
    s.background = {0, 0, 0};
    return s;
}

// The principal axis of an image's red channel (the highlight's moments
// about the image centre) as an angle in the quad's plane: image x is +x,
// image rows run along −y.
double highlightAxis(const Image& image, int size)
{
    double sxx = 0, syy = 0, sxy = 0;
    for (int row = 0; row < size; ++row)
        for (int column = 0; column < size; ++column) {
            double w = image.rgb[3 * (size_t(row) * size_t(size) + size_t(column))];
            double x = column + 0.5 - size / 2.0, y = size / 2.0 - (row + 0.5);
            sxx += w * x * x;
            syy += w * y * y;
            sxy += w * x * y;
        }
    return 0.5 * std::atan2(2 * sxy, sxx - syy);
}

// The direction is anisotropyRotation radians from the tangent towards the
// bitangent: counter-clockwise seen from the normal's side (glTF's
// definition). The highlight's axis is the rotation, within 0.1 rad, for
// ±π/4 (a handedness the other way round turns each to the other, π/2 off).
// And a texture's direction is turned by it: diagonal.png's (1, −1), at
// −π/4, turned by π/4 lies along the tangent (turned the other way, π/2 off).
TEST_F(Textures, AnisotropyTurnsFromTheTangentTowardsTheBitangent)
{
    json pbr = {{"metallicFactor", 1.0}, {"roughnessFactor", 0.2}};
    const int size = 48, iterations = 8;
    DeviceInfo device = test::devicesUnderTest()[0];
    for (double rotation : {M_PI / 4, -M_PI / 4, 0.0}) {
        SCOPED_TRACE("rotation " + std::to_string(rotation));
        json anisotropy = {{"anisotropyStrength", 1.0}, {"anisotropyRotation", rotation}};
        if (rotation == 0.0) { // the texture's direction turned by π/4
            anisotropy["anisotropyRotation"] = M_PI / 4;
            anisotropy["anisotropyTexture"] = {{"index", 6}};
        }
        Scene s = brushedQuad(writeQuadWith("brushed", pbr, json::object(), true,
                                            {{"KHR_materials_anisotropy", anisotropy}}));
        ASSERT_EQ(s.materials.at(0).lobes, LOBE_GGX_REFLECTION);
        ASSERT_TRUE(s.features().anisotropy && s.features().tangents);
        Image image = test::render(device, s, Algorithm::PathTracing, size, size, iterations, 3).image;
        double axis = highlightAxis(image, size);
        EXPECT_LT(std::abs(std::remainder(axis - rotation, M_PI)), 0.1) << "highlight axis " << axis;
    }
}

// anisotropyTexture (linear data): its RG, mapped to [−1, 1]², is the
// direction in the tangent frame, turned by anisotropyRotation; its B scales
// anisotropyStrength. anisotropy.png's top left holds (1, −1) at strength 1,
// its top right (1, 1), its bottom row strength 0: each corner block renders
// as the untextured quad of rotation −π/4, +π/4 and strength 0 does at the
// same seed (direct light alone: the same samples, 1e-3 relative). The
// references differ where they are compared (by more than 20 % of the
// brighter), so that the check means something.
TEST_F(Textures, AnisotropyTextureGivesDirectionAndStrength)
{
    json clamp = {{"wrapS", 33071}, {"wrapT", 33071}};
    json pbr = {{"metallicFactor", 1.0}, {"roughnessFactor", 0.2}};
    auto quad = [&](const std::string& name, double strength, double rotation, bool textured) {
        json anisotropy = {{"anisotropyStrength", strength}, {"anisotropyRotation", rotation}};
        if (textured) anisotropy["anisotropyTexture"] = {{"index", 5}};
        return brushedQuad(writeQuadWith(name, pbr, clamp, true, {{"KHR_materials_anisotropy", anisotropy}}));
    };
    const int size = 32, block = 8, iterations = 8;
    DeviceInfo device = test::devicesUnderTest()[0];
    auto render = [&](const Scene& s) { return test::render(device, s, Algorithm::PathTracing, size, size, iterations, 9).image; };
    Scene textured = quad("aniso-textured", 1.0, 0.0, true);
    ASSERT_EQ(textured.materials.at(0).anisotropyTexture, 1);
    Image t = render(textured), down = render(quad("aniso-down", 1.0, -M_PI / 4, false)),
          up = render(quad("aniso-up", 1.0, M_PI / 4, false)), none = render(quad("aniso-none", 0.0, 0.0, false));
    const int right = size - block, bottom = size - block;
    struct Corner {
        int x0, y0;
        const Image* expected;
        const Image* other;
    };
    for (const Corner& c : {Corner{0, 0, &down, &up}, Corner{right, 0, &up, &down}, Corner{0, bottom, &none, &down},
                            Corner{right, bottom, &none, &up}}) {
        SCOPED_TRACE("corner " + std::to_string(c.x0) + ", " + std::to_string(c.y0));
        double se, expected = blockMean(*c.expected, size, c.x0, c.y0, block, 0, &se);
        double other = blockMean(*c.other, size, c.x0, c.y0, block, 0, &se);
        EXPECT_NEAR(blockMean(t, size, c.x0, c.y0, block, 0, &se), expected, 1e-3 * expected + 1e-6);
        EXPECT_GT(std::abs(expected - other), 0.2 * std::max(expected, other)) << "the references must differ";
    }
}

// TEXCOORD_1: the base-colour texture read through the second set, which
// mirrors the first (u along −x), shows each texel in the horizontally
// opposite corner from where TEXCOORD_0 puts it.
TEST_F(Textures, SecondTexCoordSetIsRead)
{
    test::QuadFile q;
    q.material = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}}, {"metallicFactor", 0.0}}},
                  {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}};
    q.images = {"texture.png"};
    q.sampler = {{"wrapS", 33071}, {"wrapT", 33071}};
    q.uv1 = {1, 1, 0, 1, 0, 0, 1, 0};
    Scene s = loadGltf(test::writeQuad(dir_, "second", q));
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_NE(s.features().buildOptions().find("-DHAS_TEXCOORD1"), std::string::npos);
    const float L = 0.8f;
    s.background = {L, L, L};
    const int size = 32, block = 8;
    test::Render r = test::render(test::devicesUnderTest()[0], s, Algorithm::PathTracing, size, size, 32, 5);
    expectCornersShow(r.image, size, block, s.textures[0], L, {1, 0, 3, 2}); // TEXCOORD_0 would show 0, 1, 2, 3
}

// Vertex colours (COLOR_0) multiply the base colour, interpolated over each
// triangle: corners coloured ((1 − x) / 2, (1 + x) / 2, 0.5) by their x make
// a colour linear in x, which the interpolation reproduces exactly, so each
// corner block of the Lambert quad shows that colour at its mean x (±0.75)
// times L. With the colours ignored, every block would be white × L.
TEST_F(Textures, VertexColorsScaleTheBaseColor)
{
    Scene s = loadGltf(writeQuadWith("colours", {{"metallicFactor", 0.0}}, json::object(), false));
    ASSERT_TRUE(s.colors.empty());
    for (const Vec3& v : s.vertices) s.colors.push_back({(1 - v.x) / 2, (1 + v.x) / 2, 0.5f, 1});
    EXPECT_NE(s.features().buildOptions().find("-DHAS_VERTEX_COLORS"), std::string::npos);
    const float L = 0.8f;
    s.background = {L, L, L};
    const int size = 32, block = 8;
    DeviceInfo device = test::devicesUnderTest()[0];
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        test::Render r = test::render(device, s, a, size, size, 32, 5);
        EXPECT_EQ(r.nonFinite, 0u);
        for (int corner = 0; corner < 4; ++corner) {
            int x0 = (corner % 2) * (size - block), y0 = (corner / 2) * (size - block);
            float x = corner % 2 ? 0.75f : -0.75f;
            const float expected[3] = {(1 - x) / 2, (1 + x) / 2, 0.5f};
            for (int c = 0; c < 3; ++c) {
                double se, mean = blockMean(r.image, size, x0, y0, block, c, &se);
                EXPECT_NEAR(mean, L * expected[c], 5 * se + 1e-4) << "corner " << corner << " channel " << c;
            }
        }
    }
}

// COLOR_0's alpha multiplies the base colour's: a black BLEND quad whose
// vertex alpha is 0.25 lets 0.75 of the uniform background L through,
// where alpha 1 (the colour's alpha ignored) would show black. Within 5
// standard errors of the image's mean (each camera ray passes or stops).
TEST_F(Textures, VertexColorAlphaBlends)
{
    Scene s = loadGltf(writeQuadWith("blend", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0.0}},
                                     json::object(), false));
    for (Material& m : s.materials) m.alphaMode = ALPHA_BLEND;
    for (size_t k = 0; k < s.vertices.size(); ++k) s.colors.push_back({1, 1, 1, 0.25f});
    const float L = 0.8f;
    s.background = {L, L, L};
    test::Render r = test::render(test::devicesUnderTest()[0], s, Algorithm::PathTracing, 32, 32, 32, 5);
    double mean, se;
    test::meanAndStandardError(r.image, &mean, &se);
    EXPECT_NEAR(mean, 0.75 * L, 5 * se + 1e-4);
}

} // namespace
} // namespace wv
