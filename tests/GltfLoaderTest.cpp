// wv::loadGltf on small glTF files written by the tests: node transforms of
// vertices and normals, accessor layouts, cameras, KHR_lights_punctual lights,
// the material-to-lobe mapping, the background, warnings for what is ignored
// and wv::Error (naming the file) for what is malformed or unsupported.
// Ends with the bundled Cornell box.
#include "Error.h"
#include "TestDevices.h"
#include "TestRendering.h"
#include "image/Image.h"
#include "scene/DracoMesh.h"
#include "scene/GltfLoader.h"

#ifdef WAVEVCM_HAVE_DRACO
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#endif

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

namespace wv {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;
const double kHalfSqrt2 = std::sqrt(0.5); // cos and sin of 45°, for 90° quaternions

::testing::AssertionResult near(Vec3 actual, Vec3 expected, float tolerance = 1e-5f)
{
    for (int i = 0; i < 3; ++i)
        if (!(std::fabs(actual[i] - expected[i]) <= tolerance))
            return ::testing::AssertionFailure()
                   << "(" << actual.x << ", " << actual.y << ", " << actual.z << ") != expected (" << expected.x
                   << ", " << expected.y << ", " << expected.z << ") within " << tolerance;
    return ::testing::AssertionSuccess();
}

Vec3 triangleNormal(const Scene& s, size_t t)
{
    const Vec3* v = &s.vertices[3 * t];
    return normalize(cross(v[1] - v[0], v[2] - v[0]));
}

bool anyWarningContains(const Scene& s, const std::string& text)
{
    for (const std::string& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

void writeFile(const fs::path& path, const void* data, size_t size)
{
    std::ofstream f(path, std::ios::binary);
    f.write(static_cast<const char*>(data), std::streamsize(size));
    ASSERT_TRUE(f.good()) << "cannot write " << path;
}

// A glTF document being put together: the JSON and the one binary buffer its
// buffer views point into. Every add* returns the index of what it added.
class GltfBuilder {
public:
    json j;
    std::vector<unsigned char> bin;

    GltfBuilder()
    {
        j["asset"] = {{"version", "2.0"}};
        j["scene"] = 0;
        j["scenes"] = json::array({{{"nodes", json::array()}}});
        j["nodes"] = json::array();
        j["meshes"] = json::array();
        j["accessors"] = json::array();
        j["bufferViews"] = json::array();
    }

    int addView(const void* data, size_t size, int byteStride = 0)
    {
        while (bin.size() % 4) bin.push_back(0);
        json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}};
        if (byteStride) view["byteStride"] = byteStride;
        auto bytes = static_cast<const unsigned char*>(data);
        bin.insert(bin.end(), bytes, bytes + size);
        return push("bufferViews", view);
    }

    int addAccessor(int view, int componentType, const std::string& type, size_t count, size_t byteOffset = 0)
    {
        return push("accessors", {{"bufferView", view},
                                  {"componentType", componentType},
                                  {"type", type},
                                  {"count", count},
                                  {"byteOffset", byteOffset}});
    }

    int addVec3s(const std::vector<Vec3>& v)
    {
        return addAccessor(addView(v.data(), v.size() * sizeof(Vec3)), kFloat, "VEC3", v.size());
    }

    template <class T> int addIndices(const std::vector<T>& indices)
    {
        static_assert(sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4, "index size");
        int type = sizeof(T) == 1 ? kUnsignedByte : sizeof(T) == 2 ? kUnsignedShort : kUnsignedInt;
        return addAccessor(addView(indices.data(), indices.size() * sizeof(T)), type, "SCALAR", indices.size());
    }

    // Makes accessor `accessor` sparse: its elements at `indices` (T: the
    // index type) replaced by `values`, each array in a bufferView of its own.
    template <class T, class V>
    void makeSparse(int accessor, const std::vector<T>& indices, const std::vector<V>& values)
    {
        int type = sizeof(T) == 1 ? kUnsignedByte : sizeof(T) == 2 ? kUnsignedShort : kUnsignedInt;
        j["accessors"][accessor]["sparse"] = {
            {"count", indices.size()},
            {"indices", {{"bufferView", addView(indices.data(), indices.size() * sizeof(T))}, {"componentType", type}}},
            {"values", {{"bufferView", addView(values.data(), values.size() * sizeof(V))}}}};
    }

    // An accessor of `count` VEC3 floats without a bufferView (zeros until made sparse).
    int addZeroVec3s(size_t count)
    {
        return push("accessors", {{"componentType", kFloat}, {"type", "VEC3"}, {"count", count}});
    }

    // A mesh of the given primitives (see primitive()).
    int addMesh(std::vector<json> primitives) { return push("meshes", {{"primitives", primitives}}); }

    int addNode(const json& node, bool root = true)
    {
        int index = push("nodes", node);
        if (root) j["scenes"][0]["nodes"].push_back(index);
        return index;
    }

    int addMaterial(const json& material)
    {
        if (!j.contains("materials")) j["materials"] = json::array();
        return push("materials", material);
    }

    // `name`.gltf with its buffer in `name`.bin beside it.
    std::string writeGltf(const fs::path& dir, const std::string& name)
    {
        j["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", name + ".bin"}}});
        writeFile(dir / (name + ".bin"), bin.data(), bin.size());
        std::string text = j.dump(1);
        writeFile(dir / (name + ".gltf"), text.data(), text.size());
        return (dir / (name + ".gltf")).string();
    }

    // `name`.glb: header, JSON chunk (space-padded), BIN chunk (zero-padded).
    std::string writeGlb(const fs::path& dir, const std::string& name)
    {
        j["buffers"] = json::array({{{"byteLength", bin.size()}}});
        std::string text = j.dump();
        while (text.size() % 4) text += ' ';
        std::vector<unsigned char> payload = bin;
        while (payload.size() % 4) payload.push_back(0);
        std::vector<unsigned char> out;
        auto u32 = [&](uint32_t v) {
            unsigned char b[4];
            std::memcpy(b, &v, 4); // glb is little-endian, as is every host we build for
            out.insert(out.end(), b, b + 4);
        };
        out.insert(out.end(), {'g', 'l', 'T', 'F'});
        u32(2);
        u32(uint32_t(12 + 8 + text.size() + 8 + payload.size()));
        u32(uint32_t(text.size()));
        u32(0x4E4F534A); // "JSON"
        out.insert(out.end(), text.begin(), text.end());
        u32(uint32_t(payload.size()));
        u32(0x004E4942); // "BIN\0"
        out.insert(out.end(), payload.begin(), payload.end());
        writeFile(dir / (name + ".glb"), out.data(), out.size());
        return (dir / (name + ".glb")).string();
    }

    // Appends `value` to the array `key` (e.g. an accessor without a bufferView).
    int push(const char* key, const json& value)
    {
        j[key].push_back(value);
        return int(j[key].size()) - 1;
    }
};

json primitive(int position, int normal = -1, int indices = -1, int material = -1)
{
    json p = {{"attributes", {{"POSITION", position}}}};
    if (normal >= 0) p["attributes"]["NORMAL"] = normal;
    if (indices >= 0) p["indices"] = indices;
    if (material >= 0) p["material"] = material;
    return p;
}

// The triangle (0,0,0), (1,0,0), (0,1,0) with normal +z.
const std::vector<Vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// The model most tests start from: node 0 (a root) holds mesh 0, one
// non-indexed triangle (kTriangle, normals +z) of material 0, a grey Lambert
// diffuse (metallic 0).
GltfBuilder oneTriangle()
{
    GltfBuilder b;
    int pos = b.addVec3s(kTriangle);
    int nrm = b.addVec3s({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    int material = b.addMaterial(
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}}, {"metallicFactor", 0.0}}}});
    b.addNode({{"mesh", b.addMesh({primitive(pos, nrm, -1, material)})}});
    return b;
}

// A triangle in the plane x + y = 1 whose winding gives the normal (1,1,0)/√2,
// the normal its vertices carry.
GltfBuilder slantedTriangle(const json& nodeTransform)
{
    GltfBuilder b;
    int pos = b.addVec3s({{1, 0, 0}, {0, 1, 0}, {0, 1, 1}});
    Vec3 n = normalize(Vec3(1, 1, 0));
    int nrm = b.addVec3s({n, n, n});
    json node = nodeTransform;
    node["mesh"] = b.addMesh({primitive(pos, nrm)});
    b.addNode(node);
    return b;
}

// Each test writes into a directory of its own, removed afterwards.
class GltfLoader : public ::testing::Test {
protected:
    void SetUp() override
    {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::path(::testing::TempDir()) /
               ("wavevcm_gltf_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override
    {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    Scene load(GltfBuilder& b, const std::string& name = "scene") { return loadGltf(b.writeGltf(dir_, name)); }

    // One primitive of the given triangles with TEXCOORD_0 `uv` and a flat
    // normal map, so the loader gives its corners tangents, loaded.
    template <class Index>
    Scene loadNormalMapped(const std::vector<Vec3>& p, const std::vector<float>& uv, const std::vector<Index>& indices)
    {
        Image texture(1, 1);
        texture.rgb = {0.5f, 0.5f, 1.0f};
        writeImage((dir_ / "flat.png").string(), texture);
        GltfBuilder b;
        int pos = b.addVec3s(p);
        int tex = b.addAccessor(b.addView(uv.data(), uv.size() * 4), kFloat, "VEC2", int(p.size()));
        int idx = b.addIndices(indices);
        b.j["images"] = {{{"uri", "flat.png"}}};
        b.j["textures"] = {{{"source", 0}}};
        int material = b.addMaterial({{"normalTexture", {{"index", 0}}}, {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}});
        json prim = primitive(pos, -1, idx, material);
        prim["attributes"]["TEXCOORD_0"] = tex;
        b.addNode({{"mesh", b.addMesh({prim})}});
        return load(b, "normal-mapped");
    }

    // The Material the one triangle of oneTriangle() gets when its material is `material`.
    Material loadMaterial(const json& material)
    {
        GltfBuilder b = oneTriangle();
        b.j["materials"][0] = material;
        Scene s = load(b);
        EXPECT_EQ(s.triangleCount(), 1u);
        return s.materials.at(s.triangleMaterial.at(0));
    }

    // The same for a rough dielectric (metallic 0, roughness 1) with these material extensions.
    Material loadRoughDielectric(const json& extensions)
    {
        return loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
                             {"extensions", extensions}});
    }

    // Loading must throw wv::Error naming the file and containing `keyword`.
    void expectLoadError(const std::string& path, const std::string& keyword)
    {
        EXPECT_THROW(loadGltf(path), Error);
        try {
            loadGltf(path);
        } catch (const Error& e) {
            std::string message = e.what();
            EXPECT_NE(message.find(path), std::string::npos) << "message does not name the file: " << message;
            EXPECT_NE(message.find(keyword), std::string::npos)
                << "message does not mention '" << keyword << "': " << message;
        }
    }

    fs::path dir_;
};

// ---------------------------------------------------------------- transforms

TEST_F(GltfLoader, ParentTrsAndChildMatrixGiveWorldPositions)
{
    // Parent: T = (1,2,3), R = 90° about z, S = (2,3,4). Child: a matrix
    // scaling x by 2 and translating by (1,0,5). Worked by hand:
    // (0,0,0) → child (1,0,5) → S (2,0,20) → R (0,2,20) → T (1,4,23), etc.
    GltfBuilder b;
    int pos = b.addVec3s(kTriangle);
    int child = b.addNode({{"mesh", b.addMesh({primitive(pos)})},
                           {"matrix", {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 5, 1}}},
                          false);
    b.addNode({{"translation", {1, 2, 3}},
               {"rotation", {0, 0, kHalfSqrt2, kHalfSqrt2}},
               {"scale", {2, 3, 4}},
               {"children", {child}}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 1u);
    EXPECT_TRUE(near(s.vertices[0], {1, 4, 23}));
    EXPECT_TRUE(near(s.vertices[1], {1, 8, 23}));
    EXPECT_TRUE(near(s.vertices[2], {-2, 4, 23}));
    EXPECT_TRUE(s.normals.empty()) << "no primitive has NORMAL";
}

TEST_F(GltfLoader, NormalsUseTheInverseTransposeAndAreNormalized)
{
    // Scale x by 2: M·n would give (2,1,0)/√5; the inverse transpose gives
    // (1,2,0)/√5, which is also the normal of the scaled triangle.
    GltfBuilder b = slantedTriangle({{"scale", {2, 1, 1}}});
    Scene s = load(b);
    ASSERT_EQ(s.normals.size(), 3u);
    Vec3 expected = normalize(Vec3(1, 2, 0));
    for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(near(s.normals[k], expected)) << "vertex " << k;
        EXPECT_NEAR(length(s.normals[k]), 1.0f, 1e-6f);
    }
    EXPECT_TRUE(near(triangleNormal(s, 0), expected));
}

TEST_F(GltfLoader, MirroringKeepsNormalsAndWindingConsistent)
{
    // Mirror x: the normal (1,1,0)/√2 becomes (-1,1,0)/√2. glTF says a
    // negative determinant turns the winding clockwise, so the winding the
    // kernels see (counter-clockwise = front) must agree with that normal too.
    GltfBuilder b = slantedTriangle({{"scale", {-1, 1, 1}}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 1u);
    Vec3 expected = normalize(Vec3(-1, 1, 0));
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(s.normals[k], expected)) << "vertex " << k;
    EXPECT_TRUE(near(triangleNormal(s, 0), expected)) << "winding of the mirrored triangle";
    // The same three mirrored points, whatever their order.
    for (Vec3 p : {Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, 1, 1)}) {
        bool found = false;
        for (int k = 0; k < 3; ++k) found |= bool(near(s.vertices[k], p));
        EXPECT_TRUE(found) << "vertex (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
}

TEST_F(GltfLoader, IndexedAndNonIndexedPrimitives)
{
    GltfBuilder b;
    // Non-indexed: two triangles, six vertices in order.
    std::vector<Vec3> soup = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
    int soupPos = b.addVec3s(soup);
    // Indexed: a quad of four vertices, two triangles sharing an edge.
    std::vector<Vec3> quad = {{0, 0, 2}, {1, 0, 2}, {0, 1, 2}, {1, 1, 2}};
    int quadPos = b.addVec3s(quad);
    std::vector<uint16_t> quadIndices = {0, 1, 2, 2, 1, 3};
    int idx = b.addIndices(quadIndices);
    b.addNode({{"mesh", b.addMesh({primitive(soupPos), primitive(quadPos, -1, idx)})}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 4u);
    for (size_t i = 0; i < soup.size(); ++i) EXPECT_TRUE(near(s.vertices[i], soup[i])) << "soup vertex " << i;
    for (size_t i = 0; i < quadIndices.size(); ++i)
        EXPECT_TRUE(near(s.vertices[6 + i], quad[quadIndices[i]])) << "quad index " << i;
}

TEST_F(GltfLoader, IndexComponentTypes)
{
    // Each index type, read from an accessor that starts one index into its
    // view (the leading index is junk that must not be read).
    std::vector<Vec3> quad = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    std::vector<uint32_t> indices = {9, 0, 1, 2, 2, 1, 3};
    for (int type : {kUnsignedByte, kUnsignedShort, kUnsignedInt}) {
        SCOPED_TRACE("componentType " + std::to_string(type));
        size_t size = type == kUnsignedByte ? 1 : type == kUnsignedShort ? 2 : 4;
        std::vector<unsigned char> bytes(indices.size() * size);
        for (size_t i = 0; i < indices.size(); ++i) {
            uint32_t v = indices[i];
            uint16_t v16 = uint16_t(v);
            uint8_t v8 = uint8_t(v);
            std::memcpy(&bytes[i * size], size == 1 ? (void*)&v8 : size == 2 ? (void*)&v16 : (void*)&v, size);
        }
        GltfBuilder b;
        int pos = b.addVec3s(quad);
        int idx = b.addAccessor(b.addView(bytes.data(), bytes.size()), type, "SCALAR", indices.size() - 1, size);
        b.addNode({{"mesh", b.addMesh({primitive(pos, -1, idx)})}});
        Scene s = load(b, "indices" + std::to_string(type));
        ASSERT_EQ(s.triangleCount(), 2u);
        for (size_t i = 1; i < indices.size(); ++i)
            EXPECT_TRUE(near(s.vertices[i - 1], quad[indices[i]])) << "index " << i - 1;
    }
}

TEST_F(GltfLoader, InterleavedPositionAndNormalWithByteStride)
{
    // One view of 28-byte vertices: position, normal, 4 bytes of padding.
    std::vector<Vec3> positions = {{0, 0, 0}, {2, 0, 0}, {0, 0, -2}};
    std::vector<Vec3> normals = {{0, 1, 0}, normalize(Vec3(0, 1, 1)), normalize(Vec3(1, 1, 0))};
    const int stride = 28;
    std::vector<unsigned char> bytes(positions.size() * stride, 0xff);
    for (size_t i = 0; i < positions.size(); ++i) {
        std::memcpy(&bytes[i * stride], &positions[i], 12);
        std::memcpy(&bytes[i * stride + 12], &normals[i], 12);
    }
    GltfBuilder b;
    int view = b.addView(bytes.data(), bytes.size(), stride);
    int pos = b.addAccessor(view, kFloat, "VEC3", 3, 0);
    int nrm = b.addAccessor(view, kFloat, "VEC3", 3, 12);
    b.addNode({{"mesh", b.addMesh({primitive(pos, nrm)})}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 1u);
    ASSERT_EQ(s.normals.size(), 3u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(near(s.vertices[k], positions[k])) << "vertex " << k;
        EXPECT_TRUE(near(s.normals[k], normals[k])) << "normal " << k;
    }
}

TEST_F(GltfLoader, PrimitivesWithoutNormalsGetGeometricNormalsOnceAnyHasThem)
{
    // First a primitive without NORMAL, then one with: the first is filled in
    // with its geometric normal so the normal array stays per-vertex.
    GltfBuilder b;
    int pos = b.addVec3s({{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}); // normal -x by winding
    int withNormals = b.addVec3s(kTriangle);
    int nrm = b.addVec3s({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    b.addNode({{"mesh", b.addMesh({primitive(pos), primitive(withNormals, nrm)})}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 2u);
    ASSERT_EQ(s.normals.size(), 6u);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(s.normals[k], {-1, 0, 0})) << "vertex " << k;
    for (int k = 3; k < 6; ++k) EXPECT_TRUE(near(s.normals[k], {0, 0, 1})) << "vertex " << k;
}

TEST_F(GltfLoader, ZeroScaleNodeIsSkippedWithAWarning)
{
    GltfBuilder b = oneTriangle();
    b.addNode({{"mesh", 0}, {"translation", {5, 5, 5}}, {"scale", {0, 0, 0}}});
    Scene s = load(b);
    EXPECT_EQ(s.triangleCount(), 1u);
    EXPECT_TRUE(anyWarningContains(s, "zero-scale"));
    for (const Vec3& v : s.vertices) EXPECT_LT(v.x, 2.0f) << "a vertex of the zero-scale node";
}

// A scene far from the origin compared with its size is moved so that its
// centre is the origin, in double precision: the triangle 1e5 + 1e-3 away
// keeps its 1e-3 offsets exactly (a float at 1e5 resolves only 0.0078), and
// so does the camera beside it.
// A scene near the origin stays where it is.
TEST_F(GltfLoader, FarSceneIsMovedToTheOriginInDoublePrecision)
{
    GltfBuilder b = oneTriangle();
    // Bounds far off the data: the centre comes from the positions themselves.
    b.j["accessors"][0]["min"] = {-1e30, 0, 0};
    b.j["accessors"][0]["max"] = {1e30, 1, 0};
    b.j["nodes"][0]["translation"] = {1e5 + 1e-3, 0, 0};
    b.j["nodes"][0]["scale"] = {1e-3, 1e-3, 1e-3};
    // The camera moves with it.
    b.j["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.01}}}}});
    b.addNode({{"camera", 0}, {"translation", {1e5 + 1e-3, 0, 1e-2}}});
    Scene s = load(b);
    EXPECT_TRUE(near(s.camera.position, {-0.5e-3f, -0.5e-3f, 1e-2f}, 1e-9f));
    EXPECT_DOUBLE_EQ(s.origin[0], 1e5 + 1e-3 + 0.5e-3);
    EXPECT_DOUBLE_EQ(s.origin[1], 0.5e-3);
    EXPECT_TRUE(near(s.vertices[0], {-0.5e-3f, -0.5e-3f, 0}, 1e-9f));
    EXPECT_TRUE(near(s.vertices[1], {0.5e-3f, -0.5e-3f, 0}, 1e-9f));

    GltfBuilder atOrigin = oneTriangle();
    Scene unmoved = load(atOrigin, "unmoved");
    for (double o : unmoved.origin) EXPECT_EQ(o, 0.0);
}

TEST_F(GltfLoader, BinaryGlbLoads)
{
    GltfBuilder b = oneTriangle();
    b.j["nodes"][0]["translation"] = {0, 0, -3};
    Scene s = loadGltf(b.writeGlb(dir_, "scene"));
    ASSERT_EQ(s.triangleCount(), 1u);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(s.vertices[k], kTriangle[k] + Vec3(0, 0, -3)));
    ASSERT_EQ(s.normals.size(), 3u);
    EXPECT_TRUE(near(s.normals[0], {0, 0, 1}));
    EXPECT_EQ(s.materials.at(0).lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION);
}

// ------------------------------------------------------------------- cameras

json perspective(double yfov, double aspectRatio = 0)
{
    json p = {{"yfov", yfov}, {"znear", 0.01}};
    if (aspectRatio > 0) p["aspectRatio"] = aspectRatio;
    return {{"type", "perspective"}, {"perspective", p}};
}

TEST_F(GltfLoader, CameraFromNodeTransform)
{
    // Parent translates by (1,2,3); the camera node turns 90° about y, so its
    // -z (the view direction) becomes -x and its +y stays +y.
    GltfBuilder b = oneTriangle();
    b.j["cameras"] = json::array({perspective(0.9, 1.5)});
    int cam = b.addNode({{"camera", 0}, {"translation", {0, 0, 1}}, {"rotation", {0, kHalfSqrt2, 0, kHalfSqrt2}}},
                        false);
    b.addNode({{"translation", {1, 2, 3}}, {"children", {cam}}});
    Scene s = load(b);
    ASSERT_TRUE(s.cameraFromFile);
    EXPECT_TRUE(near(s.camera.position, {1, 2, 4}));
    EXPECT_TRUE(near(s.camera.forward, {-1, 0, 0}));
    EXPECT_TRUE(near(s.camera.up, {0, 1, 0}));
    EXPECT_FLOAT_EQ(s.camera.yfov, 0.9f);
    EXPECT_FLOAT_EQ(s.camera.aspectRatio, 1.5f);
    EXPECT_FALSE(anyWarningContains(s, "camera"));
}

TEST_F(GltfLoader, CameraUpFollowsRollAndAspectRatioIsOptional)
{
    // Rolled 90° about z: forward stays -z, up becomes -x.
    GltfBuilder b = oneTriangle();
    b.j["cameras"] = json::array({perspective(0.5)});
    b.addNode({{"camera", 0}, {"rotation", {0, 0, kHalfSqrt2, kHalfSqrt2}}});
    Scene s = load(b);
    ASSERT_TRUE(s.cameraFromFile);
    EXPECT_TRUE(near(s.camera.forward, {0, 0, -1}));
    EXPECT_TRUE(near(s.camera.up, {-1, 0, 0}));
    EXPECT_EQ(s.camera.aspectRatio, 0.0f) << "no aspectRatio in the file";
}

TEST_F(GltfLoader, FirstCameraWins)
{
    // Traversal meets the orthographic camera 0 first, at x = 7, then camera 2
    // at x = 1, then camera 1 at x = 2: all three, in that order.
    GltfBuilder b = oneTriangle();
    b.j["cameras"] = json::array({{{"type", "orthographic"},
                                   {"orthographic", {{"xmag", 2}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}},
                                  perspective(0.8), perspective(0.5)});
    b.addNode({{"camera", 0}, {"translation", {7, 0, 0}}});
    b.addNode({{"camera", 2}, {"translation", {1, 0, 0}}});
    b.addNode({{"camera", 1}, {"translation", {2, 0, 0}}});
    Scene s = load(b);
    ASSERT_TRUE(s.cameraFromFile);
    ASSERT_EQ(s.cameras.size(), 3u);
    EXPECT_TRUE(s.camera.orthographic);
    EXPECT_TRUE(near(s.camera.position, {7, 0, 0}));
    EXPECT_FALSE(s.cameras[1].orthographic);
    EXPECT_FLOAT_EQ(s.cameras[1].yfov, 0.5f);
    EXPECT_TRUE(near(s.cameras[1].position, {1, 0, 0}));
}

// glTF's orthographic camera: parallel rays over [−xmag, xmag] × [−ymag,
// ymag]; the default image aspect is xmag / ymag. xmag or ymag 0 is an error.
TEST_F(GltfLoader, OrthographicCamera)
{
    GltfBuilder b = oneTriangle();
    b.j["cameras"] = json::array(
        {{{"type", "orthographic"}, {"orthographic", {{"xmag", 3}, {"ymag", 1.5}, {"znear", 0.1}, {"zfar", 10}}}}});
    b.addNode({{"camera", 0}, {"translation", {7, 0, 0}}});
    Scene s = load(b);
    ASSERT_TRUE(s.cameraFromFile);
    EXPECT_TRUE(s.camera.orthographic);
    EXPECT_FLOAT_EQ(s.camera.ymag, 1.5f);
    EXPECT_FLOAT_EQ(s.camera.aspectRatio, 2.0f);
    EXPECT_TRUE(near(s.camera.forward, {0, 0, -1}));
    Camera c = makeCamera(s.camera, 200, 100);
    EXPECT_TRUE(s.features().orthographicCamera);
    EXPECT_FLOAT_EQ(c.up[1], 1.5f) << "half-height in scene units";
    EXPECT_FLOAT_EQ(c.right[0], 3.0f) << "half-width: ymag × the image's aspect";

    b.j["cameras"][0]["orthographic"]["ymag"] = 0;
    expectLoadError(b.writeGltf(dir_, "flat"), "xmag and ymag must be finite and not zero");
}

TEST_F(GltfLoader, NoCameraGivesWarningAndFramingCamera)
{
    GltfBuilder b = oneTriangle();
    Scene s = load(b);
    EXPECT_FALSE(s.cameraFromFile);
    EXPECT_TRUE(anyWarningContains(s, "no camera"));
    // The framing camera looks at the triangle's bounds from +z.
    EXPECT_TRUE(near(s.camera.position, framingCamera(s.bounds(), 0.0f).position));
    EXPECT_NEAR(s.camera.position.x, 0.5f, 1e-5f);
    EXPECT_NEAR(s.camera.position.y, 0.5f, 1e-5f);
    EXPECT_GT(s.camera.position.z, 0.5f);
    EXPECT_TRUE(near(s.camera.forward, {0, 0, -1}));
}

// -------------------------------------------------------------------- lights

// oneTriangle() plus the given KHR_lights_punctual lights.
GltfBuilder withLights(const json& lights)
{
    GltfBuilder b = oneTriangle();
    b.j["extensionsUsed"] = {"KHR_lights_punctual"};
    b.j["extensions"]["KHR_lights_punctual"]["lights"] = lights;
    return b;
}

json lightRef(int light) { return {{"KHR_lights_punctual", {{"light", light}}}}; }

TEST_F(GltfLoader, PointLight)
{
    GltfBuilder b = withLights(json::array({{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 4}}}));
    b.addNode({{"translation", {1, 2, 3}}, {"extensions", lightRef(0)}});
    Scene s = load(b);
    ASSERT_EQ(s.lights.size(), 1u);
    const Light& l = s.lights[0];
    EXPECT_EQ(l.type, LIGHT_POINT);
    EXPECT_TRUE(near({l.position[0], l.position[1], l.position[2]}, {1, 2, 3}));
    EXPECT_TRUE(near({l.emission[0], l.emission[1], l.emission[2]}, {4, 2, 1})) << "intensity × color";
    EXPECT_TRUE(s.features().pointLights);
    EXPECT_FALSE(s.features().spotLights);
    EXPECT_FALSE(s.features().directionalLights);
    EXPECT_FALSE(anyWarningContains(s, "KHR_lights_punctual")) << "KHR_lights_punctual is supported";
}

TEST_F(GltfLoader, SpotLight)
{
    // Turned -90° about x: the light's -z points down (-y). Colour defaults to white.
    GltfBuilder b = withLights(json::array(
        {{{"type", "spot"}, {"intensity", 10}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}}}));
    b.addNode({{"translation", {0, 3, 0}}, {"rotation", {-kHalfSqrt2, 0, 0, kHalfSqrt2}}, {"extensions", lightRef(0)}});
    Scene s = load(b);
    ASSERT_EQ(s.lights.size(), 1u);
    const Light& l = s.lights[0];
    EXPECT_EQ(l.type, LIGHT_SPOT);
    EXPECT_TRUE(near({l.position[0], l.position[1], l.position[2]}, {0, 3, 0}));
    EXPECT_TRUE(near({l.direction[0], l.direction[1], l.direction[2]}, {0, -1, 0}));
    EXPECT_TRUE(near({l.emission[0], l.emission[1], l.emission[2]}, {10, 10, 10}));
    EXPECT_NEAR(l.cosInnerCone, std::cos(0.2), 1e-6);
    EXPECT_NEAR(l.cosOuterCone, std::cos(0.5), 1e-6);
    EXPECT_TRUE(s.features().spotLights);
}

TEST_F(GltfLoader, DirectionalLightPointsAlongNodeMinusZInWorldSpace)
{
    // Child turns -z to -y (-90° about x); the parent scales y by 3 and turns
    // 90° about z, taking -y to +x. The direction is normalized.
    GltfBuilder b = withLights(json::array({{{"type", "directional"}, {"color", {0.5, 1, 0}}, {"intensity", 2}}}));
    int child = b.addNode({{"rotation", {-kHalfSqrt2, 0, 0, kHalfSqrt2}}, {"extensions", lightRef(0)}}, false);
    b.addNode({{"rotation", {0, 0, kHalfSqrt2, kHalfSqrt2}}, {"scale", {1, 3, 1}}, {"children", {child}}});
    Scene s = load(b);
    ASSERT_EQ(s.lights.size(), 1u);
    const Light& l = s.lights[0];
    EXPECT_EQ(l.type, LIGHT_DIRECTIONAL);
    EXPECT_TRUE(near({l.direction[0], l.direction[1], l.direction[2]}, {1, 0, 0}));
    EXPECT_TRUE(near({l.emission[0], l.emission[1], l.emission[2]}, {1, 2, 0}));
    EXPECT_TRUE(s.features().directionalLights);
}

TEST_F(GltfLoader, BadSpotConeAnglesThrow)
{
    struct Cone {
        double inner, outer;
    };
    int n = 0;
    for (Cone c : {Cone{0.5, 0.5}, Cone{0.6, 0.5}, Cone{0.0, 2.0}, Cone{-0.1, 0.5}}) {
        SCOPED_TRACE("inner " + std::to_string(c.inner) + ", outer " + std::to_string(c.outer));
        GltfBuilder b = withLights(json::array(
            {{{"type", "spot"}, {"spot", {{"innerConeAngle", c.inner}, {"outerConeAngle", c.outer}}}}}));
        b.addNode({{"extensions", lightRef(0)}});
        expectLoadError(b.writeGltf(dir_, "cone" + std::to_string(n++)), "cone");
    }
}

// ----------------------------------------------------------------- materials

TEST_F(GltfLoader, MaterialPureLambert)
{
    Material m = loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
                               {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.0}}}}}});
    EXPECT_EQ(m.lobes, LOBE_DIFFUSE);
    EXPECT_EQ(m.specular, 0.0f);
}

TEST_F(GltfLoader, MaterialDefaultDielectric)
{
    Material m = loadMaterial(
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.6, 0.4, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.5}}}});
    EXPECT_EQ(m.lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION);
    EXPECT_FLOAT_EQ(m.baseColor[0], 0.8f);
    EXPECT_FLOAT_EQ(m.baseColor[1], 0.6f);
    EXPECT_FLOAT_EQ(m.baseColor[2], 0.4f);
    EXPECT_FLOAT_EQ(m.roughness, 0.5f);
    EXPECT_FLOAT_EQ(m.specular, 1.0f);
    EXPECT_FLOAT_EQ(m.ior, 1.5f);
}

TEST_F(GltfLoader, MaterialSmoothMetal)
{
    Material m = loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}}});
    EXPECT_EQ(m.lobes, LOBE_DELTA_REFLECTION);
}

TEST_F(GltfLoader, MaterialGlass)
{
    Material m = loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                               {"extensions",
                                {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                                 {"KHR_materials_ior", {{"ior", 1.5}}},
                                 {"KHR_materials_volume", {{"thicknessFactor", 0.1}}}}}});
    EXPECT_EQ(m.lobes, LOBE_DELTA_REFLECTION | LOBE_DELTA_TRANSMISSION);
    EXPECT_EQ(m.lobes & LOBE_DIFFUSE, 0u);
    EXPECT_EQ(m.thinWalled, 0);
    EXPECT_FLOAT_EQ(m.transmission, 1.0f);
    EXPECT_FLOAT_EQ(m.ior, 1.5f);
}

TEST_F(GltfLoader, MaterialRoughGlass)
{
    Material m = loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.3}}},
                               {"extensions",
                                {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                                 {"KHR_materials_volume", {{"thicknessFactor", 1.0}}}}}});
    EXPECT_EQ(m.lobes, LOBE_GGX_REFLECTION | LOBE_GGX_TRANSMISSION);
}

TEST_F(GltfLoader, MaterialTransmissionWithoutVolumeIsThinWalled)
{
    Material m = loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                               {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}});
    EXPECT_EQ(m.thinWalled, 1);
    EXPECT_EQ(m.lobes, LOBE_DELTA_REFLECTION | LOBE_DELTA_TRANSMISSION);
}

TEST_F(GltfLoader, MaterialVolumeWithZeroThicknessIsThinWalled)
{
    Material m = loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                               {"extensions",
                                {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                                 {"KHR_materials_volume", {{"thicknessFactor", 0.0}}}}}});
    EXPECT_EQ(m.thinWalled, 1);
}

TEST_F(GltfLoader, MaterialEmissionIsFactorTimesStrength)
{
    GltfBuilder b = oneTriangle();
    b.j["materials"][0]["emissiveFactor"] = {1, 0.5, 0.25};
    b.j["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 4;
    Scene s = load(b);
    const Material& m = s.materials.at(s.triangleMaterial.at(0));
    EXPECT_FLOAT_EQ(m.emission[0], 4.0f);
    EXPECT_FLOAT_EQ(m.emission[1], 2.0f);
    EXPECT_FLOAT_EQ(m.emission[2], 1.0f);
    EXPECT_TRUE(s.features().emissiveTriangles);
}

// KHR_materials_clearcoat: the coat's weight and roughness (default 0: a
// smooth coat), a GGX coat lobe above α = roughness² ≥ 1e-3, a delta one
// below, none at weight 0.
TEST_F(GltfLoader, MaterialClearcoat)
{
    auto coated = [&](json coat) {
        return loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}},
                             {"extensions", {{"KHR_materials_clearcoat", coat}}}});
    };
    Material rough = coated({{"clearcoatFactor", 0.7}, {"clearcoatRoughnessFactor", 0.4}});
    EXPECT_FLOAT_EQ(rough.clearcoat, 0.7f);
    EXPECT_FLOAT_EQ(rough.clearcoatRoughness, 0.4f);
    EXPECT_EQ(rough.lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_GGX_COAT);
    Material smooth = coated({{"clearcoatFactor", 1.0}});
    EXPECT_FLOAT_EQ(smooth.clearcoatRoughness, 0.0f);
    EXPECT_EQ(smooth.lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_DELTA_COAT);
    Material none = coated({{"clearcoatRoughnessFactor", 0.4}});
    EXPECT_EQ(none.clearcoat, 0.0f);
    EXPECT_EQ(none.lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION);
    Material clamped = coated({{"clearcoatFactor", 3.0}, {"clearcoatRoughnessFactor", -1.0}});
    EXPECT_EQ(clamped.clearcoat, 1.0f);
    EXPECT_EQ(clamped.clearcoatRoughness, 0.0f);
}

TEST_F(GltfLoader, MaterialClearcoatTextureNeedsAnIndex)
{
    GltfBuilder b = oneTriangle();
    b.j["materials"][0]["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0},
                                                                    {"clearcoatTexture", {{"texCoord", 0}}}};
    expectLoadError(b.writeGltf(dir_, "scene"), "KHR_materials_clearcoat.clearcoatTexture needs an integer index");
}

TEST_F(GltfLoader, MaterialClearcoatNormalTextureWarns)
{
    GltfBuilder b = oneTriangle();
    b.j["materials"][0]["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0},
                                                                    {"clearcoatNormalTexture", {{"index", 0}}}};
    Scene s = load(b);
    EXPECT_TRUE(anyWarningContains(s, "clearcoat normal texture is ignored"));
    EXPECT_TRUE(s.features().lobes & LOBE_DELTA_COAT);
}

// KHR_materials_sheen: the colour and roughness (defaults black and 0), a
// sheen lobe for a colour that is not black, none for black.
TEST_F(GltfLoader, MaterialSheen)
{
    auto sheened = [&](json sheen) { return loadRoughDielectric({{"KHR_materials_sheen", sheen}}); };
    Material m = sheened({{"sheenColorFactor", {0.5, 0.25, 2.0}}, {"sheenRoughnessFactor", 0.3}});
    EXPECT_FLOAT_EQ(m.sheenColor[0], 0.5f);
    EXPECT_FLOAT_EQ(m.sheenColor[1], 0.25f);
    EXPECT_FLOAT_EQ(m.sheenColor[2], 1.0f) << "clamped to 1";
    EXPECT_FLOAT_EQ(m.sheenRoughness, 0.3f);
    EXPECT_EQ(m.lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_SHEEN);
    Material black = sheened({{"sheenRoughnessFactor", 0.3}});
    EXPECT_EQ(black.sheenColor[0], 0.0f);
    EXPECT_EQ(black.lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION);
}

// KHR_materials_diffuse_transmission: the factor and colour (defaults 0 and
// white), a diffuse transmission lobe beside the diffuse one, which it
// replaces at factor 1 (a texture may scale the factor down, so the diffuse
// lobe stays then); none for a black colour; into a solid with
// KHR_materials_volume, where the solid's absorption is then compiled in.
TEST_F(GltfLoader, MaterialDiffuseTransmission)
{
    auto translucent = [&](json dt, json more = json::object()) {
        json extensions = {{"KHR_materials_diffuse_transmission", dt}};
        extensions.update(more);
        return loadRoughDielectric(extensions);
    };
    Material m = translucent({{"diffuseTransmissionFactor", 0.4}, {"diffuseTransmissionColorFactor", {0.5, 0.25, 2.0}}});
    EXPECT_FLOAT_EQ(m.diffuseTransmission, 0.4f);
    EXPECT_FLOAT_EQ(m.diffuseTransmissionColor[0], 0.5f);
    EXPECT_FLOAT_EQ(m.diffuseTransmissionColor[1], 0.25f);
    EXPECT_FLOAT_EQ(m.diffuseTransmissionColor[2], 1.0f) << "clamped to 1";
    EXPECT_EQ(m.thinWalled, 1);
    EXPECT_EQ(m.lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_DIFFUSE_TRANSMISSION);
    Material whole = translucent({{"diffuseTransmissionFactor", 1.0}});
    EXPECT_FLOAT_EQ(whole.diffuseTransmissionColor[1], 1.0f) << "white by default";
    EXPECT_EQ(whole.lobes, LOBE_GGX_REFLECTION | LOBE_DIFFUSE_TRANSMISSION);
    EXPECT_EQ(translucent({{"diffuseTransmissionFactor", 0.5}, {"diffuseTransmissionColorFactor", {0, 0, 0}}}).lobes,
              LOBE_DIFFUSE | LOBE_GGX_REFLECTION);
    EXPECT_EQ(translucent(json::object()).lobes, LOBE_DIFFUSE | LOBE_GGX_REFLECTION);
    Material solid = translucent({{"diffuseTransmissionFactor", 1.0}},
                                 {{"KHR_materials_volume",
                                   {{"thicknessFactor", 1.0}, {"attenuationDistance", 2.0},
                                    {"attenuationColor", {1.0, 0.5, 0.5}}}}});
    EXPECT_EQ(solid.thinWalled, 0);
    EXPECT_EQ(solid.lobes, LOBE_GGX_REFLECTION | LOBE_DIFFUSE_TRANSMISSION);

    GltfBuilder b = oneTriangle();
    b.j["materials"][0]["extensions"]["KHR_materials_diffuse_transmission"] = {{"diffuseTransmissionFactor", 1.0}};
    b.j["materials"][0]["extensions"]["KHR_materials_volume"] = {
        {"thicknessFactor", 1.0}, {"attenuationDistance", 2.0}, {"attenuationColor", {1.0, 0.5, 0.5}}};
    Scene s = load(b);
    EXPECT_TRUE(s.features().volumeAbsorption) << "a diffusely transmitting solid absorbs";
    EXPECT_FALSE(anyWarningContains(s, "KHR_materials_diffuse_transmission"));

    // With a texture the factor may fall anywhere to 0: the diffuse lobe stays.
    Image texture(1, 1);
    texture.rgb = {1, 1, 1};
    writeImage((dir_ / "white.png").string(), texture);
    GltfBuilder t = oneTriangle();
    t.j["images"] = {{{"uri", "white.png"}}};
    t.j["textures"] = {{{"source", 0}}};
    t.j["materials"][0]["extensions"]["KHR_materials_diffuse_transmission"] = {
        {"diffuseTransmissionFactor", 1.0}, {"diffuseTransmissionTexture", {{"index", 0}}}};
    Scene withTexture = load(t);
    const Material& textured = withTexture.materials.at(0);
    EXPECT_EQ(textured.diffuseTransmissionTexture, 1);
    EXPECT_EQ(textured.lobes & (LOBE_DIFFUSE | LOBE_DIFFUSE_TRANSMISSION), LOBE_DIFFUSE | LOBE_DIFFUSE_TRANSMISSION);
}

// KHR_materials_anisotropy: the strength (default 0) and the rotation's
// cosine and sine (default 0 rad); a smooth material made anisotropic is
// rough along the direction (a GGX lobe); tangents for its triangles (a
// primitive without TANGENT or texture coordinates gets an arbitrary one,
// with a warning); a rotation that is not a number leaves the default.
TEST_F(GltfLoader, MaterialAnisotropy)
{
    auto brushed = [&](json anisotropy, double roughness = 0.3) {
        return loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 1.0}, {"roughnessFactor", roughness}}},
                             {"extensions", {{"KHR_materials_anisotropy", anisotropy}}}});
    };
    Material m = brushed({{"anisotropyStrength", 0.6}, {"anisotropyRotation", 1.0}});
    EXPECT_FLOAT_EQ(m.anisotropy, 0.6f);
    EXPECT_FLOAT_EQ(m.anisotropyRotation[0], std::cos(1.0f));
    EXPECT_FLOAT_EQ(m.anisotropyRotation[1], std::sin(1.0f));
    EXPECT_EQ(m.lobes, LOBE_GGX_REFLECTION);
    Material plain = brushed(json::object());
    EXPECT_EQ(plain.anisotropy, 0.0f);
    EXPECT_FLOAT_EQ(plain.anisotropyRotation[0], 1.0f);
    EXPECT_EQ(brushed({{"anisotropyStrength", 0.5}}, 0.0).lobes, LOBE_GGX_REFLECTION) << "rough along the direction";
    EXPECT_EQ(brushed(json::object(), 0.0).lobes, LOBE_DELTA_REFLECTION);

    GltfBuilder b = oneTriangle();
    b.j["materials"][0]["extensions"]["KHR_materials_anisotropy"] = {{"anisotropyStrength", 1.0}};
    Scene s = load(b);
    EXPECT_TRUE(s.features().anisotropy);
    ASSERT_EQ(s.tangents.size(), 3u);
    EXPECT_NEAR(std::abs(s.tangents[0][2]), 0.0f, 1e-6f) << "perpendicular to the normal (0, 0, 1)";
    EXPECT_TRUE(anyWarningContains(s, "anisotropic material without TANGENT or texture coordinates"));
    EXPECT_FALSE(anyWarningContains(s, "KHR_materials_anisotropy"));

    b.j["materials"][0]["extensions"]["KHR_materials_anisotropy"] = {{"anisotropyStrength", 1.0},
                                                                     {"anisotropyRotation", "north"}};
    EXPECT_FLOAT_EQ(load(b).materials.at(0).anisotropyRotation[0], 1.0f) << "not a number: the default";
}

TEST_F(GltfLoader, MaterialDiffuseTransmissionTextureNeedsAnIndex)
{
    GltfBuilder b = oneTriangle();
    b.j["materials"][0]["extensions"]["KHR_materials_diffuse_transmission"] = {
        {"diffuseTransmissionFactor", 1.0}, {"diffuseTransmissionTexture", {{"texCoord", 0}}}};
    expectLoadError(b.writeGltf(dir_, "scene"),
                    "KHR_materials_diffuse_transmission.diffuseTransmissionTexture needs an integer index");
}

TEST_F(GltfLoader, MaterialIor1GlassHasNoReflection)
{
    // An interface of ior 1 reflects nothing: only the transmission lobe.
    Material m = loadMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                               {"extensions",
                                {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                                 {"KHR_materials_ior", {{"ior", 1.0}}}}}});
    EXPECT_EQ(m.lobes, LOBE_DELTA_TRANSMISSION);
}

// doubleSided: an emitter then emits from both faces (Light::sides, tested
// in DoubleSidedEmitterTest); glTF's default is one-sided.
TEST_F(GltfLoader, MaterialDoubleSided)
{
    EXPECT_EQ(loadMaterial({{"doubleSided", true}, {"emissiveFactor", {1, 1, 1}}}).doubleSided, 1);
    EXPECT_EQ(loadMaterial({{"emissiveFactor", {1, 1, 1}}}).doubleSided, 0);
}

TEST_F(GltfLoader, MaterialIorBelowOneThrows)
{
    GltfBuilder b = oneTriangle();
    b.j["materials"][0]["extensions"]["KHR_materials_ior"]["ior"] = 0.5;
    expectLoadError(b.writeGltf(dir_, "scene"), "ior");
}

TEST_F(GltfLoader, PrimitiveWithoutMaterialGetsTheGltfDefault)
{
    GltfBuilder b = oneTriangle();
    b.j["meshes"][0]["primitives"][0].erase("material");
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 1u);
    const Material& m = s.materials.at(s.triangleMaterial[0]);
    EXPECT_EQ(s.triangleMaterial[0], 1) << "appended after the file's one material";
    EXPECT_FLOAT_EQ(m.metallic, 1.0f);
    EXPECT_FLOAT_EQ(m.roughness, 1.0f);
    EXPECT_FLOAT_EQ(m.baseColor[0], 1.0f);
    EXPECT_EQ(m.lobes, LOBE_GGX_REFLECTION);
}

TEST_F(GltfLoader, BaseColorTextureWarns)
{
    // The image file only has to exist: images are not decoded.
    GltfBuilder b = oneTriangle();
    const char png[] = "not really a png";
    writeFile(dir_ / "tex.png", png, sizeof png);
    b.j["images"] = json::array({{{"uri", "tex.png"}}});
    b.j["textures"] = json::array({{{"source", 0}}});
    b.j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    Scene s = load(b);
    EXPECT_EQ(s.triangleCount(), 1u);
    EXPECT_TRUE(anyWarningContains(s, "texture"));
    EXPECT_FLOAT_EQ(s.materials.at(0).baseColor[0], 0.5f) << "the factor is still used";
}

// A texture whose image file is missing: textures are not used, so this is a
// warning naming the file, and the factors still apply.
TEST_F(GltfLoader, MissingTextureImageWarns)
{
    GltfBuilder b = oneTriangle();
    b.j["images"] = json::array({{{"uri", "missing.png"}}});
    b.j["textures"] = json::array({{{"source", 0}}});
    b.j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    Scene s = load(b);
    EXPECT_EQ(s.triangleCount(), 1u);
    EXPECT_TRUE(anyWarningContains(s, "missing.png"));
    EXPECT_FLOAT_EQ(s.materials.at(0).baseColor[0], 0.5f);
}

// ---------------------------------------------------------------- background

TEST_F(GltfLoader, BackgroundFromSceneExtras)
{
    GltfBuilder b = oneTriangle();
    b.j["scenes"][0]["extras"]["background"] = {0.1, 0.2, 0.3};
    Scene s = load(b);
    EXPECT_TRUE(near(s.background, {0.1f, 0.2f, 0.3f}, 1e-7f));
    EXPECT_TRUE(s.features().background);

    GltfBuilder none = oneTriangle();
    EXPECT_FALSE(load(none, "none").features().background);
}

TEST_F(GltfLoader, MalformedBackgroundThrows)
{
    int n = 0;
    for (json bg : {json{0.1, 0.2}, json{0.1, -1.0, 0.2}, json{0.1, 0.2, 0.3, 0.4}, json("white"),
                    json{0.1, "x", 0.2}}) {
        SCOPED_TRACE(bg.dump());
        GltfBuilder b = oneTriangle();
        b.j["scenes"][0]["extras"]["background"] = bg;
        expectLoadError(b.writeGltf(dir_, "bg" + std::to_string(n++)), "background");
    }
}

// KHR_mesh_quantization: positions as unsigned shorts (as values, placed by
// the node's scale and translation, as quantizing exporters do) and normals
// as normalized signed bytes give the float triangle's positions and normals;
// normalized unsigned bytes and signed shorts as values work too, and a
// 32-bit integer VEC3 is an error.
TEST_F(GltfLoader, QuantizedPositionsAndNormals)
{
    GltfBuilder b;
    // kTriangle scaled by 1/1000 around (2, 3, 4): stored as ((v − t) / s).
    // Elements 4-byte aligned, as the extension requires: a stride of 8 and 4 bytes.
    std::vector<uint16_t> pos = {0, 0, 0, 0, 1000, 0, 0, 0, 0, 1000, 0};
    std::vector<int8_t> nrm = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127};
    int p = b.addAccessor(b.addView(pos.data(), pos.size() * 2, 8), kUnsignedShort, "VEC3", 3);
    int n = b.addAccessor(b.addView(nrm.data(), nrm.size(), 4), 5120, "VEC3", 2);
    b.j["accessors"][n]["count"] = 3;
    b.j["accessors"][n]["normalized"] = true;
    b.j["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.j["extensionsRequired"] = {"KHR_mesh_quantization"};
    int material = b.addMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}});
    b.addNode({{"mesh", b.addMesh({primitive(p, n, -1, material)})},
               {"scale", {0.001, 0.001, 0.001}},
               {"translation", {2, 3, 4}}});
    Scene s = load(b, "quantized");
    ASSERT_EQ(s.vertices.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
        Vec3 expected = Vec3(2, 3, 4) + kTriangle[k] * 1.0f;
        EXPECT_TRUE(near(s.vertices[k] + Vec3(float(s.origin[0]), float(s.origin[1]), float(s.origin[2])), expected,
                         1e-5f))
            << k;
        EXPECT_TRUE(near(s.normals.at(k), {0, 0, 1}, 1e-6f)) << k;
    }

    GltfBuilder c;
    std::vector<uint8_t> unorm = {0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0}; // kTriangle, stride 4
    std::vector<int16_t> values = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}; // stride 8
    int p2 = c.addAccessor(c.addView(unorm.data(), unorm.size(), 4), kUnsignedByte, "VEC3", 3);
    c.j["accessors"][p2]["normalized"] = true;
    int n2 = c.addAccessor(c.addView(values.data(), values.size() * 2, 8), 5122, "VEC3", 3);
    int m2 = c.addMaterial({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}});
    c.addNode({{"mesh", c.addMesh({primitive(p2, n2, -1, m2)})}});
    Scene t = load(c, "quantized2");
    for (size_t k = 0; k < 3; ++k) {
        EXPECT_TRUE(near(t.vertices[k], kTriangle[k], 1e-6f)) << k;
        EXPECT_TRUE(near(t.normals.at(k), {0, 0, 1}, 1e-6f)) << k;
    }

    GltfBuilder d = oneTriangle();
    d.j["accessors"][0]["componentType"] = kUnsignedInt;
    expectLoadError(d.writeGltf(dir_, "quantized32"), "8- or 16-bit integers");
}

// A sparse accessor is its bufferView's elements, or zeros without one, with
// the elements at its indices replaced by its values: for vertex attributes
// and for indices alike.
TEST_F(GltfLoader, SparseAccessorsReplaceTheElementsTheyIndex)
{
    GltfBuilder b;
    int pos = b.addVec3s({{0, 0, 0}, {1, 0, 0}, {5, 5, 5}});
    b.makeSparse(pos, std::vector<uint16_t>{2}, std::vector<Vec3>{{0, 1, 0}});
    b.addNode({{"mesh", b.addMesh({primitive(pos)})}});
    Scene s = load(b, "sparse-view");
    ASSERT_EQ(s.vertices.size(), 3u);
    for (size_t k = 0; k < 3; ++k) EXPECT_TRUE(near(s.vertices[k], kTriangle[k])) << k;

    GltfBuilder c;
    int zeros = c.addZeroVec3s(3);
    c.makeSparse(zeros, std::vector<uint8_t>{1, 2}, std::vector<Vec3>{{1, 0, 0}, {0, 1, 0}});
    int idx = c.addIndices(std::vector<uint32_t>{0, 1, 1});
    c.makeSparse(idx, std::vector<uint32_t>{2}, std::vector<uint32_t>{2});
    c.addNode({{"mesh", c.addMesh({primitive(zeros, -1, idx)})}});
    Scene t = load(c, "sparse-zeros");
    ASSERT_EQ(t.vertices.size(), 3u);
    for (size_t k = 0; k < 3; ++k) EXPECT_TRUE(near(t.vertices[k], kTriangle[k])) << k;
}

TEST_F(GltfLoader, MalformedSparseAccessorsThrow)
{
    auto sparseTriangle = [&](const std::vector<uint16_t>& indices, const std::vector<Vec3>& values) {
        GltfBuilder b;
        int pos = b.addVec3s(kTriangle);
        b.makeSparse(pos, indices, values);
        b.addNode({{"mesh", b.addMesh({primitive(pos)})}});
        return b;
    };
    GltfBuilder b = sparseTriangle({3}, {{0, 0, 0}});
    expectLoadError(b.writeGltf(dir_, "past"), "sparse index 3 out of range");
    b = sparseTriangle({2, 1}, {{0, 0, 0}, {0, 0, 0}});
    expectLoadError(b.writeGltf(dir_, "order"), "not strictly increasing");
    b = sparseTriangle({1, 2}, {{0, 0, 0}});
    b.j["accessors"][0]["sparse"]["values"]["bufferView"] = b.j["accessors"][0]["sparse"]["indices"]["bufferView"];
    expectLoadError(b.writeGltf(dir_, "short"), "sparse values need");
    b = sparseTriangle({1}, {{0, 0, 0}});
    b.j["accessors"][0]["sparse"]["count"] = 4;
    expectLoadError(b.writeGltf(dir_, "count"), "sparse count 4");
    b = sparseTriangle({1}, {{0, 0, 0}});
    b.j["accessors"][0]["sparse"]["indices"]["componentType"] = kFloat;
    expectLoadError(b.writeGltf(dir_, "type"), "sparse indices must be");
    GltfBuilder c;
    int huge = c.addZeroVec3s(size_t(1) << 30);
    c.makeSparse(huge, std::vector<uint16_t>{0}, std::vector<Vec3>{{0, 0, 0}});
    c.addNode({{"mesh", c.addMesh({primitive(huge)})}});
    expectLoadError(c.writeGltf(dir_, "huge"), "without a bufferView");
}

// Morph targets are applied at the node's weights, else the mesh's (the pose
// a viewer shows without animation), to positions and normals; a target may
// be sparse, and a mesh without weights keeps its base geometry.
TEST_F(GltfLoader, MorphTargetsAtTheNodesOrTheMeshsWeights)
{
    auto morphed = [&](const json& meshWeights, const json& nodeWeights) {
        GltfBuilder b;
        int pos = b.addVec3s(kTriangle);
        int nrm = b.addVec3s({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
        int lift = b.addVec3s({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
        int tilt = b.addVec3s({{0, 1, -1}, {0, 1, -1}, {0, 1, -1}});
        int stretch = b.addZeroVec3s(3); // only vertex 2 moves: (0, 1, 0)
        b.makeSparse(stretch, std::vector<uint8_t>{2}, std::vector<Vec3>{{0, 1, 0}});
        json prim = primitive(pos, nrm);
        prim["targets"] = {{{"POSITION", lift}, {"NORMAL", tilt}}, {{"POSITION", stretch}}};
        json mesh = {{"primitives", {prim}}};
        if (!meshWeights.is_null()) mesh["weights"] = meshWeights;
        json node = {{"mesh", b.push("meshes", mesh)}};
        if (!nodeWeights.is_null()) node["weights"] = nodeWeights;
        b.addNode(node);
        return load(b, "morph");
    };
    Scene base = morphed(nullptr, nullptr);
    ASSERT_EQ(base.vertices.size(), 3u);
    for (size_t k = 0; k < 3; ++k) EXPECT_TRUE(near(base.vertices[k], kTriangle[k])) << k;

    Scene mesh = morphed(json{0.5, 0}, nullptr); // lift by 0.5, normal (0, 0.5, 0.5) normalized
    ASSERT_EQ(mesh.vertices.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
        EXPECT_TRUE(near(mesh.vertices[k], kTriangle[k] + Vec3(0, 0, 0.5f))) << k;
        EXPECT_TRUE(near(mesh.normals.at(k), {0, float(kHalfSqrt2), float(kHalfSqrt2)})) << k;
    }

    Scene node = morphed(json{0.5, 0}, json{1, 2}); // the node's weights win
    ASSERT_EQ(node.vertices.size(), 3u);
    EXPECT_TRUE(near(node.vertices[0], {0, 0, 1}));
    EXPECT_TRUE(near(node.vertices[1], {1, 0, 1}));
    EXPECT_TRUE(near(node.vertices[2], {0, 3, 1}));
    for (size_t k = 0; k < 3; ++k) EXPECT_TRUE(near(node.normals.at(k), {0, 1, 0})) << k;

    Scene fewer = morphed(json{1}, nullptr); // a missing weight is 0, with a warning
    EXPECT_TRUE(near(fewer.vertices[2], {0, 1, 1}));
    EXPECT_TRUE(anyWarningContains(fewer, "2 morph targets and 1 weights"));

    GltfBuilder b = oneTriangle();
    b.j["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 0}}};
    b.j["meshes"][0]["weights"] = {1e39}; // a double, but no float
    expectLoadError(b.writeGltf(dir_, "overflow"), "is not a finite float");
}

// COLOR_0 is read per vertex (normalized unsigned bytes as c / 255, floats as
// they are; a VEC3's alpha 1) and given out per triangle corner; once a
// primitive has colours, the triangles of those without are opaque white; a
// VEC2 is an error.
TEST_F(GltfLoader, VertexColorsArePerCorner)
{
    GltfBuilder b;
    int pos = b.addVec3s(kTriangle);
    std::vector<uint8_t> rgba = {255, 0, 0, 255, 0, 51, 0, 255, 0, 0, 255, 102};
    int col = b.addAccessor(b.addView(rgba.data(), rgba.size()), kUnsignedByte, "VEC4", 3);
    b.j["accessors"][col]["normalized"] = true;
    json coloured = primitive(pos);
    coloured["attributes"]["COLOR_0"] = col;
    int other = b.addVec3s({{0, 0, 1}, {1, 0, 1}, {0, 1, 1}});
    std::vector<float> rgb = {0.5f, 0.25f, 0.125f, 0.5f, 0.25f, 0.125f, 0.5f, 0.25f, 0.125f};
    int floats = b.addAccessor(b.addView(rgb.data(), rgb.size() * 4), kFloat, "VEC3", 3);
    json colouredToo = primitive(other);
    colouredToo["attributes"]["COLOR_0"] = floats;
    b.addNode({{"mesh", b.addMesh({primitive(pos), coloured, colouredToo})}});
    Scene s = load(b, "colours");
    ASSERT_EQ(s.vertices.size(), 9u);
    ASSERT_EQ(s.colors.size(), 9u);
    EXPECT_NE(s.features().buildOptions().find("-DHAS_VERTEX_COLORS"), std::string::npos);
    auto colour = [&](size_t k) {
        const std::array<float, 4>& c = s.colors[k];
        return std::vector<float>(c.begin(), c.end());
    };
    for (size_t k = 0; k < 3; ++k) EXPECT_EQ(colour(k), std::vector<float>({1, 1, 1, 1})) << k; // the first, uncoloured
    EXPECT_EQ(colour(3), std::vector<float>({1, 0, 0, 1}));
    EXPECT_EQ(colour(4), std::vector<float>({0, 0.2f, 0, 1}));
    EXPECT_EQ(colour(5), std::vector<float>({0, 0, 1, 0.4f}));
    for (size_t k = 6; k < 9; ++k) EXPECT_EQ(colour(k), std::vector<float>({0.5f, 0.25f, 0.125f, 1})) << k;

    GltfBuilder c = oneTriangle();
    std::vector<float> uv = {0, 0, 1, 0, 0, 1};
    c.j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
        c.addAccessor(c.addView(uv.data(), uv.size() * 4), kFloat, "VEC2", 3);
    expectLoadError(c.writeGltf(dir_, "vec2"), "COLOR_0 must be a VEC3 or a VEC4");
}

// A skinned mesh is placed by its joints, not its node: each vertex by the
// joint matrices (joint world transform × inverse bind matrix) weighted by
// its JOINTS_0 / WEIGHTS_0, its normal by their inverse transpose.
TEST_F(GltfLoader, SkinsPlaceVerticesByTheirJoints)
{
    // Joint 0 at (0, 0, 5) turned 90° about x; joint 1 its child, 2 up.
    auto skinned = [&](bool inverseBind, const std::vector<uint8_t>& jointIndices) {
        GltfBuilder b;
        int pos = b.addVec3s(kTriangle);
        int nrm = b.addVec3s({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
        int jnt = b.addAccessor(b.addView(jointIndices.data(), jointIndices.size()), kUnsignedByte, "VEC4", 3);
        std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0};
        int wgt = b.addAccessor(b.addView(weights.data(), weights.size() * 4), kFloat, "VEC4", 3);
        json prim = primitive(pos, nrm);
        prim["attributes"]["JOINTS_0"] = jnt;
        prim["attributes"]["WEIGHTS_0"] = wgt;
        int child = b.addNode({{"translation", {0, 2, 0}}}, false);
        int root = b.addNode({{"translation", {0, 0, 5}}, {"rotation", {kHalfSqrt2, 0, 0, kHalfSqrt2}}, {"children", {child}}});
        // Joint 1's bind pose 2 up (both joints then give one rigid motion), or
        // identities (Debian's tinygltf 2.7 refuses a skin without inverseBindMatrices).
        std::vector<float> m = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -2, 0, 1};
        if (!inverseBind) m[29] = 0;
        int ibm = b.addAccessor(b.addView(m.data(), m.size() * 4), kFloat, "MAT4", 2);
        b.j["skins"] = {{{"joints", {root, child}}, {"inverseBindMatrices", ibm}}};
        b.addNode({{"mesh", b.addMesh({prim})}, {"skin", 0}, {"translation", {100, 0, 0}}}); // ignored
        return b;
    };
    GltfBuilder rigid = skinned(true, {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
    Scene s = load(rigid, "rigid");
    ASSERT_EQ(s.vertices.size(), 3u);
    EXPECT_TRUE(near(s.vertices[0], {0, 0, 5}));
    EXPECT_TRUE(near(s.vertices[1], {1, 0, 5}));
    EXPECT_TRUE(near(s.vertices[2], {0, 0, 6}));
    for (size_t k = 0; k < 3; ++k) EXPECT_TRUE(near(s.normals.at(k), {0, -1, 0})) << k;

    GltfBuilder blended = skinned(false, {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}); // joint 1 at (0, 0, 7)
    Scene t = load(blended, "blended");
    ASSERT_EQ(t.vertices.size(), 3u);
    EXPECT_TRUE(near(t.vertices[0], {0, 0, 5}));
    EXPECT_TRUE(near(t.vertices[1], {1, 0, 7}));
    EXPECT_TRUE(near(t.vertices[2], {0, 0, 7})); // (0, 0, 1) + halfway between (0, 0, 5) and (0, 0, 7)

    // Far from the origin by its joints alone: moved there like any far scene.
    GltfBuilder distant = skinned(true, {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
    distant.j["nodes"][1]["translation"] = {1e8, 0, 5};
    Scene d = load(distant, "distant");
    ASSERT_EQ(d.vertices.size(), 3u);
    EXPECT_GT(d.origin[0], 9e7);
    Vec3 origin(float(d.origin[0]), float(d.origin[1]), float(d.origin[2]));
    EXPECT_TRUE(near(d.vertices[1] - d.vertices[0], {1, 0, 0})); // floats 1e8 out are 8 apart
    EXPECT_TRUE(near(d.vertices[0] + origin, {1e8f, 0, 5}, 8.0f));

    GltfBuilder far = skinned(true, {0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0});
    expectLoadError(far.writeGltf(dir_, "joint"), "names joint 2");
    GltfBuilder bare = skinned(true, {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
    bare.j["meshes"][0]["primitives"][0]["attributes"].erase("JOINTS_0");
    bare.j["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
    expectLoadError(bare.writeGltf(dir_, "bare"), "no JOINTS_0");
    GltfBuilder outside = skinned(true, {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});
    outside.j["scenes"][0]["nodes"] = {2}; // the mesh's node only: its joints are not rendered
    expectLoadError(outside.writeGltf(dir_, "outside"), "not in the rendered scene");
}

// A 4 × 2 map beside the glTF file, as extras.environment names it: read with
// the scene (rows from the top, texel values kept), its strength and rotation
// taken; a missing map, a non-linear format or a bad number is an error
// naming what is wrong.
TEST_F(GltfLoader, EnvironmentFromSceneExtras)
{
    std::vector<float> texels(4 * 2 * 3);
    for (size_t i = 0; i < texels.size(); ++i) texels[i] = float(i);
    std::string header = "PF\n4 2\n-1.0\n";
    std::vector<char> pfm(header.begin(), header.end());
    for (int row = 1; row >= 0; --row) { // PFM stores the bottom row first
        const char* p = reinterpret_cast<const char*>(&texels[size_t(row) * 12]);
        pfm.insert(pfm.end(), p, p + 12 * sizeof(float));
    }
    writeFile(dir_ / "map.pfm", pfm.data(), pfm.size());

    GltfBuilder b = oneTriangle();
    b.j["scenes"][0]["extras"]["environment"] = {{"uri", "map.pfm"}, {"strength", 2.5}, {"rotation", 90}};
    Scene s = load(b, "env");
    ASSERT_EQ(s.environment.image.width, 4);
    ASSERT_EQ(s.environment.image.height, 2);
    EXPECT_EQ(s.environment.image.rgb, texels);
    EXPECT_FLOAT_EQ(s.environment.strength, 2.5f);
    EXPECT_FLOAT_EQ(s.environment.rotation, 90.0f);
    EXPECT_TRUE(s.features().environmentMap);
    EXPECT_TRUE(s.hasLight());

    int n = 0;
    for (auto [environment, message] :
         {std::pair{json{{"uri", "missing.pfm"}}, std::string("missing.pfm: no such file")},
          std::pair{json{{"uri", "map.png"}}, std::string("must be linear radiance")},
          std::pair{json{{"uri", "map.pfm"}, {"strength", -1}}, std::string("strength must be >= 0")},
          std::pair{json{{"uri", "map.pfm"}, {"rotation", "north"}}, std::string("rotation must be a finite number")},
          std::pair{json("map.pfm"), std::string("\"uri\" string")}}) {
        SCOPED_TRACE(environment.dump());
        GltfBuilder bad = oneTriangle();
        bad.j["scenes"][0]["extras"]["environment"] = environment;
        expectLoadError(bad.writeGltf(dir_, "badenv" + std::to_string(n++)), message);
    }
}

// -------------------------------------------------------------------- errors

TEST_F(GltfLoader, MissingFileThrows)
{
    expectLoadError((dir_ / "does-not-exist.gltf").string(), "no such file");
}

TEST_F(GltfLoader, TruncatedJsonThrows)
{
    GltfBuilder b = oneTriangle();
    std::string path = b.writeGltf(dir_, "scene");
    fs::resize_file(path, fs::file_size(path) / 2);
    expectLoadError(path, "parse");
}

TEST_F(GltfLoader, MalformedJsonThrows)
{
    std::string text = "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [{\"mesh\": 0,]]}";
    writeFile(dir_ / "bad.gltf", text.data(), text.size());
    expectLoadError((dir_ / "bad.gltf").string(), "parse");
}

TEST_F(GltfLoader, TruncatedGlbThrows)
{
    GltfBuilder b = oneTriangle();
    std::string path = b.writeGlb(dir_, "scene");
    for (uintmax_t size : {fs::file_size(path) - 4, fs::file_size(path) / 2, uintmax_t(10)}) {
        SCOPED_TRACE("truncated to " + std::to_string(size) + " bytes");
        fs::resize_file(path, size);
        expectLoadError(path, "parse");
    }
}

TEST_F(GltfLoader, AccessorPastTheEndOfItsBufferViewThrows)
{
    // Thirty positions claimed, three stored.
    GltfBuilder b = oneTriangle();
    b.j["accessors"][0]["count"] = 30;
    expectLoadError(b.writeGltf(dir_, "scene"), "accessor needs");
}

TEST_F(GltfLoader, AccessorOffsetPastTheEndOfItsBufferViewThrows)
{
    GltfBuilder b = oneTriangle();
    b.j["accessors"][1]["byteOffset"] = 1000000000000000;
    expectLoadError(b.writeGltf(dir_, "scene"), "accessor needs");
}

TEST_F(GltfLoader, BufferViewPastTheEndOfItsBufferThrows)
{
    GltfBuilder b = oneTriangle();
    b.j["bufferViews"][1]["byteLength"] = 4096;
    expectLoadError(b.writeGltf(dir_, "scene"), "past the end");
}

TEST_F(GltfLoader, BinFileShorterThanItsBufferThrows)
{
    GltfBuilder b = oneTriangle();
    std::string path = b.writeGltf(dir_, "scene");
    fs::resize_file(dir_ / "scene.bin", 20);
    expectLoadError(path, "parse");
}

TEST_F(GltfLoader, IndexOutOfRangeThrows)
{
    GltfBuilder b;
    int pos = b.addVec3s(kTriangle);
    int idx = b.addIndices(std::vector<uint16_t>{0, 1, 7});
    b.addNode({{"mesh", b.addMesh({primitive(pos, -1, idx)})}});
    expectLoadError(b.writeGltf(dir_, "scene"), "index 7 out of range");
}

TEST_F(GltfLoader, IndexCountNotAMultipleOfThreeThrows)
{
    GltfBuilder b;
    int pos = b.addVec3s(kTriangle);
    int idx = b.addIndices(std::vector<uint32_t>{0, 1, 2, 0});
    b.addNode({{"mesh", b.addMesh({primitive(pos, -1, idx)})}});
    expectLoadError(b.writeGltf(dir_, "scene"), "multiple of 3");
}

TEST_F(GltfLoader, NaNPositionThrows)
{
    GltfBuilder b;
    float nan = std::numeric_limits<float>::quiet_NaN();
    int pos = b.addVec3s({{0, 0, 0}, {1, nan, 0}, {0, 1, 0}});
    b.addNode({{"mesh", b.addMesh({primitive(pos)})}});
    expectLoadError(b.writeGltf(dir_, "scene"), "NaN");
}

TEST_F(GltfLoader, InfinitePositionThrows)
{
    GltfBuilder b;
    float inf = std::numeric_limits<float>::infinity();
    int pos = b.addVec3s({{0, 0, 0}, {1, 0, -inf}, {0, 1, 0}});
    b.addNode({{"mesh", b.addMesh({primitive(pos)})}});
    expectLoadError(b.writeGltf(dir_, "scene"), "NaN or Inf");
}

TEST_F(GltfLoader, LinesOnlySceneThrowsNamingTheSkippedLines)
{
    GltfBuilder b = oneTriangle();
    b.j["meshes"][0]["primitives"][0]["mode"] = 1;
    expectLoadError(b.writeGltf(dir_, "scene"), "no triangles (skipped: LINES primitives)");
}

TEST_F(GltfLoader, PointsAndLinesBesideTrianglesAreSkippedWithAWarning)
{
    GltfBuilder b = oneTriangle();
    json points = b.j["meshes"][0]["primitives"][0];
    points["mode"] = 0;
    json lines = points;
    lines["mode"] = 3;
    b.j["meshes"][0]["primitives"].push_back(points);
    b.j["meshes"][0]["primitives"].push_back(lines);
    Scene s = load(b);
    EXPECT_EQ(s.triangleCount(), 1u);
    EXPECT_TRUE(anyWarningContains(s, "POINTS primitives are skipped"));
    EXPECT_TRUE(anyWarningContains(s, "LINE_STRIP primitives are skipped"));
}

TEST_F(GltfLoader, UnknownPrimitiveModeThrows)
{
    GltfBuilder b = oneTriangle();
    b.j["meshes"][0]["primitives"][0]["mode"] = 7;
    expectLoadError(b.writeGltf(dir_, "scene"), "unknown primitive mode 7");
}

// glTF's fan rule: triangle i is (v_{i+1}, v_{i+2}, v_0); counter-clockwise
// vertices around v_0 give triangles facing +z.
TEST_F(GltfLoader, TriangleFanIsTriangulatedWithGltfWinding)
{
    GltfBuilder b;
    json p = primitive(b.addVec3s({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}}));
    p["mode"] = 6;
    b.addNode({{"mesh", b.addMesh({p})}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 3u);
    for (size_t t = 0; t < s.triangleCount(); ++t) EXPECT_TRUE(near(triangleNormal(s, t), {0, 0, 1})) << t;
}

// Vertices alternating between y = 1 and y = 0 along x.
std::vector<Vec3> zigzag(int n)
{
    std::vector<Vec3> v;
    for (int i = 0; i < n; ++i) v.push_back({float(i / 2) + (i % 2) * 0.5f, float(1 - i % 2), 0});
    return v;
}

TEST_F(GltfLoader, TriangleStripWithARepeatedIndexDropsTheDegenerateTriangles)
{
    GltfBuilder b;
    json p = primitive(b.addVec3s(zigzag(4)), -1, b.addIndices<uint16_t>({0, 1, 2, 2, 3}));
    p["mode"] = 5;
    b.addNode({{"mesh", b.addMesh({p})}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 1u) << "(0,1,2) kept, (1,2,2) and (2,2,3) dropped";
    EXPECT_TRUE(near(triangleNormal(s, 0), {0, 0, 1}));
}

TEST_F(GltfLoader, LongTriangleStripKeepsOneWindingThroughout)
{
    // Strip triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}): with the zigzag
    // starting at y = 1, all face +z. Ignoring the alternation would flip
    // every other one.
    GltfBuilder b;
    json p = primitive(b.addVec3s(zigzag(10)));
    p["mode"] = 5;
    b.addNode({{"mesh", b.addMesh({p})}});
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 8u);
    for (size_t t = 0; t < s.triangleCount(); ++t) EXPECT_TRUE(near(triangleNormal(s, t), {0, 0, 1})) << t;
}

// ------------------------------------------------ one mesh, five encodings

// An octagon on the integer grid [0, 64]² (z = 0, counter-clockwise seen from
// +z) as quantizing exporters store it; kOctagonScale makes it 2 units wide.
// As floats, ring[i] × kOctagonScale exactly (a power of two).
const std::vector<uint16_t> kOctagonGrid = {16, 0, 0, 48, 0, 0, 64, 16, 0, 64, 48, 0,
                                            48, 64, 0, 16, 64, 0, 0, 48, 0, 0, 16, 0};
constexpr double kOctagonScale = 1.0 / 32;

std::vector<Vec3> octagonRing()
{
    std::vector<Vec3> ring;
    for (size_t i = 0; i < kOctagonGrid.size(); i += 3)
        ring.push_back(Vec3(float(kOctagonGrid[i] * kOctagonScale), float(kOctagonGrid[i + 1] * kOctagonScale), 0));
    return ring;
}

// glTF's fan of the ring: triangles (r_{i+1}, r_{i+2}, r_0).
std::vector<uint16_t> octagonFanTriangles()
{
    std::vector<uint16_t> t;
    for (uint16_t i = 0; i + 2 < 8; ++i) t.insert(t.end(), {uint16_t(i + 1), uint16_t(i + 2), 0});
    return t;
}

#ifdef WAVEVCM_HAVE_DRACO
// The octagon's triangle list, with TEXCOORD_0 = (x, y) / 2, encoded by
// Draco without quantization (lossless); the ids of POSITION and TEXCOORD_0.
std::vector<unsigned char> dracoOctagon(int* positionId, int* uvId)
{
    std::vector<Vec3> ring = octagonRing();
    std::vector<uint16_t> tri = octagonFanTriangles();
    draco::TriangleSoupMeshBuilder builder;
    builder.Start(int(tri.size() / 3));
    *positionId = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    *uvId = builder.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
    for (size_t f = 0; f < tri.size() / 3; ++f) {
        const Vec3 &a = ring[tri[3 * f]], &b = ring[tri[3 * f + 1]], &c = ring[tri[3 * f + 2]];
        float ua[2] = {a.x / 2, a.y / 2}, ub[2] = {b.x / 2, b.y / 2}, uc[2] = {c.x / 2, c.y / 2};
        builder.SetAttributeValuesForFace(*positionId, draco::FaceIndex(uint32_t(f)), &a.x, &b.x, &c.x);
        builder.SetAttributeValuesForFace(*uvId, draco::FaceIndex(uint32_t(f)), ua, ub, uc);
    }
    std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
    draco::Encoder encoder;
    draco::EncoderBuffer out;
    EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &out).ok());
    return std::vector<unsigned char>(out.data(), out.data() + out.size());
}
#endif

enum class Encoding { List, Fan, Strip, Quantized, Draco };

// The octagon, tilted 60° about x and lifted over a 6 × 6 floor (both grey
// Lambert) under a white background, in one encoding: a triangle list of the fan's triangles; a
// TRIANGLE_FAN; a TRIANGLE_STRIP zigzagging across it (other triangles, the
// same surface); unsigned shorts placed by a child node's scale
// (KHR_mesh_quantization); the list compressed by Draco.
GltfBuilder octagonScene(Encoding encoding)
{
    GltfBuilder b;
    int material = b.addMaterial(
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.7, 0.7, 1.0}}, {"metallicFactor", 0.0}}}});
    int floor = b.addVec3s({{-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {-3, 0, -3}, {3, 0, 3}, {3, 0, -3}});
    b.addNode({{"mesh", b.addMesh({primitive(floor, -1, -1, material)})}});

    json octagon;
    json::array_t children;
    if (encoding == Encoding::Quantized) {
        int q = b.addAccessor(b.addView(kOctagonGrid.data(), kOctagonGrid.size() * 2), kUnsignedShort, "VEC3", 8);
        octagon = primitive(q, -1, b.addIndices<uint16_t>(octagonFanTriangles()), material);
        b.j["extensionsUsed"] = {"KHR_mesh_quantization"};
        b.j["extensionsRequired"] = {"KHR_mesh_quantization"};
    } else if (encoding == Encoding::Draco) {
#ifdef WAVEVCM_HAVE_DRACO
        int positionId, uvId;
        std::vector<unsigned char> data = dracoOctagon(&positionId, &uvId);
        int view = b.addView(data.data(), data.size());
        // Accessors of compressed data have no bufferView.
        int p = b.push("accessors", {{"componentType", kFloat}, {"type", "VEC3"}, {"count", 8},
                                     {"min", {0, 0, 0}}, {"max", {2, 2, 0}}});
        int uv = b.push("accessors", {{"componentType", kFloat}, {"type", "VEC2"}, {"count", 8}});
        int indices = b.push("accessors", {{"componentType", kUnsignedShort}, {"type", "SCALAR"}, {"count", 18}});
        octagon = primitive(p, -1, indices, material);
        octagon["attributes"]["TEXCOORD_0"] = uv;
        octagon["extensions"]["KHR_draco_mesh_compression"] = {
            {"bufferView", view}, {"attributes", {{"POSITION", positionId}, {"TEXCOORD_0", uvId}}}};
        b.j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
        b.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
#endif
    } else {
        std::vector<Vec3> ring = octagonRing();
        if (encoding == Encoding::Strip) // r0 r1 r7 r2 r6 r3 r5 r4
            ring = {ring[0], ring[1], ring[7], ring[2], ring[6], ring[3], ring[5], ring[4]};
        int p = b.addVec3s(ring);
        octagon = primitive(p, -1, encoding == Encoding::List ? b.addIndices<uint16_t>(octagonFanTriangles()) : -1, material);
        if (encoding != Encoding::List) octagon["mode"] = encoding == Encoding::Fan ? 6 : 5;
    }
    int mesh = b.addMesh({octagon});
    json tilted = {{"rotation", {std::sin(M_PI / 6), 0, 0, std::cos(M_PI / 6)}}, {"translation", {-1, 0.5, 0}}};
    if (encoding == Encoding::Quantized)
        tilted["children"] = {b.addNode({{"mesh", mesh}, {"scale", {kOctagonScale, kOctagonScale, kOctagonScale}}},
                                        false)};
    else
        tilted["mesh"] = mesh;
    b.addNode(tilted);
    b.addNode({{"camera", 0}, {"translation", {0, 3, 4}}, {"rotation", {-std::sin(0.3), 0, 0, std::cos(0.3)}}});
    b.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}}};
    b.j["scenes"][0]["extras"]["background"] = {1, 1, 1};
    return b;
}

// Triangles as sorted lists of their corners (after a cyclic rotation that
// puts the smallest corner first, so the winding is kept), for comparing
// meshes whose triangles come in another order.
std::vector<std::array<float, 9>> canonicalTriangles(const Scene& s)
{
    std::vector<std::array<float, 9>> out;
    for (size_t t = 0; t < s.triangleCount(); ++t) {
        std::array<std::array<float, 3>, 3> c;
        for (int k = 0; k < 3; ++k) c[k] = {s.vertices[3 * t + k].x, s.vertices[3 * t + k].y, s.vertices[3 * t + k].z};
        int first = int(std::min_element(c.begin(), c.end()) - c.begin());
        std::array<float, 9> tri;
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a) tri[3 * k + a] = c[(first + k) % 3][a];
        out.push_back(tri);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// KHR_draco_mesh_compression: the decoded triangles are the list's exactly
// (lossless encoding), windings kept, TEXCOORD_0 decoded beside them.
TEST_F(GltfLoader, DracoCompressedMeshGivesTheTrianglesOfTheList)
{
    if (!dracoSupported()) GTEST_SKIP() << "built without Draco (libdraco-dev)";
    GltfBuilder list = octagonScene(Encoding::List), draco = octagonScene(Encoding::Draco);
    Scene a = load(list, "list"), d = load(draco, "draco");
    EXPECT_TRUE(d.warnings.empty() || !anyWarningContains(d, "Draco")) << d.warnings.front();
    EXPECT_EQ(d.triangleCount(), a.triangleCount());
    EXPECT_EQ(canonicalTriangles(d), canonicalTriangles(a));
    for (size_t t = 2; t < d.triangleCount(); ++t) // the floor's two first, then the octagon's
        EXPECT_TRUE(near(triangleNormal(d, t), triangleNormal(a, 2), 1e-6f)) << t;
    GltfBuilder glb = octagonScene(Encoding::Draco);
    EXPECT_EQ(canonicalTriangles(loadGltf(glb.writeGlb(dir_, "draco"))), canonicalTriangles(a)) << "as .glb";

#ifdef WAVEVCM_HAVE_DRACO
    // TEXCOORD_0 beside the positions: (x, y) / 2 at every decoded point.
    int positionId, uvId;
    std::vector<unsigned char> data = dracoOctagon(&positionId, &uvId);
    DracoMesh m = decodeDraco(data.data(), data.size(), {{positionId, 3}, {uvId, 2}});
    ASSERT_EQ(m.points, 8u);
    ASSERT_EQ(m.indices.size(), 18u);
    for (size_t i = 0; i < m.points; ++i) {
        EXPECT_EQ(m.attributes[uvId][2 * i], m.attributes[positionId][3 * i] / 2) << i;
        EXPECT_EQ(m.attributes[uvId][2 * i + 1], m.attributes[positionId][3 * i + 1] / 2) << i;
    }
#endif
}

// A file made by Draco's own tool (draco_transcoder -qp 14 on the fuzz seed
// triangle.gltf, positions quantized to 14 bits): the same triangle, within
// the quantization step (the triangle spans 1 unit: 2^-14 ≈ 6e-5).
TEST_F(GltfLoader, DracoFileFromDracoTranscoderLoads)
{
    if (!dracoSupported()) GTEST_SKIP() << "built without Draco (libdraco-dev)";
    const std::string seeds = std::string(WAVEVCM_SOURCE_DIR) + "/tests/fuzz/seeds/";
    Scene plain = loadGltf(seeds + "triangle.gltf"), draco = loadGltf(seeds + "triangle-draco.glb");
    ASSERT_EQ(draco.triangleCount(), plain.triangleCount());
    for (size_t k = 0; k < 3; ++k) {
        bool found = false;
        for (size_t j = 0; j < 3; ++j) found = found || near(draco.vertices[k], plain.vertices[j], 1.5e-4f);
        EXPECT_TRUE(found) << "corner " << k;
    }
    EXPECT_TRUE(near(triangleNormal(draco, 0), triangleNormal(plain, 0), 1e-3f)) << "winding kept";
}

TEST_F(GltfLoader, DracoErrorsNameTheExtension)
{
    if (!dracoSupported()) GTEST_SKIP() << "built without Draco (libdraco-dev)";
    GltfBuilder truncated = octagonScene(Encoding::Draco);
    size_t length = truncated.j["bufferViews"].back()["byteLength"];
    truncated.j["bufferViews"].back()["byteLength"] = length / 2;
    expectLoadError(truncated.writeGltf(dir_, "truncated"), "KHR_draco_mesh_compression: Draco cannot decode it");

    GltfBuilder notDraco = octagonScene(Encoding::Draco);
    notDraco.j["meshes"].back()["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 0;
    expectLoadError(notDraco.writeGltf(dir_, "notdraco"), "not Draco data");

    GltfBuilder badView = octagonScene(Encoding::Draco);
    badView.j["meshes"].back()["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"] = 99;
    expectLoadError(badView.writeGltf(dir_, "badview"), "bufferView out of range");

    GltfBuilder badId = octagonScene(Encoding::Draco);
    badId.j["meshes"].back()["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"] = 7;
    expectLoadError(badId.writeGltf(dir_, "badid"), "no attribute 7");
}

// Two semantics naming one Draco attribute and one accessor (found by the
// fuzzer: the second took the decoded values from the first, leaving
// POSITION empty while the triangles indexed it). Each gets the values.
TEST_F(GltfLoader, DracoAttributeSharedBySemanticsLoads)
{
    if (!dracoSupported()) GTEST_SKIP() << "built without Draco (libdraco-dev)";
    GltfBuilder shared = octagonScene(Encoding::Draco);
    json& prim = shared.j["meshes"].back()["primitives"][0];
    prim["attributes"]["NORMAL"] = prim["attributes"]["POSITION"];
    prim["extensions"]["KHR_draco_mesh_compression"]["attributes"]["NORMAL"] =
        prim["extensions"]["KHR_draco_mesh_compression"]["attributes"]["POSITION"];
    Scene list = loadGltf(octagonScene(Encoding::List).writeGltf(dir_, "list"));
    Scene scene = loadGltf(shared.writeGltf(dir_, "shared"));
    EXPECT_EQ(scene.vertices.size(), list.vertices.size());
}

// What a viewer shows must not depend on how the mesh is stored: the same
// seed renders the same image (pt, the octagon's shading and its shadow on
// the floor) from every encoding. The fan and the quantized mesh give the
// list's triangles bit for bit; Draco gives them in another order (another
// BVH) and the strip cuts the same plane into other triangles, so their hits
// may differ by float rounding: relMSE ~1e-16 measured. The bound, 1e-10, is
// far below what a wrong mesh gives: one strip vertex moved by 1/32 (a grid
// step) measured 5e-6.
TEST_F(GltfLoader, EveryEncodingOfOneMeshRendersTheSameImage)
{
    DeviceInfo device = test::devicesUnderTest()[0];
    auto renderOf = [&](Encoding e, const std::string& name) {
        GltfBuilder b = octagonScene(e);
        return test::render(device, load(b, name), Algorithm::PathTracing, 64, 48, 2, 7).image;
    };
    Image plain = renderOf(Encoding::List, "list");
    std::vector<std::pair<Encoding, std::string>> others = {
        {Encoding::Fan, "fan"}, {Encoding::Strip, "strip"}, {Encoding::Quantized, "quantized"}};
    if (dracoSupported()) others.emplace_back(Encoding::Draco, "draco");
    for (const auto& [encoding, name] : others) {
        ImageDifference d = compareImages(renderOf(encoding, name), plain);
        EXPECT_LE(d.relMse, 1e-10) << name;
        std::printf("%s relMSE %g\n", name.c_str(), d.relMse);
    }
}

// Tangents made from the UVs at a mirror seam: a strip whose u runs 0 → 1 →
// 0 along x shares its middle vertices between the two halves. Summed over
// both (as per-vertex averaging does) the halves' ∂p/∂u cancel there; kept
// apart by UV winding, as MikkTSpace keeps them, every corner of the left
// half gets +x (handedness +1) and every corner of the right half −x
// (handedness −1: its bitangent still points up the texture).
TEST_F(GltfLoader, GeneratedTangentsKeepMirroredHalvesApart)
{
    std::vector<Vec3> p = {{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}, {-1, 1, 0}, {0, 1, 0}, {1, 1, 0}};
    std::vector<float> uv = {0, 1, 1, 1, 0, 1, 0, 0, 1, 0, 0, 0}; // v = 1 at the bottom row
    Scene s = loadNormalMapped(p, uv, std::vector<uint16_t>{0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4});
    ASSERT_EQ(s.triangleCount(), 4u);
    ASSERT_EQ(s.tangents.size(), 12u);
    for (size_t c = 0; c < 12; ++c) {
        bool left = c < 6;
        const std::array<float, 4>& t = s.tangents[c];
        EXPECT_TRUE(near(Vec3(t[0], t[1], t[2]), Vec3(left ? 1.0f : -1.0f, 0, 0), 1e-5f)) << "corner " << c;
        EXPECT_EQ(t[3], left ? 1.0f : -1.0f) << "corner " << c;
    }
}

// Tangents made from the UVs against MikkTSpace's own, as Blender computes
// and exports them (tests/data/mikktspace-*.gltf, written by
// scripts/make_tangent_references.py): Suzanne (mirrored UV halves, UV
// stretch), a UV sphere (seams, poles) and a wave with a hand-mirrored UV
// island. Each file is loaded as written and with TANGENT taken out; every
// corner's tangent must match within 5e-4 with the same handedness. The two
// agree to 1.2e-4 at worst (Blender's float arithmetic and the files'
// rounding, v' = 1 - v among it); the earlier per-vertex sums of unit ∂p/∂u
// with 3-D corner angles missed on Suzanne by 2.3e-3 at the median and 0.02
// at the 90th percentile (the sphere and the wave do not tell the two
// apart). Where MikkTSpace leaves a tangent undefined (a triangle of zero UV
// area sharing no vertex with others: Blender writes (1, 0, 0), not
// perpendicular to the normal), the loader's must be a unit vector
// perpendicular to the normal; Suzanne has one such triangle.
TEST_F(GltfLoader, GeneratedTangentsAreMikkTSpace)
{
    size_t undefined = 0;
    for (const char* name : {"suzanne", "sphere", "mirrored-wave"}) {
        fs::path file = fs::path(WAVEVCM_TEST_DATA_DIR) / ("mikktspace-" + std::string(name) + ".gltf");
        Scene reference = loadGltf(file.string());
        json doc = json::parse(std::ifstream(file));
        for (json& mesh : doc["meshes"])
            for (json& prim : mesh["primitives"]) prim["attributes"].erase("TANGENT");
        fs::path stripped = dir_ / (std::string(name) + "-no-tangents.gltf");
        std::ofstream(stripped) << doc.dump();
        Scene generated = loadGltf(stripped.string());
        ASSERT_EQ(reference.tangents.size(), generated.tangents.size()) << name;
        ASSERT_EQ(generated.normals.size(), generated.tangents.size()) << name;
        ASSERT_GT(generated.tangents.size(), 0u) << name;
        double worst = 0;
        size_t flipped = 0;
        for (size_t c = 0; c < generated.tangents.size(); ++c) {
            const std::array<float, 4>& r = reference.tangents[c];
            const std::array<float, 4>& g = generated.tangents[c];
            Vec3 rt = normalize(Vec3(r[0], r[1], r[2])), gt(g[0], g[1], g[2]), n = normalize(generated.normals[c]);
            if (std::fabs(dot(rt, n)) > 1e-3f) {
                ++undefined;
                EXPECT_NEAR(length(gt), 1.0f, 1e-5f) << name << " corner " << c;
                EXPECT_NEAR(dot(gt, n), 0.0f, 1e-5f) << name << " corner " << c;
                continue;
            }
            worst = std::max(worst, double(length(rt - gt)));
            flipped += r[3] != g[3];
        }
        EXPECT_LT(worst, 5e-4) << name << ": largest tangent difference";
        EXPECT_EQ(flipped, 0u) << name << ": corners of the other handedness of " << generated.tangents.size();
    }
    EXPECT_EQ(undefined, 3u) << "corners where MikkTSpace's tangent is undefined";
}

// A flat disc of 2,000 triangles around one centre vertex, UVs planar
// (u = x, v = −y): every tangent is +x with handedness +1 (within 1e-4: the
// rim's thin triangles lose digits to cancellation), the centre's too, whose
// group of 2,000 triangles takes the large-group path (host/scene/Tangents.cpp).
TEST_F(GltfLoader, LargeFanGetsThePlanarTangent)
{
    const int n = 2000;
    std::vector<Vec3> p = {{0, 0, 0}};
    std::vector<float> uv = {0, 0};
    std::vector<uint32_t> fan;
    for (int i = 0; i < n; ++i) {
        float a = 2.0f * float(M_PI) * float(i) / float(n);
        p.push_back({std::cos(a), std::sin(a), 0});
        uv.insert(uv.end(), {std::cos(a), -std::sin(a)});
        fan.insert(fan.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % n)});
    }
    Scene s = loadNormalMapped(p, uv, fan);
    ASSERT_EQ(s.tangents.size(), size_t(3 * n));
    size_t wrong = 0;
    for (const std::array<float, 4>& t : s.tangents)
        wrong += !near(Vec3(t[0], t[1], t[2]), Vec3(1, 0, 0), 1e-4f) || t[3] != 1.0f;
    EXPECT_EQ(wrong, 0u);
}

TEST_F(GltfLoader, Gltf1IsRefusedByName)
{
    fs::path path = dir_ / "old.gltf";
    std::ofstream(path) << R"({"asset": {"version": "1.0"}, "scene": "defaultScene",
        "scenes": {"defaultScene": {"nodes": ["node"]}}, "nodes": {"node": {"meshes": ["mesh"]}}})";
    expectLoadError(path.string(), "glTF 1.0 is not supported");
    // 1.0 files without asset.version show themselves by their string ids.
    std::ofstream(path) << R"({"scene": "defaultScene", "scenes": {"defaultScene": {"nodes": []}}})";
    expectLoadError(path.string(), "glTF 1.0 is not supported");
    // A binary glTF 1.0 (KHR_binary_glTF): header version 1.
    fs::path glb = dir_ / "old.glb";
    const unsigned char header[20] = {'g', 'l', 'T', 'F', 1, 0, 0, 0, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    writeFile(glb, header, sizeof header);
    expectLoadError(glb.string(), "glTF 1 is not supported");
}

TEST_F(GltfLoader, EveryPerspectiveCameraIsKeptInNodeOrder)
{
    GltfBuilder b = oneTriangle();
    b.j["cameras"] = json::array({perspective(0.8), perspective(0.5)});
    b.addNode({{"camera", 1}, {"translation", {1, 0, 0}}});
    b.addNode({{"camera", 0}, {"translation", {2, 0, 0}}});
    Scene s = load(b);
    ASSERT_EQ(s.cameras.size(), 2u);
    EXPECT_TRUE(near(s.cameras[0].position, {1, 0, 0}));
    EXPECT_TRUE(near(s.cameras[1].position, {2, 0, 0}));
    EXPECT_FLOAT_EQ(s.cameras[1].yfov, 0.8f);
    EXPECT_TRUE(near(s.camera.position, {1, 0, 0})) << "the first is the default";
}

TEST_F(GltfLoader, HasLightSeesEachKindOfLight)
{
    GltfBuilder dark = oneTriangle();
    EXPECT_FALSE(load(dark, "dark").hasLight());
    GltfBuilder emissive = oneTriangle();
    emissive.j["materials"][0]["emissiveFactor"] = {1, 1, 1};
    EXPECT_TRUE(load(emissive, "emissive").hasLight());
    GltfBuilder unusedEmissive = oneTriangle(); // an emissive material no triangle uses
    unusedEmissive.addMaterial({{"emissiveFactor", {1, 1, 1}}});
    EXPECT_FALSE(load(unusedEmissive, "unused").hasLight());
    GltfBuilder background = oneTriangle();
    background.j["scenes"][0]["extras"]["background"] = {0, 0, 0.1};
    EXPECT_TRUE(load(background, "background").hasLight());
}

TEST_F(GltfLoader, RequiredUnsupportedExtensionThrows)
{
    GltfBuilder b = oneTriangle();
    b.j["extensionsUsed"] = {"EXT_meshopt_compression"};
    b.j["extensionsRequired"] = {"EXT_meshopt_compression"};
    expectLoadError(b.writeGltf(dir_, "scene"), "required extension EXT_meshopt_compression is not supported");
}

TEST_F(GltfLoader, UsedUnsupportedExtensionWarns)
{
    GltfBuilder b = oneTriangle();
    b.j["extensionsUsed"] = {"KHR_materials_iridescence"};
    Scene s = load(b);
    EXPECT_TRUE(anyWarningContains(s, "KHR_materials_iridescence"));
}

TEST_F(GltfLoader, NodeCycleThrows)
{
    // Node 1 and node 2 are each other's child: an error, not an endless loop.
    GltfBuilder b = oneTriangle();
    b.addNode({{"mesh", 0}, {"children", {2}}});
    b.addNode({{"children", {1}}}, false);
    expectLoadError(b.writeGltf(dir_, "scene"), "cycle");
}

// A chain of a million nodes, each the only child of the one before, the
// last holding the mesh: loads (iteratively: recursion would overflow the
// stack) with every translation applied once.
TEST_F(GltfLoader, MillionNodeHierarchyLoads)
{
    const int depth = 1000000;
    GltfBuilder b = oneTriangle();
    json mesh = b.j["nodes"][0];
    json& nodes = b.j["nodes"];
    nodes = json::array();
    for (int i = 0; i < depth - 1; ++i)
        nodes.push_back({{"translation", {1e-6, 0, 0}}, {"children", {i + 1}}});
    mesh["translation"] = {1e-6, 0, 0};
    nodes.push_back(mesh);
    b.j["scenes"][0]["nodes"] = {0};
    Scene s = load(b);
    ASSERT_EQ(s.triangleCount(), 1u);
    EXPECT_NEAR(s.vertices[0].x, 1.0f, 1e-3f) << "a million translations of 1e-6";
}

TEST_F(GltfLoader, SceneWithoutTrianglesThrows)
{
    GltfBuilder b = oneTriangle();
    b.j["scenes"][0]["nodes"] = json::array();
    b.addNode({{"translation", {1, 2, 3}}});
    expectLoadError(b.writeGltf(dir_, "scene"), "no triangles");
}

// --------------------------------------------------------------- Cornell box

TEST_F(GltfLoader, BundledCornellBox)
{
    Scene s = loadGltf(std::string(WAVEVCM_SOURCE_DIR) + "/scenes/cornell-box.gltf");
    EXPECT_EQ(s.triangleCount(), 1932u);
    EXPECT_EQ(s.vertices.size(), 3 * s.triangleCount());
    EXPECT_TRUE(s.cameraFromFile);
    SceneFeatures f = s.features();
    EXPECT_TRUE(f.emissiveTriangles);
    EXPECT_TRUE(f.vertexNormals);
    EXPECT_EQ(s.normals.size(), s.vertices.size());
    EXPECT_TRUE(f.lobes & LOBE_DIFFUSE);
    EXPECT_TRUE(f.lobes & LOBE_DELTA_REFLECTION);
    EXPECT_TRUE(f.lobes & LOBE_DELTA_TRANSMISSION);
    for (size_t i = 0; i < s.normals.size(); i += 97)
        EXPECT_NEAR(length(s.normals[i]), 1.0f, 1e-5f) << "normal " << i;
}

} // namespace
} // namespace wv
