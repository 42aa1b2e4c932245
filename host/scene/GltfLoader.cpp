#include "GltfLoader.h"

#include "../Error.h"
#include "DracoMesh.h"
#include "Tangents.h"

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace wv {
namespace {

using Mat4 = std::array<double, 16>; // column-major, as glTF stores matrices

Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 multiply(const Mat4& a, const Mat4& b)
{
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row)
            for (int k = 0; k < 4; ++k) r[c * 4 + row] += a[k * 4 + row] * b[c * 4 + k];
    return r;
}

Vec3 transformPoint(const Mat4& m, Vec3 p)
{
    return {float(m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12]),
            float(m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13]),
            float(m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14])};
}

Vec3 transformVector(const Mat4& m, Vec3 v)
{
    return {float(m[0] * v.x + m[4] * v.y + m[8] * v.z), float(m[1] * v.x + m[5] * v.y + m[9] * v.z),
            float(m[2] * v.x + m[6] * v.y + m[10] * v.z)};
}

// Normals transform with the inverse transpose; the cofactor matrix is that
// up to a positive or negative scale, which normalisation and the sign of the
// determinant take care of.
Vec3 transformNormal(const Mat4& m, Vec3 n)
{
    Vec3 c0{float(m[0]), float(m[1]), float(m[2])}, c1{float(m[4]), float(m[5]), float(m[6])},
        c2{float(m[8]), float(m[9]), float(m[10])};
    Vec3 r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
    float det = dot(c0, r0);
    Vec3 out = r0 * n.x + r1 * n.y + r2 * n.z;
    return det < 0 ? -out : out;
}

double determinant3(const Mat4& m)
{
    Vec3 c0{float(m[0]), float(m[1]), float(m[2])}, c1{float(m[4]), float(m[5]), float(m[6])},
        c2{float(m[8]), float(m[9]), float(m[10])};
    return dot(c0, cross(c1, c2));
}

// The node's local transform: its matrix, or T · R · S.
Mat4 localTransform(const tinygltf::Node& node)
{
    if (node.matrix.size() == 16) {
        Mat4 m;
        std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
        return m;
    }
    Mat4 t = identity(), r = identity(), s = identity();
    if (node.translation.size() == 3)
        for (int i = 0; i < 3; ++i) t[12 + i] = node.translation[i];
    if (node.rotation.size() == 4) {
        double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
        r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
             2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
             2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
             0, 0, 0, 1};
    }
    if (node.scale.size() == 3)
        for (int i = 0; i < 3; ++i) s[i * 5] = node.scale[i];
    return multiply(t, multiply(r, s));
}

// The images of a file, decoded by OpenImageIO as tinygltf hands over
// their bytes (from a file, a data URI or a bufferView), by image index; an
// image that does not decode is recorded, not fatal: a material that uses it
// keeps its factor, with a warning.
struct DecodedImages {
    std::map<int, Image> images;
    std::map<int, std::string> errors;
};

class Loader {
public:
    Loader(const std::string& path, Scene& scene) : path_(path), scene_(scene) {}

    void load();

private:
    [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }
    void warn(const std::string& what) { scene_.warnings.push_back(path_ + ": " + what); }
    void checkVersion(bool binary);
    void warnOnce(const std::string& what)
    {
        if (warned_.insert(what).second) warn(what);
    }

    void checkExtensions();
    void loadMaterials();
    Material convertMaterial(const tinygltf::Material& m, int index);
    void visitNodes();
    void chooseOrigin(const std::vector<std::pair<int, Mat4>>& placed);
    void addMesh(int meshIndex, const Mat4& world, const std::string& nodeName, const tinygltf::Node& node);
    const std::vector<Mat4>& skinMatrices(int skin, const std::string& nodeName);
    std::vector<Mat4> vertexSkinMatrices(const tinygltf::Primitive& prim, const std::vector<Mat4>& joints,
                                         size_t count, const std::string& what);
    void addCamera(int cameraIndex, const Mat4& world);
    void addLight(const tinygltf::Value& ext, const Mat4& world, const std::string& nodeName);
    void loadBackground();
    void loadEnvironment(const tinygltf::Value& environment);

    // 1 + the scene texture of a material's texture `info`, 0 (with a
    // warning) when it cannot be used; `kind` names it ("base-colour"),
    // `srgb`: its values are sRGB-encoded colour (else linear data).
    int sceneTexture(const tinygltf::TextureInfo& info, const std::string& material, const char* kind, bool srgb);

    // KHR_draco_mesh_compression (see hideDracoIndices): decodes mesh m's
    // primitive p once; its attributes' accessors then read from
    // dracoFloats_, its triangles are dracoTriangles_[{m, p}].
    std::string hideDracoIndices(const std::string& json);
    std::vector<unsigned char> hideDracoIndicesJson(const std::vector<unsigned char>& file);
    std::vector<unsigned char> hideDracoIndicesGlb(const std::vector<unsigned char>& file);
    void decodeDracoPrimitive(int mesh, int p, const std::string& what);

    // Reads an accessor's elements: `components` floats each (VECn), as
    // Vec3, as texture coordinates, or as indices.
    std::vector<float> readFloats(int accessorIndex, int components, const std::string& what, int type = 0);
    std::vector<Vec3> readVec3(int accessorIndex, const std::string& what);
    std::vector<float> readTexCoords(int accessorIndex, const std::string& what); // u, v per element
    std::vector<uint32_t> readIndices(int accessorIndex);
    // An accessor's elements as (data, stride): in its bufferView, or, for
    // a sparse accessor, packed into `storage` with the substitutions made.
    const unsigned char* accessorElements(const tinygltf::Accessor& a, size_t elementSize, size_t* stride,
                                          std::vector<unsigned char>& storage, const std::string& what);
    const unsigned char* accessorData(const tinygltf::Accessor& a, size_t elementSize,
                                      size_t* stride, const std::string& what);
    const tinygltf::BufferView& checkedView(int view, const std::string& what);
    std::vector<Vec3> morphDisplacement(const tinygltf::Primitive& prim, const std::vector<double>& weights,
                                        const char* semantic, size_t count, const std::string& what);

    std::string path_;
    Scene& scene_;
    tinygltf::Model model_;
    std::set<std::string> warned_;
    std::set<std::string> skippedModes_; // points and lines, for the error when nothing else is left
    int defaultMaterial_ = -1;
    bool tangentFrames_ = false; // some material has a normal texture or anisotropy: every triangle gets tangents
    DecodedImages images_;
    // (glTF texture, sRGB, uv transform, TEXCOORD set) → 1 + index in scene_.textures
    std::map<std::tuple<int, bool, std::array<float, 6>, int>, int> sceneTexture_;
    bool texCoord1_ = false; // some texture reads TEXCOORD_1: triangles keep that set too
    std::map<std::pair<int, int>, std::vector<uint32_t>> dracoTriangles_; // (mesh, primitive) → decoded indices
    std::map<int, std::vector<float>> dracoFloats_;                      // accessor → its decoded elements
    std::map<int, Mat4> jointWorld_; // skins' joint nodes → their world transforms (before the origin's move)
    std::map<int, std::vector<Mat4>> skinMatrices_; // skin → its joint matrices (likewise), made once
};

bool decodeGltfImage(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                     const unsigned char* bytes, int size, void* user)
{
    auto* decoded = static_cast<DecodedImages*>(user);
    std::string name = "image " + std::to_string(index) + (image->name.empty() ? "" : " '" + image->name + "'");
    try {
        decoded->images[index] = decodeImage(bytes, size_t(std::max(size, 0)), name);
    } catch (const Error& e) {
        decoded->errors[index] = e.what();
    }
    return true;
}

// After a failed parse: a glTF 1.0 file (string ids, techniques) fails with
// a message about some field; say what it is instead. (One that parses is
// caught by its asset.version.) Reads the file again only on this path.
void Loader::checkVersion(bool binary)
{
    std::ifstream in(path_, std::ios::binary);
    std::string version;
    if (binary) {
        unsigned char header[8] = {};
        in.read(reinterpret_cast<char*>(header), 8);
        if (in.gcount() == 8 && std::memcmp(header, "glTF", 4) == 0)
            version = std::to_string(header[4] | header[5] << 8 | header[6] << 16 | unsigned(header[7]) << 24);
    } else {
        nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
        if (j.is_object() && j.contains("asset") && j["asset"].is_object() && j["asset"].contains("version") &&
            j["asset"]["version"].is_string())
            version = j["asset"]["version"].get<std::string>();
        else if (j.is_object() && j.contains("scene") && j["scene"].is_string())
            version = "1.0"; // 1.0's string ids, with no asset.version
    }
    if (!version.empty() && version[0] == '1')
        fail("glTF " + version + " is not supported (only glTF 2.0): convert the file to glTF 2.0");
}

// KHR_draco_mesh_compression: the accessors of compressed data have no
// bufferView, and tinygltf (built without Draco, as Debian's is) refuses a
// primitive whose indices accessor has none. So before tinygltf parses the
// JSON, each compressed primitive's "indices" is taken out (the decoded
// triangles replace it), and the loader decodes the data itself
// (decodeDracoPrimitive), checking everything tinygltf's own decoder takes on
// trust. Malformed JSON is passed on unchanged, for tinygltf to report.
std::string Loader::hideDracoIndices(const std::string& text)
{
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (!j.is_object() || !j.contains("meshes") || !j["meshes"].is_array()) return text;
    bool changed = false;
    for (size_t m = 0; m < j["meshes"].size(); ++m) {
        nlohmann::json& mesh = j["meshes"][m];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (size_t p = 0; p < mesh["primitives"].size(); ++p) {
            nlohmann::json& prim = mesh["primitives"][p];
            if (!prim.is_object() || !prim.contains("extensions") || !prim["extensions"].is_object() ||
                !prim["extensions"].contains("KHR_draco_mesh_compression") || !prim.contains("indices"))
                continue;
            prim.erase("indices");
            changed = true;
        }
    }
    return changed ? j.dump() : text;
}

std::vector<unsigned char> Loader::hideDracoIndicesJson(const std::vector<unsigned char>& file)
{
    std::string text = hideDracoIndices(std::string(file.begin(), file.end()));
    return std::vector<unsigned char>(text.begin(), text.end());
}

// A .glb: 12-byte header, the JSON chunk, then the others (BIN), each chunk
// a length, a type and 4-byte-aligned data; rebuilt around the new JSON.
std::vector<unsigned char> Loader::hideDracoIndicesGlb(const std::vector<unsigned char>& file)
{
    auto u32 = [&](size_t at) {
        uint32_t v;
        std::memcpy(&v, &file[at], 4);
        return v;
    };
    if (file.size() < 20 || std::memcmp(file.data(), "glTF", 4) != 0 || u32(16) != 0x4E4F534A) return file;
    size_t jsonLength = u32(12);
    if (jsonLength > file.size() - 20) return file; // tinygltf says what is wrong
    std::string text = hideDracoIndices(std::string(file.begin() + 20, file.begin() + 20 + long(jsonLength)));
    while (text.size() % 4) text += ' ';
    std::vector<unsigned char> out(file.begin(), file.begin() + 12);
    auto put = [&](uint32_t v) {
        unsigned char b[4];
        std::memcpy(b, &v, 4);
        out.insert(out.end(), b, b + 4);
    };
    put(uint32_t(text.size()));
    put(0x4E4F534A);
    out.insert(out.end(), text.begin(), text.end());
    out.insert(out.end(), file.begin() + 20 + long(jsonLength), file.end());
    uint32_t total = uint32_t(out.size());
    std::memcpy(&out[8], &total, 4);
    return out;
}

void Loader::load()
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(path_, ec)) throw Error(path_ + ": no such file");
    if (!fs::is_regular_file(path_, ec)) throw Error(path_ + ": not a regular file");

    std::ifstream in(path_, std::ios::binary);
    if (!in) fail("cannot open the file");
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) fail("cannot read the file");
    if (bytes.size() > std::numeric_limits<unsigned>::max()) fail("files over 4 GiB are not supported");
    std::string ext = fs::path(path_).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    const bool binary = ext == ".glb";
    static const std::string draco = "KHR_draco_mesh_compression";
    if (std::search(bytes.begin(), bytes.end(), draco.begin(), draco.end()) != bytes.end())
        bytes = binary ? hideDracoIndicesGlb(bytes) : hideDracoIndicesJson(bytes);

    tinygltf::TinyGLTF gltf;
    gltf.SetImageLoader(decodeGltfImage, &images_);
    std::string err, warn;
    const std::string baseDir = fs::path(path_).parent_path().string();
    bool ok = false;
    try {
        ok = binary ? gltf.LoadBinaryFromMemory(&model_, &err, &warn, bytes.data(), unsigned(bytes.size()), baseDir)
                    : gltf.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                               unsigned(bytes.size()), baseDir);
    } catch (const std::exception& e) {
        checkVersion(binary);
        fail(std::string("cannot parse glTF: ") + e.what());
    }
    if (!ok || !err.empty()) {
        checkVersion(binary);
        while (!err.empty() && err.back() == '\n') err.pop_back();
        fail("cannot parse glTF: " + (err.empty() ? std::string("unknown error") : err));
    }
    if (!warn.empty()) {
        while (!warn.empty() && warn.back() == '\n') warn.pop_back();
        this->warn("tinygltf: " + warn);
    }
    if (!model_.asset.version.empty() && model_.asset.version[0] == '1')
        fail("glTF " + model_.asset.version + " is not supported (only glTF 2.0): convert the file to glTF 2.0");
    checkExtensions();
    loadMaterials();
    visitNodes();
    if (scene_.textures.empty()) scene_.uvs = {}; // only textures read them
    if (!texCoord1_) scene_.uvs1 = {};
    loadBackground();
    if (scene_.triangleCount() == 0) {
        std::string skipped;
        for (const std::string& m : skippedModes_) skipped += (skipped.empty() ? "" : ", ") + m;
        fail("the scene has no triangles" + (skipped.empty() ? std::string() : " (skipped: " + skipped + " primitives)"));
    }
}

const std::set<std::string>& supportedExtensions()
{
    static const std::set<std::string> s = [] {
        std::set<std::string> names{"KHR_materials_emissive_strength", "KHR_materials_specular",
                                    "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                                    "KHR_materials_clearcoat", "KHR_materials_sheen",
                                    "KHR_materials_diffuse_transmission", "KHR_materials_anisotropy",
                                    "KHR_lights_punctual",
                                    "EXT_texture_webp", "KHR_mesh_quantization", "KHR_texture_transform"};
        if (dracoSupported()) names.insert("KHR_draco_mesh_compression");
        return names;
    }();
    return s;
}

void Loader::checkExtensions()
{
    for (const std::string& e : model_.extensionsRequired)
        if (!supportedExtensions().count(e))
            fail("required extension " + e + " is not supported" +
                 (e == "KHR_draco_mesh_compression" ? ": this build has no Draco (install libdraco-dev and rebuild)" : ""));
    for (const std::string& e : model_.extensionsUsed)
        if (!supportedExtensions().count(e)) warn("extension " + e + " is not supported and is ignored");
}

double number(const tinygltf::Value& v, const char* key, double fallback)
{
    if (!v.IsObject() || !v.Has(key)) return fallback;
    const tinygltf::Value& x = v.Get(key);
    return x.IsNumber() ? x.GetNumberAsDouble() : fallback;
}

const tinygltf::Value* extension(const tinygltf::ExtensionMap& map, const char* name)
{
    auto it = map.find(name);
    return it == map.end() ? nullptr : &it->second;
}

void Loader::loadMaterials()
{
    for (size_t i = 0; i < model_.materials.size(); ++i) {
        scene_.materials.push_back(convertMaterial(model_.materials[i], int(i)));
        const Material& m = scene_.materials.back();
        tangentFrames_ = tangentFrames_ || m.normalTexture > 0 || m.anisotropy > 0;
    }
}

float clamp01(double x) { return float(std::min(1.0, std::max(0.0, x))); }

int Loader::sceneTexture(const tinygltf::TextureInfo& info, const std::string& material, const char* kind, bool srgb)
{
    std::string what = material + ": " + kind + " texture " + std::to_string(info.index);
    if (size_t(info.index) >= model_.textures.size()) fail(what + " out of range");
    int texCoord = info.texCoord;
    // KHR_texture_transform: uv' = offset + R(rotation) · (scale ∘ uv), R
    // counter-clockwise (the extension's matrix translation · rotation · scale).
    std::array<float, 6> transform{1, 0, 0, 0, 1, 0};
    if (const tinygltf::Value* e = extension(info.extensions, "KHR_texture_transform")) {
        auto pair = [&](const char* key, double fallback, int i) {
            if (!e->Has(key)) return fallback;
            const tinygltf::Value& v = e->Get(key);
            if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber() ||
                !std::isfinite(v.Get(i).GetNumberAsDouble()))
                fail(what + ": KHR_texture_transform." + key + " must be two finite numbers");
            return v.Get(i).GetNumberAsDouble();
        };
        double rotation = number(*e, "rotation", 0.0);
        if (!std::isfinite(rotation)) fail(what + ": KHR_texture_transform.rotation must be finite");
        double c = std::cos(rotation), s = std::sin(rotation);
        double sx = pair("scale", 1, 0), sy = pair("scale", 1, 1);
        transform = {float(c * sx), float(-s * sy), float(pair("offset", 0, 0)),
                     float(s * sx), float(c * sy), float(pair("offset", 0, 1))};
        if (e->Has("texCoord")) texCoord = int(number(*e, "texCoord", 0)); // the extension overrides the set
    }
    if (texCoord != 0 && texCoord != 1) {
        warnOnce(what + " uses TEXCOORD_" + std::to_string(texCoord) +
                 "; only TEXCOORD_0 and TEXCOORD_1 are read, so the material's factor is used");
        return 0;
    }
    auto known = sceneTexture_.find({info.index, srgb, transform, texCoord});
    if (known != sceneTexture_.end()) return known->second;
    const tinygltf::Texture& t = model_.textures[size_t(info.index)];
    // EXT_texture_webp names a WebP image, which OpenImageIO decodes, in place
    // of `source` (then an optional fallback for viewers without WebP).
    int source = t.source;
    if (const tinygltf::Value* webp = extension(t.extensions, "EXT_texture_webp")) {
        if (!webp->Has("source") || !webp->Get("source").IsInt())
            fail(what + ": EXT_texture_webp needs an integer source");
        source = webp->Get("source").GetNumberAsInt();
    }
    int result = 0;
    auto image = images_.images.find(source);
    if (source < 0 || size_t(source) >= model_.images.size()) {
        warnOnce(what + " has no image; the material's factor is used");
    } else if (image == images_.images.end()) {
        auto error = images_.errors.find(source);
        warnOnce(what + ": " + (error != images_.errors.end() ? error->second : "image " + std::to_string(source) +
                                    " could not be read") + "; the material's factor is used");
    } else {
        Texture texture;
        texture.name = what;
        texture.image = image->second;
        if (srgb) srgbToLinear(texture.image); // colour is sRGB-encoded (glTF 2.0 §3.9.2), data linear
        texture.uvTransform = transform;
        texture.texCoord = texCoord;
        texCoord1_ = texCoord1_ || texCoord == 1;
        if (t.sampler >= 0 && size_t(t.sampler) < model_.samplers.size()) {
            auto wrap = [](int mode) {
                return mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? WRAP_CLAMP
                       : mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? WRAP_MIRROR
                                                                       : WRAP_REPEAT;
            };
            texture.wrapS = wrap(model_.samplers[size_t(t.sampler)].wrapS);
            texture.wrapT = wrap(model_.samplers[size_t(t.sampler)].wrapT);
        }
        scene_.textures.push_back(std::move(texture));
        result = int(scene_.textures.size());
    }
    sceneTexture_[{info.index, srgb, transform, texCoord}] = result;
    return result;
}

Material Loader::convertMaterial(const tinygltf::Material& m, int index)
{
    std::string name = "material " + std::to_string(index) + (m.name.empty() ? "" : " '" + m.name + "'");
    const auto& pbr = m.pbrMetallicRoughness;
    Material out{};
    for (int c = 0; c < 3; ++c) {
        out.baseColor[c] = clamp01(pbr.baseColorFactor.size() == 4 ? pbr.baseColorFactor[c] : 1.0);
        out.emission[c] = float(std::max(0.0, m.emissiveFactor.size() == 3 ? m.emissiveFactor[c] : 0.0));
        out.specularColor[c] = 1.0f;
    }
    out.metallic = clamp01(pbr.metallicFactor);
    out.roughness = clamp01(pbr.roughnessFactor);
    out.specular = 1.0f;
    out.ior = 1.5f;
    out.thinWalled = 1;

    if (pbr.baseColorTexture.index >= 0)
        out.baseColorTexture = sceneTexture(pbr.baseColorTexture, name, "base-colour", true);
    if (pbr.metallicRoughnessTexture.index >= 0)
        out.metallicRoughnessTexture = sceneTexture(pbr.metallicRoughnessTexture, name, "metallic-roughness", false);
    if (m.normalTexture.index >= 0) {
        tinygltf::TextureInfo info;
        info.index = m.normalTexture.index;
        info.texCoord = m.normalTexture.texCoord;
        info.extensions = m.normalTexture.extensions;
        out.normalTexture = sceneTexture(info, name, "normal", false);
        out.normalScale = std::isfinite(m.normalTexture.scale) ? float(m.normalTexture.scale) : 1.0f;
    }
    if (m.emissiveTexture.index >= 0) out.emissiveTexture = sceneTexture(m.emissiveTexture, name, "emissive", true);
    if (m.occlusionTexture.index >= 0)
        warnOnce(name + ": the occlusion texture is ignored (the renderer computes occlusion itself)");
    // alphaMode: MASK cuts out where alpha < alphaCutoff, BLEND lets a ray
    // through with probability 1 − alpha (materials/alpha.h); alpha is
    // baseColorFactor's times the base-colour texture's.
    out.baseColorAlpha = clamp01(pbr.baseColorFactor.size() == 4 ? pbr.baseColorFactor[3] : 1.0);
    out.alphaCutoff = float(std::isfinite(m.alphaCutoff) ? m.alphaCutoff : 0.5);
    out.doubleSided = m.doubleSided ? 1 : 0;
    if (m.alphaMode == "MASK") out.alphaMode = ALPHA_MASK;
    else if (m.alphaMode == "BLEND") out.alphaMode = ALPHA_BLEND;
    else if (m.alphaMode != "OPAQUE" && !m.alphaMode.empty())
        fail(name + ": unknown alphaMode '" + m.alphaMode + "' (OPAQUE, MASK or BLEND)");

    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_emissive_strength")) {
        double strength = std::max(0.0, number(*e, "emissiveStrength", 1.0));
        for (float& c : out.emission) c *= float(strength);
    }
    // An extension's texture reference is plain JSON to tinygltf: its texture
    // (linear data, or sRGB-encoded colour), or 0 where it has none.
    auto extensionTexture = [&](const tinygltf::Value& e, const char* extensionName, const char* key,
                                const char* kind, bool srgb = false) {
        if (!e.Has(key)) return 0;
        const tinygltf::Value& t = e.Get(key);
        if (!t.IsObject() || !t.Has("index") || !t.Get("index").IsInt())
            fail(name + ": " + extensionName + "." + key + " needs an integer index");
        tinygltf::TextureInfo info;
        info.index = t.Get("index").GetNumberAsInt();
        info.texCoord = t.Has("texCoord") && t.Get("texCoord").IsInt() ? t.Get("texCoord").GetNumberAsInt() : 0;
        if (t.Has("extensions") && t.Get("extensions").IsObject())
            for (const std::string& k : t.Get("extensions").Keys()) info.extensions[k] = t.Get("extensions").Get(k);
        return sceneTexture(info, name, kind, srgb);
    };
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_specular")) {
        out.specular = clamp01(number(*e, "specularFactor", 1.0));
        if (e->Has("specularColorFactor") && e->Get("specularColorFactor").IsArray() &&
            e->Get("specularColorFactor").ArrayLen() == 3)
            for (int c = 0; c < 3; ++c)
                out.specularColor[c] = float(std::max(0.0, e->Get("specularColorFactor").Get(c).GetNumberAsDouble()));
        out.specularTexture = extensionTexture(*e, "KHR_materials_specular", "specularTexture", "specular");
        out.specularColorTexture =
            extensionTexture(*e, "KHR_materials_specular", "specularColorTexture", "specular colour", true);
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_ior")) {
        double ior = number(*e, "ior", 1.5);
        if (!(ior >= 1.0) || !std::isfinite(ior)) fail(name + ": KHR_materials_ior ior must be >= 1, got " + std::to_string(ior));
        out.ior = float(ior);
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_transmission")) {
        out.transmission = clamp01(number(*e, "transmissionFactor", 0.0));
        out.transmissionTexture =
            extensionTexture(*e, "KHR_materials_transmission", "transmissionTexture", "transmission");
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_sheen")) {
        if (e->Has("sheenColorFactor") && e->Get("sheenColorFactor").IsArray() &&
            e->Get("sheenColorFactor").ArrayLen() == 3)
            for (int c = 0; c < 3; ++c) out.sheenColor[c] = clamp01(e->Get("sheenColorFactor").Get(c).GetNumberAsDouble());
        out.sheenRoughness = clamp01(number(*e, "sheenRoughnessFactor", 0.0));
        if (std::max({out.sheenColor[0], out.sheenColor[1], out.sheenColor[2]}) > 0) {
            out.sheenColorTexture = extensionTexture(*e, "KHR_materials_sheen", "sheenColorTexture", "sheen colour", true);
            out.sheenRoughnessTexture =
                extensionTexture(*e, "KHR_materials_sheen", "sheenRoughnessTexture", "sheen roughness");
        }
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_clearcoat")) {
        out.clearcoat = clamp01(number(*e, "clearcoatFactor", 0.0));
        out.clearcoatRoughness = clamp01(number(*e, "clearcoatRoughnessFactor", 0.0));
        if (out.clearcoat > 0) {
            out.clearcoatTexture = extensionTexture(*e, "KHR_materials_clearcoat", "clearcoatTexture", "clearcoat");
            out.clearcoatRoughnessTexture = extensionTexture(*e, "KHR_materials_clearcoat",
                                                             "clearcoatRoughnessTexture", "clearcoat roughness");
            // The BSDF has one shading frame (kernels/materials/bsdf.h).
            if (e->Has("clearcoatNormalTexture"))
                warnOnce(name + ": the clearcoat normal texture is ignored; the coat follows the base's shading normal");
            else if (out.normalTexture > 0)
                warnOnce(name + ": the clearcoat follows the base's normal texture, where glTF leaves the coat unmapped");
        }
    }
    out.anisotropyRotation[0] = 1.0f;
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_anisotropy")) {
        out.anisotropy = clamp01(number(*e, "anisotropyStrength", 0.0));
        double rotation = number(*e, "anisotropyRotation", 0.0);
        if (!std::isfinite(rotation)) fail(name + ": KHR_materials_anisotropy anisotropyRotation is not finite");
        out.anisotropyRotation[0] = float(std::cos(rotation));
        out.anisotropyRotation[1] = float(std::sin(rotation));
        if (out.anisotropy > 0)
            out.anisotropyTexture = extensionTexture(*e, "KHR_materials_anisotropy", "anisotropyTexture", "anisotropy");
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_diffuse_transmission")) {
        out.diffuseTransmission = clamp01(number(*e, "diffuseTransmissionFactor", 0.0));
        for (int c = 0; c < 3; ++c) out.diffuseTransmissionColor[c] = 1.0f;
        if (e->Has("diffuseTransmissionColorFactor") && e->Get("diffuseTransmissionColorFactor").IsArray() &&
            e->Get("diffuseTransmissionColorFactor").ArrayLen() == 3)
            for (int c = 0; c < 3; ++c)
                out.diffuseTransmissionColor[c] =
                    clamp01(e->Get("diffuseTransmissionColorFactor").Get(c).GetNumberAsDouble());
        if (out.diffuseTransmission > 0) {
            out.diffuseTransmissionTexture = extensionTexture(*e, "KHR_materials_diffuse_transmission",
                                                              "diffuseTransmissionTexture", "diffuse transmission");
            out.diffuseTransmissionColorTexture =
                extensionTexture(*e, "KHR_materials_diffuse_transmission", "diffuseTransmissionColorTexture",
                                 "diffuse transmission colour", true);
        }
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_volume")) {
        out.thinWalled = number(*e, "thicknessFactor", 0.0) > 0.0 ? 0 : 1;
        out.attenuationDistance = float(std::max(0.0, number(*e, "attenuationDistance", 0.0)));
        for (int c = 0; c < 3; ++c) out.attenuationColor[c] = 1.0f;
        if (e->Has("attenuationColor") && e->Get("attenuationColor").IsArray() &&
            e->Get("attenuationColor").ArrayLen() == 3)
            for (int c = 0; c < 3; ++c)
                out.attenuationColor[c] = clamp01(e->Get("attenuationColor").Get(c).GetNumberAsDouble());
    }

    // Lobes (docs/scenes.md): a GGX alpha = roughness² below 1e-3 is treated as
    // perfectly smooth, where a microfacet lobe would be numerically useless;
    // anisotropy raises alpha along its direction to mix(alpha, 1, strength²).
    float alpha = out.roughness * out.roughness, strength2 = out.anisotropy * out.anisotropy;
    bool smooth = alpha + (1.0f - alpha) * strength2 < 1e-3f;
    auto maxOf = [](const float c[3]) { return std::max(c[0], std::max(c[1], c[2])); };
    // A metallic-roughness texture scales metallic down anywhere from the
    // factor to 0: the lobes must cover every value in between.
    float dielectric = out.metallicRoughnessTexture > 0 ? 1.0f : 1.0f - out.metallic;
    // A transmission texture scales transmission down anywhere to 0: the
    // diffuse lobe must then be there too.
    float opaquePart = out.transmissionTexture > 0 ? 1.0f : 1.0f - out.transmission;
    // Diffuse transmission takes its share of the diffuse part; its texture
    // scales it down anywhere to 0, which the reflecting share then covers.
    float reflectedPart = out.diffuseTransmissionTexture > 0 ? 1.0f : 1.0f - out.diffuseTransmission;
    bool diffuse = dielectric * opaquePart * reflectedPart > 0 && maxOf(out.baseColor) > 0;
    bool diffuseTransmits = dielectric * opaquePart * out.diffuseTransmission > 0 && maxOf(out.diffuseTransmissionColor) > 0;
    bool metalReflects = out.metallic > 0 && maxOf(out.baseColor) > 0;
    bool dielectricReflects = dielectric > 0 && out.ior != 1.0f &&
                              ((out.specular > 0 && maxOf(out.specularColor) > 0) || out.transmission > 0);
    bool transmits = dielectric * out.transmission > 0;
    if (diffuse) out.lobes |= LOBE_DIFFUSE;
    if (diffuseTransmits) out.lobes |= LOBE_DIFFUSE_TRANSMISSION;
    if (metalReflects || dielectricReflects) out.lobes |= smooth ? LOBE_DELTA_REFLECTION : LOBE_GGX_REFLECTION;
    if (transmits) out.lobes |= smooth ? LOBE_DELTA_TRANSMISSION : LOBE_GGX_TRANSMISSION;
    if (out.clearcoat > 0)
        out.lobes |= out.clearcoatRoughness * out.clearcoatRoughness < 1e-3f ? LOBE_DELTA_COAT : LOBE_GGX_COAT;
    if (maxOf(out.sheenColor) > 0) out.lobes |= LOBE_SHEEN;
    return out;
}

void Loader::visitNodes()
{
    int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    std::vector<int> roots;
    if (model_.scenes.empty()) {
        warn("no scene object; every root node is used");
        std::vector<bool> isChild(model_.nodes.size(), false);
        for (const auto& n : model_.nodes)
            for (int c : n.children)
                if (c >= 0 && size_t(c) < isChild.size()) isChild[c] = true;
        for (size_t i = 0; i < model_.nodes.size(); ++i)
            if (!isChild[i]) roots.push_back(int(i));
    } else {
        if (size_t(sceneIndex) >= model_.scenes.size()) fail("default scene index out of range");
        roots = model_.scenes[sceneIndex].nodes;
    }

    // Depth-first with an explicit stack: a very deep hierarchy cannot
    // overflow the call stack, and a node reached twice (a cycle or a shared
    // child, both invalid glTF) is an error rather than an endless loop.
    std::vector<bool> visited(model_.nodes.size(), false);
    std::set<int> joints; // of every skin: their world transforms are kept for skinMatrices
    for (size_t k = 0; k < model_.skins.size(); ++k)
        for (int j : model_.skins[k].joints) {
            if (j < 0 || size_t(j) >= model_.nodes.size())
                fail("skin " + std::to_string(k) + ": joint node " + std::to_string(j) + " out of range");
            joints.insert(j);
        }
    std::vector<std::pair<int, Mat4>> stack;
    std::vector<std::pair<int, Mat4>> placed; // nodes with a mesh, camera or light, and their world transforms
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, identity()});
    while (!stack.empty()) {
        auto [index, parent] = stack.back();
        stack.pop_back();
        if (index < 0 || size_t(index) >= model_.nodes.size())
            fail("node index " + std::to_string(index) + " out of range");
        if (visited[index]) fail("node " + std::to_string(index) + " is reached twice (cycle or shared child)");
        visited[index] = true;
        const tinygltf::Node& node = model_.nodes[index];
        if ((node.matrix.size() != 0 && node.matrix.size() != 16) ||
            (node.translation.size() != 0 && node.translation.size() != 3) ||
            (node.rotation.size() != 0 && node.rotation.size() != 4) ||
            (node.scale.size() != 0 && node.scale.size() != 3))
            fail("node " + std::to_string(index) + " has a malformed transform");
        Mat4 world = multiply(parent, localTransform(node));
        for (double v : world)
            if (!std::isfinite(v)) fail("node " + std::to_string(index) + " has a non-finite transform");
        if (node.mesh >= 0 || node.camera >= 0 || extension(node.extensions, "KHR_lights_punctual"))
            placed.push_back({index, world});
        if (joints.count(index)) jointWorld_[index] = world;
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, world});
    }

    chooseOrigin(placed);
    for (auto& [index, world] : placed) {
        const tinygltf::Node& node = model_.nodes[index];
        for (int k = 0; k < 3; ++k) world[12 + k] -= scene_.origin[k]; // translate(-origin) · world
        std::string nodeName = "node " + std::to_string(index) + (node.name.empty() ? "" : " '" + node.name + "'");
        if (node.mesh >= 0) addMesh(node.mesh, world, nodeName, node);
        if (node.camera >= 0) addCamera(node.camera, world);
        if (const tinygltf::Value* e = extension(node.extensions, "KHR_lights_punctual"))
            addLight(*e, world, nodeName);
    }
}

// A scene far from the origin compared with its size (more than 100 times
// its diagonal) is moved, camera and lights with it, so that its centre is
// the origin: the transforms are applied in double and only the moved
// coordinates are rounded to float, which then keep their full precision
// relative to the scene's size (at 1e5 units a float resolves only ~0.008:
// too coarse for ray offsets or a merge radius a thousandth of the scene).
// Radiance does not change under a translation, so neither does the image.
void Loader::chooseOrigin(const std::vector<std::pair<int, Mat4>>& placed)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    auto include = [&](const Mat4& world, double x, double y, double z) {
        for (int k = 0; k < 3; ++k) {
            double v = world[k] * x + world[4 + k] * y + world[8 + k] * z + world[12 + k];
            lo[k] = std::min(lo[k], v);
            hi[k] = std::max(hi[k], v);
        }
    };
    // Each POSITION accessor's own bounds (from its values, not its
    // min/max, which may be wrong; without morph targets), once; every
    // instance then adds the corners of that box, transformed: a bound of
    // the scene, enough to pick a centre.
    std::map<int, Bounds> localBounds;
    for (const auto& [index, world] : placed) {
        const tinygltf::Node& node = model_.nodes[index];
        int meshIndex = node.mesh;
        if (meshIndex < 0 || size_t(meshIndex) >= model_.meshes.size()) continue; // addMesh reports it
        // A skinned vertex is a weighted mean of its joint matrices' images,
        // so within the bound of the box under each of them (a vertex of no
        // weight, left in the bind pose, is not counted: the bound only
        // picks a centre).
        const std::vector<Mat4> placedBy{world};
        const std::vector<Mat4>& instances =
            node.skin >= 0 ? skinMatrices(node.skin, "node " + std::to_string(index)) : placedBy;
        if (node.skin < 0 && determinant3(world) == 0) continue; // a zero-scale instance, which addMesh skips
        const std::vector<tinygltf::Primitive>& primitives = model_.meshes[meshIndex].primitives;
        for (size_t p = 0; p < primitives.size(); ++p) {
            if (primitives[p].mode >= 0 && primitives[p].mode < TINYGLTF_MODE_TRIANGLES) continue; // skipped by addMesh
            auto pos = primitives[p].attributes.find("POSITION");
            if (pos == primitives[p].attributes.end()) continue;
            auto known = localBounds.find(pos->second);
            if (known == localBounds.end()) {
                Bounds box;
                std::string what = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p);
                decodeDracoPrimitive(meshIndex, int(p), what);
                for (const Vec3& v : readVec3(pos->second, what + " POSITION"))
                    if (isFinite(v)) box.extend(v); // addMesh rejects the others
                known = localBounds.emplace(pos->second, box).first;
            }
            const Bounds& box = known->second;
            if (box.empty()) continue; // no finite position
            for (const Mat4& m : instances)
                for (int c = 0; c < 8; ++c)
                    include(m, (c & 1 ? box.hi : box.lo).x, (c & 2 ? box.hi : box.lo).y, (c & 4 ? box.hi : box.lo).z);
        }
    }
    double centre[3], diagonal2 = 0, distance2 = 0;
    for (int k = 0; k < 3; ++k) {
        centre[k] = 0.5 * (lo[k] + hi[k]);
        diagonal2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
        distance2 += centre[k] * centre[k];
    }
    // Moved beyond 100 diagonals, where float rounding of the coordinates
    // (6e-8 of the distance) exceeds 6e-6 of the scene's size, 1/500 of the
    // default merge radius; nearer scenes keep the file's coordinates.
    if (!std::isfinite(distance2) || !std::isfinite(diagonal2) || distance2 <= 1e4 * diagonal2) return;
    for (int k = 0; k < 3; ++k) scene_.origin[k] = centre[k];
}

// Buffer view `index`, checked to lie within its buffer.
const tinygltf::BufferView& Loader::checkedView(int index, const std::string& what)
{
    if (index < 0 || size_t(index) >= model_.bufferViews.size()) fail(what + ": accessor has no valid bufferView");
    const tinygltf::BufferView& view = model_.bufferViews[size_t(index)];
    if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size())
        fail(what + ": bufferView " + std::to_string(index) + " has no valid buffer");
    const tinygltf::Buffer& buffer = model_.buffers[size_t(view.buffer)];
    // Everything in size_t, with overflow-proof comparisons.
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
        fail(what + ": bufferView " + std::to_string(index) + " extends past the end of buffer " +
             std::to_string(view.buffer) + " (" + std::to_string(view.byteOffset + view.byteLength) + " > " +
             std::to_string(buffer.data.size()) + " bytes)");
    return view;
}

// A sparse accessor (glTF 2.0 §3.6.2.3) is its bufferView's elements, or
// zeros where it has none, with the elements at `sparse.indices` (strictly
// increasing) replaced by `sparse.values` in order; morph targets use them
// to store only the vertices that move.
const unsigned char* Loader::accessorElements(const tinygltf::Accessor& a, size_t elementSize, size_t* stride,
                                              std::vector<unsigned char>& storage, const std::string& what)
{
    if (!a.sparse.isSparse) return accessorData(a, elementSize, stride, what);
    // Without a bufferView nothing in the file bounds the count: a limit
    // keeps a malformed file from asking for gigabytes of zeros.
    constexpr size_t kMaxZeroFilled = size_t(1) << 24;
    if (a.bufferView < 0 && a.count > kMaxZeroFilled)
        fail(what + ": sparse accessor of " + std::to_string(a.count) + " elements without a bufferView (at most " +
             std::to_string(kMaxZeroFilled) + ")");
    size_t baseStride = 0;
    const unsigned char* base = a.bufferView >= 0 ? accessorData(a, elementSize, &baseStride, what) : nullptr;
    storage.assign(a.count * elementSize, 0);
    for (size_t i = 0; base && i < a.count; ++i) std::memcpy(&storage[i * elementSize], base + i * baseStride, elementSize);
    const auto& sparse = a.sparse;
    if (sparse.count < 1 || size_t(sparse.count) > a.count)
        fail(what + ": sparse count " + std::to_string(sparse.count) + " is not between 1 and the accessor's count " +
             std::to_string(a.count));
    size_t indexSize = sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                       : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                       : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                                : 0;
    if (indexSize == 0) fail(what + ": sparse indices must be unsigned bytes, shorts or ints");
    // The two arrays are tightly packed, from their byteOffsets in their views.
    auto packed = [&](int viewIndex, int byteOffset, size_t bytes, const char* name) {
        const tinygltf::BufferView& view = checkedView(viewIndex, what + ": sparse " + name);
        if (byteOffset < 0 || size_t(byteOffset) > view.byteLength || bytes > view.byteLength - size_t(byteOffset))
            fail(what + ": sparse " + name + " need " + std::to_string(bytes) + " bytes from offset " +
                 std::to_string(byteOffset) + " but bufferView " + std::to_string(viewIndex) + " has " +
                 std::to_string(view.byteLength));
        return model_.buffers[size_t(view.buffer)].data.data() + view.byteOffset + size_t(byteOffset);
    };
    size_t n = size_t(sparse.count);
    const unsigned char* indices = packed(sparse.indices.bufferView, sparse.indices.byteOffset, n * indexSize, "indices");
    const unsigned char* values = packed(sparse.values.bufferView, sparse.values.byteOffset, n * elementSize, "values");
    uint32_t previous = 0;
    for (size_t k = 0; k < n; ++k) {
        uint32_t i = 0;
        std::memcpy(&i, indices + k * indexSize, indexSize); // little-endian, as glTF and every host we build for
        if (i >= a.count)
            fail(what + ": sparse index " + std::to_string(i) + " out of range (" + std::to_string(a.count) +
                 " elements)");
        if (k > 0 && i <= previous) fail(what + ": sparse indices are not strictly increasing");
        previous = i;
        std::memcpy(&storage[size_t(i) * elementSize], values + k * elementSize, elementSize);
    }
    *stride = elementSize;
    return storage.data();
}

const unsigned char* Loader::accessorData(const tinygltf::Accessor& a, size_t elementSize,
                                          size_t* stride, const std::string& what)
{
    const tinygltf::BufferView& view = checkedView(a.bufferView, what);
    const tinygltf::Buffer& buffer = model_.buffers[size_t(view.buffer)];
    *stride = view.byteStride ? view.byteStride : elementSize;
    if (*stride < elementSize) fail(what + ": byteStride smaller than the element");
    if (a.count == 0) return buffer.data.data() + view.byteOffset;
    size_t need = a.byteOffset;
    if (a.count - 1 > (SIZE_MAX - need - elementSize) / *stride) fail(what + ": accessor size overflows");
    need += (a.count - 1) * *stride + elementSize;
    if (need > view.byteLength)
        fail(what + ": accessor needs " + std::to_string(need) + " bytes but bufferView " +
             std::to_string(a.bufferView) + " has " + std::to_string(view.byteLength));
    return buffer.data.data() + view.byteOffset + a.byteOffset;
}

void Loader::decodeDracoPrimitive(int meshIndex, int p, const std::string& what)
{
    const tinygltf::Primitive& prim = model_.meshes[size_t(meshIndex)].primitives[size_t(p)];
    const tinygltf::Value* e = extension(prim.extensions, "KHR_draco_mesh_compression");
    if (!e || dracoTriangles_.count({meshIndex, p})) return; // not compressed, or decoded already
    const std::string where = what + ": KHR_draco_mesh_compression";
    if (!dracoSupported()) fail(where + ": this build has no Draco (install libdraco-dev and rebuild)");
    if (!e->IsObject() || !e->Has("bufferView") || !e->Get("bufferView").IsInt() || !e->Has("attributes") ||
        !e->Get("attributes").IsObject())
        fail(where + " needs an integer bufferView and an attributes object");
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) fail(where + ": only TRIANGLES primitives can be compressed");
    // The semantics this loader reads, each with its accessor and Draco attribute id.
    std::map<int, int> components;
    std::vector<std::pair<int, int>> accessorOfId;
    for (const char* semantic : {"POSITION", "NORMAL", "TANGENT", "TEXCOORD_0", "TEXCOORD_1"}) {
        if (!e->Get("attributes").Has(semantic)) continue;
        const tinygltf::Value& id = e->Get("attributes").Get(semantic);
        auto accessor = prim.attributes.find(semantic);
        if (!id.IsInt() || id.GetNumberAsInt() < 0 || accessor == prim.attributes.end() || accessor->second < 0 ||
            size_t(accessor->second) >= model_.accessors.size())
            fail(where + ": attribute " + semantic + " needs a Draco id and a valid accessor of the primitive");
        int type = model_.accessors[size_t(accessor->second)].type;
        if (type < TINYGLTF_TYPE_VEC2 || type > TINYGLTF_TYPE_VEC4) fail(where + ": " + semantic + " is not a VEC2, VEC3 or VEC4");
        components[id.GetNumberAsInt()] = type; // tinygltf's VECn is n
        accessorOfId.emplace_back(id.GetNumberAsInt(), accessor->second);
    }
    int viewIndex = e->Get("bufferView").GetNumberAsInt();
    if (viewIndex < 0 || size_t(viewIndex) >= model_.bufferViews.size()) fail(where + ": bufferView out of range");
    const tinygltf::BufferView& view = model_.bufferViews[size_t(viewIndex)];
    if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size()) fail(where + ": its bufferView has no valid buffer");
    const std::vector<unsigned char>& buffer = model_.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        fail(where + ": bufferView " + std::to_string(viewIndex) + " extends past the end of its buffer");
    DracoMesh mesh;
    try {
        mesh = decodeDraco(buffer.data() + view.byteOffset, view.byteLength, components);
    } catch (const std::exception& ex) {
        fail(where + ": " + ex.what());
    }
    for (uint32_t i : mesh.indices)
        if (i >= mesh.points) fail(where + ": the decoded mesh has an index out of range");
    // Copied, not moved: two semantics may name one Draco attribute.
    for (const auto& [id, accessor] : accessorOfId) dracoFloats_[accessor] = mesh.attributes[id];
    dracoTriangles_[{meshIndex, p}] = std::move(mesh.indices);
}

// `type`: the accessor's tinygltf type where it is not VECn (MAT4).
std::vector<float> Loader::readFloats(int accessorIndex, int components, const std::string& what, int type)
{
    if (accessorIndex < 0 || size_t(accessorIndex) >= model_.accessors.size())
        fail(what + ": accessor index " + std::to_string(accessorIndex) + " out of range");
    const tinygltf::Accessor& a = model_.accessors[accessorIndex];
    const std::string name = type == TINYGLTF_TYPE_MAT4 ? "MAT4" : "VEC" + std::to_string(components);
    if (a.type != (type ? type : components)) fail(what + ": expected a " + name); // tinygltf's VECn is n
    auto decoded = dracoFloats_.find(accessorIndex);
    if (decoded != dracoFloats_.end()) return decoded->second;
    // Floats, or (KHR_mesh_quantization) 8- and 16-bit integers, as values
    // or normalized: unsigned c / (2^n − 1), signed max(c / (2^(n−1) − 1), −1).
    size_t size;
    switch (a.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: size = 4; break;
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: size = 1; break;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: size = 2; break;
    default: fail(what + ": " + name + " components must be floats, or 8- or 16-bit integers (KHR_mesh_quantization)");
    }
    size_t stride;
    std::vector<unsigned char> storage;
    const unsigned char* data = accessorElements(a, size_t(components) * size, &stride, storage, what);
    auto component = [&](const unsigned char* p) -> float {
        switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float f;
            std::memcpy(&f, p, 4);
            return f;
        }
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            float c = float(int8_t(p[0]));
            return a.normalized ? std::max(c / 127.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return a.normalized ? p[0] / 255.0f : float(p[0]);
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t c;
            std::memcpy(&c, p, 2);
            return a.normalized ? std::max(float(c) / 32767.0f, -1.0f) : float(c);
        }
        default: {
            uint16_t c;
            std::memcpy(&c, p, 2);
            return a.normalized ? float(c) / 65535.0f : float(c);
        }
        }
    };
    std::vector<float> out(a.count * size_t(components));
    for (size_t i = 0; i < a.count; ++i)
        for (int c = 0; c < components; ++c) out[i * components + c] = component(data + i * stride + c * size);
    return out;
}

std::vector<Vec3> Loader::readVec3(int accessorIndex, const std::string& what)
{
    std::vector<float> f = readFloats(accessorIndex, 3, what);
    std::vector<Vec3> out(f.size() / 3);
    for (size_t i = 0; i < out.size(); ++i) out[i] = Vec3(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
    return out;
}

std::vector<float> Loader::readTexCoords(int accessorIndex, const std::string& what)
{
    std::vector<float> out = readFloats(accessorIndex, 2, what);
    for (float v : out)
        if (!std::isfinite(v)) fail(what + " contains NaN or Inf");
    return out;
}

std::vector<uint32_t> Loader::readIndices(int accessorIndex)
{
    const std::string what = "indices";
    if (size_t(accessorIndex) >= model_.accessors.size())
        fail("indices: accessor index " + std::to_string(accessorIndex) + " out of range");
    const tinygltf::Accessor& a = model_.accessors[accessorIndex];
    size_t size = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                  : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                  : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                              : 0;
    if (a.type != TINYGLTF_TYPE_SCALAR || size == 0) fail("indices: expected unsigned scalars");
    size_t stride;
    std::vector<unsigned char> storage;
    const unsigned char* data = accessorElements(a, size, &stride, storage, what);
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        const unsigned char* p = data + i * stride;
        if (size == 1) out[i] = p[0];
        else if (size == 2) { uint16_t v; std::memcpy(&v, p, 2); out[i] = v; }
        else std::memcpy(&out[i], p, 4);
    }
    return out;
}

int glTFDefaultMaterial(Scene& scene)
{
    // glTF's default material: base colour 1, metallic 1, roughness 1.
    Material m{};
    for (int c = 0; c < 3; ++c) { m.baseColor[c] = 1; m.specularColor[c] = 1; }
    m.metallic = 1;
    m.roughness = 1;
    m.specular = 1;
    m.ior = 1.5f;
    m.thinWalled = 1;
    m.baseColorAlpha = 1;
    m.lobes = LOBE_GGX_REFLECTION;
    scene.materials.push_back(m);
    return int(scene.materials.size()) - 1;
}

// The triangles of a TRIANGLE_STRIP or TRIANGLE_FAN as a triangle list, with
// glTF's winding (spec §3.7.2.1): strip triangle i is (v_i, v_{i+1+i%2},
// v_{i+2-i%2}), fan triangle i is (v_{i+1}, v_{i+2}, v_0). Triangles with a
// repeated vertex (a strip's restarts) are dropped.
static std::vector<uint32_t> triangulate(int mode, const std::vector<uint32_t>& v)
{
    std::vector<uint32_t> out;
    for (size_t i = 0; i + 2 < v.size(); ++i) {
        uint32_t t[3];
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            t[0] = v[i];
            t[1] = v[i + 1 + i % 2];
            t[2] = v[i + 2 - i % 2];
        } else {
            t[0] = v[i + 1];
            t[1] = v[i + 2];
            t[2] = v[0];
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        out.insert(out.end(), t, t + 3);
    }
    return out;
}

// Σ_t w_t · (target t's displacements of `semantic`): a primitive's morph
// targets at the given weights (glTF 2.0 §3.7.2.2), or nothing where no
// target of non-zero weight moves that attribute.
std::vector<Vec3> Loader::morphDisplacement(const tinygltf::Primitive& prim, const std::vector<double>& weights,
                                            const char* semantic, size_t count, const std::string& what)
{
    std::vector<Vec3> sum;
    for (size_t t = 0; t < prim.targets.size() && t < weights.size(); ++t) {
        auto it = prim.targets[t].find(semantic);
        if (weights[t] == 0 || it == prim.targets[t].end()) continue;
        std::string name = what + " morph target " + std::to_string(t) + " " + semantic;
        std::vector<Vec3> d = readVec3(it->second, name);
        if (d.size() != count) fail(name + ": its count differs from POSITION's");
        sum.resize(count, Vec3(0, 0, 0));
        for (size_t i = 0; i < count; ++i) sum[i] = sum[i] + d[i] * float(weights[t]);
    }
    return sum;
}

// Skin `skin`'s joint matrices (glTF 2.0 §3.7.3): each joint's world
// transform (in the file's coordinates, before the origin's move) times its
// inverse bind matrix; made once per skin, for chooseOrigin and every
// instance.
const std::vector<Mat4>& Loader::skinMatrices(int skin, const std::string& nodeName)
{
    auto made = skinMatrices_.find(skin);
    if (made != skinMatrices_.end()) return made->second;
    if (skin < 0 || size_t(skin) >= model_.skins.size())
        fail(nodeName + ": skin index " + std::to_string(skin) + " out of range");
    const tinygltf::Skin& s = model_.skins[size_t(skin)];
    std::string what = nodeName + ": skin " + std::to_string(skin);
    if (s.joints.empty()) fail(what + " has no joints");
    std::vector<float> inverseBind;
    if (s.inverseBindMatrices >= 0) {
        inverseBind = readFloats(s.inverseBindMatrices, 16, what + " inverseBindMatrices", TINYGLTF_TYPE_MAT4);
        if (inverseBind.size() != 16 * s.joints.size()) fail(what + ": inverseBindMatrices and joints counts differ");
    }
    std::vector<Mat4> out;
    for (size_t j = 0; j < s.joints.size(); ++j) {
        auto world = jointWorld_.find(s.joints[j]);
        if (world == jointWorld_.end())
            fail(what + ": joint node " + std::to_string(s.joints[j]) + " is not in the rendered scene");
        Mat4 inverse = identity();
        if (!inverseBind.empty()) std::copy_n(&inverseBind[16 * j], 16, inverse.begin());
        out.push_back(multiply(world->second, inverse));
        for (double v : out.back())
            if (!std::isfinite(float(v))) fail(what + ": joint " + std::to_string(j) + " has a non-finite matrix");
    }
    return skinMatrices_[skin] = std::move(out);
}

// Each vertex's skinning matrix: the joint matrices weighted by its JOINTS_n
// and WEIGHTS_n (every set the primitive has), the weights normalized to sum
// 1. A vertex of no weight stays where the bind pose has it.
std::vector<Mat4> Loader::vertexSkinMatrices(const tinygltf::Primitive& prim, const std::vector<Mat4>& joints,
                                             size_t count, const std::string& what)
{
    std::vector<Mat4> out(count, Mat4{});
    std::vector<double> total(count, 0.0);
    int sets = 0;
    for (;; ++sets) {
        std::string j = "JOINTS_" + std::to_string(sets), w = "WEIGHTS_" + std::to_string(sets);
        auto jointsAttribute = prim.attributes.find(j), weightsAttribute = prim.attributes.find(w);
        if (jointsAttribute == prim.attributes.end() && weightsAttribute == prim.attributes.end()) break;
        if (jointsAttribute == prim.attributes.end() || weightsAttribute == prim.attributes.end())
            fail(what + ": " + j + " and " + w + " come in pairs");
        std::vector<float> index = readFloats(jointsAttribute->second, 4, what + " " + j);
        std::vector<float> weight = readFloats(weightsAttribute->second, 4, what + " " + w);
        if (index.size() != 4 * count || weight.size() != 4 * count)
            fail(what + ": " + j + " or " + w + " and POSITION counts differ");
        for (size_t i = 0; i < 4 * count; ++i) {
            if (!(weight[i] >= 0.0f) || !std::isfinite(weight[i])) fail(what + ": " + w + " has a negative or non-finite weight");
            if (weight[i] == 0.0f) continue;
            if (!(index[i] >= 0.0f && index[i] < float(joints.size())) || index[i] != std::floor(index[i]))
                fail(what + ": " + j + " names joint " + std::to_string(index[i]) + " of " + std::to_string(joints.size()));
            const Mat4& m = joints[size_t(index[i])];
            for (int k = 0; k < 16; ++k) out[i / 4][size_t(k)] += double(weight[i]) * m[size_t(k)];
            total[i / 4] += weight[i];
        }
    }
    if (sets == 0) fail(what + ": its node has a skin but it has no JOINTS_0 and WEIGHTS_0");
    Mat4 bindPose = identity();
    for (int k = 0; k < 3; ++k) bindPose[12 + size_t(k)] = -scene_.origin[k];
    for (size_t i = 0; i < count; ++i) {
        if (total[i] > 0.0)
            for (double& v : out[i]) v /= total[i];
        else
            out[i] = bindPose;
    }
    return out;
}

void Loader::addMesh(int meshIndex, const Mat4& nodeWorld, const std::string& nodeName, const tinygltf::Node& node)
{
    if (size_t(meshIndex) >= model_.meshes.size())
        fail(nodeName + ": mesh index " + std::to_string(meshIndex) + " out of range");
    const tinygltf::Mesh& mesh = model_.meshes[meshIndex];
    // The pose a viewer shows without animation: the node's morph weights,
    // else the mesh's defaults, else none.
    const std::vector<double>& weights = node.weights.empty() ? mesh.weights : node.weights;
    for (double w : weights)
        if (!std::isfinite(float(w))) fail(nodeName + ": morph target weight " + std::to_string(w) + " is not a finite float");
    // A skinned mesh ignores its node's transform (glTF 2.0 §3.7.3.3): its
    // joints place each vertex, which is then in world space already.
    std::vector<Mat4> joints = node.skin >= 0 ? skinMatrices(node.skin, nodeName) : std::vector<Mat4>();
    for (Mat4& m : joints) // translate(−origin) · m, as for the node's own transform
        for (int k = 0; k < 3; ++k) m[12 + size_t(k)] -= scene_.origin[k];
    if (joints.empty() && determinant3(nodeWorld) == 0.0) {
        warn(nodeName + ": zero-scale transform; its mesh is skipped");
        return;
    }
    static const char* modeNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP", "TRIANGLES",
                                      "TRIANGLE_STRIP", "TRIANGLE_FAN"};
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = mesh.primitives[p];
        std::string what = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p);
        int mode = prim.mode == -1 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
        if (mode < 0 || mode > TINYGLTF_MODE_TRIANGLE_FAN) fail(what + ": unknown primitive mode " + std::to_string(mode));
        if (mode < TINYGLTF_MODE_TRIANGLES) { // points and lines have no area to render
            warnOnce(std::string(modeNames[mode]) + " primitives are skipped: only triangles are rendered");
            skippedModes_.insert(modeNames[mode]);
            continue;
        }
        if (!prim.targets.empty() && !weights.empty() && weights.size() != prim.targets.size())
            warnOnce(what + " has " + std::to_string(prim.targets.size()) + " morph targets and " +
                     std::to_string(weights.size()) + " weights; a missing weight is 0");
        decodeDracoPrimitive(meshIndex, int(p), what);
        bool draco = dracoTriangles_.count({meshIndex, int(p)}) != 0;
        // Draco may reorder the vertices, which uncompressed targets and joints then no longer match.
        std::vector<double> morph = draco ? std::vector<double>() : weights;
        if (draco && !prim.targets.empty())
            warnOnce(what + ": morph targets of a Draco-compressed primitive are not applied");
        bool skinned = !joints.empty() && !draco;
        if (draco && !joints.empty())
            warnOnce(what + ": the skin of a Draco-compressed primitive is not applied; its node places it");
        const Mat4 world = skinned ? identity() : nodeWorld;
        // A mirroring transform turns the winding clockwise (glTF 2.0 meshes);
        // taking the corners in reverse order keeps counter-clockwise the front,
        // as the kernels' geometric normals assume. A skin's is its first joint's.
        double det = skinned ? determinant3(joints[0]) : determinant3(world);
        static const int cornerOrder[2][3] = {{0, 1, 2}, {0, 2, 1}};
        const int* corner = cornerOrder[det < 0];
        auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end()) fail(what + ": no POSITION attribute");
        std::vector<Vec3> positions = readVec3(pos->second, what + " POSITION");
        std::vector<Vec3> moved = morphDisplacement(prim, morph, "POSITION", positions.size(), what);
        for (size_t i = 0; i < moved.size(); ++i) positions[i] = positions[i] + moved[i];
        std::vector<Vec3> normals;
        auto nrm = prim.attributes.find("NORMAL");
        if (nrm != prim.attributes.end()) {
            normals = readVec3(nrm->second, what + " NORMAL");
            if (normals.size() != positions.size()) fail(what + ": NORMAL and POSITION counts differ");
            moved = morphDisplacement(prim, morph, "NORMAL", normals.size(), what);
            for (size_t i = 0; i < moved.size(); ++i) normals[i] = normals[i] + moved[i]; // normalized below
        }
        std::vector<Mat4> skin = skinned ? vertexSkinMatrices(prim, joints, positions.size(), what) : std::vector<Mat4>();
        for (size_t i = 0; i < skin.size(); ++i) {
            positions[i] = transformPoint(skin[i], positions[i]);
            if (!normals.empty()) normals[i] = transformNormal(skin[i], normals[i]);
        }
        for (const Vec3& v : positions)
            if (!isFinite(v)) fail(what + ": POSITION contains NaN or Inf");
        std::vector<float> uvSets[2]; // TEXCOORD_0 and _1, for textures
        for (int set = 0; set < 2; ++set) {
            std::string name = "TEXCOORD_" + std::to_string(set);
            auto uv = prim.attributes.find(name);
            if (uv == prim.attributes.end()) continue;
            uvSets[set] = readTexCoords(uv->second, what + " " + name);
            if (uvSets[set].size() != 2 * positions.size()) fail(what + ": " + name + " and POSITION counts differ");
        }
        // COLOR_0 (VEC3 or VEC4 of floats, or of normalized unsigned bytes or
        // shorts): linear RGB(A) that multiplies the base colour (and its alpha).
        std::vector<std::array<float, 4>> colors;
        auto col = prim.attributes.find("COLOR_0");
        if (col != prim.attributes.end() && draco) {
            warnOnce(what + ": COLOR_0 of a Draco-compressed primitive is not read");
        } else if (col != prim.attributes.end()) {
            if (col->second < 0 || size_t(col->second) >= model_.accessors.size())
                fail(what + ": COLOR_0 accessor index " + std::to_string(col->second) + " out of range");
            int n = model_.accessors[size_t(col->second)].type; // tinygltf's VECn is n
            if (n != 3 && n != 4) fail(what + ": COLOR_0 must be a VEC3 or a VEC4");
            std::vector<float> f = readFloats(col->second, n, what + " COLOR_0");
            if (f.size() != size_t(n) * positions.size()) fail(what + ": COLOR_0 and POSITION counts differ");
            for (size_t i = 0; i < positions.size(); ++i) {
                std::array<float, 4> c{1, 1, 1, 1};
                for (int k = 0; k < n; ++k) {
                    c[size_t(k)] = f[size_t(n) * i + size_t(k)];
                    if (!(c[size_t(k)] >= 0.0f) || !std::isfinite(c[size_t(k)]))
                        fail(what + ": COLOR_0 has a negative or non-finite value");
                }
                colors.push_back(c);
            }
        }
        std::vector<uint32_t> indices;
        if (draco) {
            if (!dracoFloats_.count(pos->second)) fail(what + ": POSITION is not among the Draco-compressed attributes");
            indices = dracoTriangles_[{meshIndex, int(p)}];
        } else if (prim.indices >= 0) {
            indices = readIndices(prim.indices);
        } else {
            indices.resize(positions.size());
            for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
        }
        // Every primitive's indices, Draco's too: decodeDracoPrimitive checks
        // them against the decoded points, this against the positions read.
        for (uint32_t i : indices)
            if (i >= positions.size())
                fail(what + ": index " + std::to_string(i) + " out of range (" + std::to_string(positions.size()) +
                     " vertices)");
        if (mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
            fail(what + ": index count is not a multiple of 3");
        if (mode != TINYGLTF_MODE_TRIANGLES) indices = triangulate(mode, indices);

        int material = prim.material;
        if (material >= int(scene_.materials.size()) || (material >= 0 && size_t(material) >= model_.materials.size()))
            fail(what + ": material index " + std::to_string(material) + " out of range");
        if (material < 0) {
            if (defaultMaterial_ < 0) defaultMaterial_ = glTFDefaultMaterial(scene_);
            material = defaultMaterial_;
        }

        const Material& used = scene_.materials[size_t(material)];
        for (int texture : {used.baseColorTexture, used.metallicRoughnessTexture, used.normalTexture,
                            used.emissiveTexture, used.transmissionTexture}) {
            if (texture <= 0) continue;
            int set = scene_.textures[size_t(texture) - 1].texCoord;
            if (uvSets[set].empty())
                warnOnce(what + ": a textured material without TEXCOORD_" + std::to_string(set) +
                         "; the texel at (0, 0) is used");
        }
        // Tangents (x, y, z, handedness) per corner for a normal map or anisotropy: TANGENT, else made from
        // the UVs (of the normal texture, else the anisotropy texture, else TEXCOORD_0).
        std::vector<float> tangents;
        if (used.normalTexture > 0 || used.anisotropy > 0) {
            auto tan = prim.attributes.find("TANGENT");
            if (tan != prim.attributes.end()) { // per vertex, given out per corner
                std::vector<float> perVertex = readFloats(tan->second, 4, what + " TANGENT");
                if (perVertex.size() != 4 * positions.size()) fail(what + ": TANGENT and POSITION counts differ");
                moved = morphDisplacement(prim, morph, "TANGENT", positions.size(), what); // xyz; w stays
                for (size_t i = 0; i < moved.size(); ++i)
                    for (int c = 0; c < 3; ++c) perVertex[4 * i + size_t(c)] += moved[i][c];
                for (size_t i = 0; i < skin.size(); ++i) {
                    Vec3 t = transformVector(skin[i], Vec3(perVertex[4 * i], perVertex[4 * i + 1], perVertex[4 * i + 2]));
                    for (int c = 0; c < 3; ++c) perVertex[4 * i + size_t(c)] = t[c];
                }
                tangents.resize(4 * indices.size());
                for (size_t c = 0; c < indices.size(); ++c)
                    std::copy_n(&perVertex[4 * size_t(indices[c])], 4, &tangents[4 * c]);
            } else {
                int frameTexture = used.normalTexture > 0 ? used.normalTexture : used.anisotropyTexture;
                const std::vector<float>& uvs = uvSets[frameTexture > 0 ? scene_.textures[size_t(frameTexture) - 1].texCoord : 0];
                if (uvs.empty() && used.anisotropy > 0)
                    warnOnce(what + ": an anisotropic material without TANGENT or texture coordinates; its direction "
                                    "follows an arbitrary tangent");
                tangents = mikkTSpaceTangents(positions, normals, uvs, indices);
            }
        }

        // Normals exist for every triangle once any primitive has them.
        bool hadNormals = !scene_.normals.empty();
        if (!normals.empty() && !hadNormals && !scene_.vertices.empty()) {
            for (size_t t = 0; t < scene_.vertices.size(); t += 3) {
                Vec3 n = normalize(cross(scene_.vertices[t + 1] - scene_.vertices[t], scene_.vertices[t + 2] - scene_.vertices[t]));
                for (int k = 0; k < 3; ++k) scene_.normals.push_back(n);
            }
        }
        bool wantNormals = !normals.empty() || hadNormals;
        // Colours likewise: white for the triangles of primitives without COLOR_0.
        bool hadColors = !scene_.colors.empty();
        if (!colors.empty() && !hadColors) scene_.colors.assign(scene_.vertices.size(), {1, 1, 1, 1});
        bool wantColors = !colors.empty() || hadColors;
        // Tangents exist for every triangle (zero where nothing reads them) once any material has a normal map
        // or anisotropy.
        bool wantTangents = tangentFrames_;
        float handedness = det < 0 ? -1.0f : 1.0f; // a mirroring transform turns the bitangent around
        for (size_t i = 0; i < indices.size(); i += 3) {
            Vec3 v[3];
            for (int k = 0; k < 3; ++k) v[k] = transformPoint(world, positions[indices[i + corner[k]]]);
            for (int k = 0; k < 3; ++k) scene_.vertices.push_back(v[k]);
            for (int k = 0; wantColors && k < 3; ++k)
                scene_.colors.push_back(colors.empty() ? std::array<float, 4>{1, 1, 1, 1} : colors[indices[i + corner[k]]]);
            scene_.triangleMaterial.push_back(material);
            for (int set = 0; set < 2; ++set) // (0, 0) where missing; dropped unless a texture reads them
                for (int k = 0; k < 3; ++k)
                    for (int c = 0; c < 2; ++c)
                        (set ? scene_.uvs1 : scene_.uvs)
                            .push_back(uvSets[set].empty() ? 0.0f
                                                           : uvSets[set][2 * size_t(indices[i + corner[k]]) + size_t(c)]);
            for (int k = 0; wantTangents && k < 3; ++k) {
                std::array<float, 4> t{0, 0, 0, 0};
                if (!tangents.empty()) {
                    const float* in = &tangents[4 * (i + size_t(corner[k]))];
                    Vec3 d = transformVector(world, Vec3(in[0], in[1], in[2]));
                    float len = length(d);
                    if (len > 0.0f && std::isfinite(len)) t = {d.x / len, d.y / len, d.z / len, in[3] < 0 ? -handedness : handedness};
                }
                scene_.tangents.push_back(t);
            }
            if (!wantNormals) continue;
            Vec3 geometric = cross(v[1] - v[0], v[2] - v[0]);
            for (int k = 0; k < 3; ++k) {
                Vec3 n = normals.empty() ? geometric : transformNormal(world, normals[indices[i + corner[k]]]);
                float len = length(n);
                scene_.normals.push_back(len > 0 && std::isfinite(len) ? n * (1.0f / len) : Vec3(0, 0, 0));
            }
        }
    }
}

void Loader::addCamera(int cameraIndex, const Mat4& world)
{
    if (size_t(cameraIndex) >= model_.cameras.size())
        fail("camera index " + std::to_string(cameraIndex) + " out of range");
    const tinygltf::Camera& cam = model_.cameras[cameraIndex];
    std::string what = "camera " + std::to_string(cameraIndex);
    CameraView view;
    if (cam.type == "perspective") {
        double yfov = cam.perspective.yfov;
        if (!(yfov > 0 && yfov < M_PI)) fail(what + ": yfov must be in (0, pi)");
        view.yfov = float(yfov);
        view.aspectRatio = cam.perspective.aspectRatio > 0 ? float(cam.perspective.aspectRatio) : 0.0f;
    } else if (cam.type == "orthographic") {
        // xmag and ymag: the view's half-width and half-height. The image
        // keeps ymag and its own aspect, as a perspective camera keeps yfov.
        double xmag = cam.orthographic.xmag, ymag = cam.orthographic.ymag;
        if (!(xmag != 0 && ymag != 0 && std::isfinite(xmag) && std::isfinite(ymag)))
            fail(what + ": orthographic xmag and ymag must be finite and not zero");
        view.orthographic = true;
        view.ymag = float(std::abs(ymag)); // in the node's units; a scale on a camera node is left out, as for yfov
        view.aspectRatio = float(std::abs(xmag / ymag));
    } else {
        fail(what + ": unknown type '" + cam.type + "' (perspective or orthographic)");
    }
    view.position = transformPoint(world, {0, 0, 0});
    view.forward = normalize(transformVector(world, {0, 0, -1}));
    view.up = normalize(transformVector(world, {0, 1, 0}));
    if (!isFinite(view.forward) || !isFinite(view.up) || !std::isfinite(view.ymag) || !(view.ymag > 0))
        fail(what + ": degenerate node transform");
    scene_.cameras.push_back(view);
    if (!scene_.cameraFromFile) scene_.camera = view; // the first camera is the default
    scene_.cameraFromFile = true;
}

void Loader::addLight(const tinygltf::Value& ext, const Mat4& world, const std::string& nodeName)
{
    if (!ext.Has("light") || !ext.Get("light").IsInt()) fail(nodeName + ": KHR_lights_punctual without a light index");
    int index = ext.Get("light").GetNumberAsInt();
    if (index < 0 || size_t(index) >= model_.lights.size())
        fail(nodeName + ": light index " + std::to_string(index) + " out of range");
    const tinygltf::Light& l = model_.lights[index];
    Light out{};
    if (l.type == "point") out.type = LIGHT_POINT;
    else if (l.type == "spot") out.type = LIGHT_SPOT;
    else if (l.type == "directional") out.type = LIGHT_DIRECTIONAL;
    else fail("light " + std::to_string(index) + ": unknown type '" + l.type + "'");
    if (l.range > 0) warnOnce("light range is ignored (lights follow the inverse-square law)");
    Vec3 p = transformPoint(world, {0, 0, 0}), d = normalize(transformVector(world, {0, 0, -1}));
    if (!isFinite(d)) fail(nodeName + ": degenerate light transform");
    for (int c = 0; c < 3; ++c) {
        double color = l.color.size() == 3 ? l.color[c] : 1.0;
        out.emission[c] = float(std::max(0.0, color * l.intensity));
        out.position[c] = p[c];
        out.direction[c] = d[c];
    }
    double outer = l.spot.outerConeAngle, inner = l.spot.innerConeAngle;
    if (out.type == LIGHT_SPOT && !(0 <= inner && inner < outer && outer <= M_PI / 2))
        fail("light " + std::to_string(index) + ": spot cone angles must satisfy 0 <= inner < outer <= pi/2");
    out.cosInnerCone = float(std::cos(inner));
    out.cosOuterCone = float(std::cos(outer));
    scene_.lights.push_back(out);
}

// extras.environment = {"uri": map beside the file, "strength": s, "rotation": degrees}
// (render's --environment options), the map read here so that a bad one is
// reported with the scene.
void Loader::loadEnvironment(const tinygltf::Value& e)
{
    if (!e.IsObject() || !e.Has("uri") || !e.Get("uri").IsString())
        fail("scene extras.environment must be an object with a \"uri\" string");
    auto number = [&](const char* key, double fallback) {
        if (!e.Has(key)) return fallback;
        const tinygltf::Value& v = e.Get(key);
        if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
            fail(std::string("scene extras.environment.") + key + " must be a finite number");
        return v.GetNumberAsDouble();
    };
    double strength = number("strength", 1.0), rotation = number("rotation", 0.0);
    if (strength < 0) fail("scene extras.environment.strength must be >= 0");
    std::string uri = e.Get("uri").Get<std::string>();
    std::filesystem::path file = std::filesystem::path(path_).parent_path() / uri;
    std::string ext = file.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".exr" && ext != ".hdr" && ext != ".pfm")
        fail("scene extras.environment: " + uri + " must be linear radiance in .exr, .hdr or .pfm");
    scene_.environment.path = file.string();
    try {
        scene_.environment.image = readImage(file.string());
    } catch (const Error& e) {
        fail(std::string("scene extras.environment: ") + e.what());
    }
    scene_.environment.strength = float(strength);
    scene_.environment.rotation = float(rotation);
}

void Loader::loadBackground()
{
    if (model_.scenes.empty()) return;
    int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    const tinygltf::Value& extras = model_.scenes[sceneIndex].extras;
    if (!extras.IsObject()) return;
    if (extras.Has("environment")) loadEnvironment(extras.Get("environment"));
    if (!extras.Has("background")) return;
    const tinygltf::Value& bg = extras.Get("background");
    if (!bg.IsArray() || bg.ArrayLen() != 3) fail("scene extras.background must be [r, g, b]");
    for (int c = 0; c < 3; ++c) {
        if (!bg.Get(c).IsNumber()) fail("scene extras.background must hold three numbers");
        double v = bg.Get(c).GetNumberAsDouble();
        if (!(v >= 0) || !std::isfinite(v)) fail("scene extras.background must be finite and >= 0");
        scene_.background[c] = float(v);
    }
}

} // namespace

Scene loadGltf(const std::string& path)
{
    Scene scene;
    scene.path = path;
    Loader(path, scene).load();
    if (!scene.cameraFromFile) {
        scene.warnings.push_back(path + ": no camera; using a default camera framing the scene");
        scene.camera = framingCamera(scene.bounds(), 0.0f);
    }
    return scene;
}

} // namespace wv
