#include "TestQuad.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace wv::test {

std::string writeQuad(const std::filesystem::path& dir, const std::string& name, const QuadFile& quad)
{
    using json = nlohmann::json;
    const float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    // Positions, texture coordinates, indices, then the tangents and the second coordinates if any.
    size_t tangentsAt = 92, uv1At = tangentsAt + 4 * quad.tangents.size();
    std::vector<unsigned char> bin(uv1At + 4 * quad.uv1.size());
    std::memcpy(bin.data(), pos, 48);
    std::memcpy(bin.data() + 48, quad.uv.data(), 32);
    std::memcpy(bin.data() + 80, idx, 12);
    if (!quad.tangents.empty()) std::memcpy(bin.data() + tangentsAt, quad.tangents.data(), 4 * quad.tangents.size());
    if (!quad.uv1.empty()) std::memcpy(bin.data() + uv1At, quad.uv1.data(), 4 * quad.uv1.size());
    std::ofstream(dir / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));

    json attributes = {{"POSITION", 0}};
    if (quad.uvs) attributes["TEXCOORD_0"] = 1;
    json views = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                  {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
                  {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}};
    json accessors = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                       {"min", {-1, -1, 0}}, {"max", {1, 1, 0}}},
                      {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                      {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}};
    if (!quad.tangents.empty()) {
        views.push_back({{"buffer", 0}, {"byteOffset", tangentsAt}, {"byteLength", 4 * quad.tangents.size()}});
        accessors.push_back({{"bufferView", views.size() - 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC4"}});
        attributes["TANGENT"] = accessors.size() - 1;
    }
    if (!quad.uv1.empty()) {
        views.push_back({{"buffer", 0}, {"byteOffset", uv1At}, {"byteLength", 4 * quad.uv1.size()}});
        accessors.push_back({{"bufferView", views.size() - 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
        attributes["TEXCOORD_1"] = accessors.size() - 1;
    }
    json textures = json::array(), images = json::array();
    for (size_t i = 0; i < quad.images.size(); ++i) {
        textures.push_back({{"source", i}, {"sampler", 0}});
        images.push_back({{"uri", quad.images[i]}});
    }
    json g = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0, 1}}}}},
        {"nodes", {{{"mesh", 0}}, {{"camera", 0}, {"translation", {0, 0, 3}}}}},
        {"cameras", {{{"type", "perspective"},
                      {"perspective", {{"yfov", 2 * std::atan(1.0 / 3)}, {"aspectRatio", 1}, {"znear", 0.01}}}}}},
        {"meshes", {{{"primitives", {{{"attributes", attributes}, {"indices", 2}, {"material", 0}}}}}}},
        {"materials", {quad.material}},
        {"buffers", {{{"byteLength", bin.size()}, {"uri", name + ".bin"}}}},
        {"bufferViews", views},
        {"accessors", accessors}};
    if (!quad.extensionsUsed.empty()) g["extensionsUsed"] = quad.extensionsUsed;
    if (!quad.images.empty()) {
        g["textures"] = textures;
        g["images"] = images;
        g["samplers"] = {quad.sampler};
    }
    std::filesystem::path path = dir / (name + ".gltf");
    std::ofstream(path) << g.dump();
    return path.string();
}

} // namespace wv::test
