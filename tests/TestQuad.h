// A textured quad written as a glTF file, for the texture and normal-map
// tests: the square [-1, 1]² in z = 0 facing +z, seen by a camera at z = 3
// whose image is exactly the quad.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace wv::test {

struct QuadFile {
    nlohmann::json material = nlohmann::json::object(); // the glTF material, whole
    // Texture i is image uri images[i] with sampler 0.
    std::vector<std::string> images;
    nlohmann::json sampler = nlohmann::json::object();
    // TEXCOORD_0 of the corners (−1, −1), (1, −1), (1, 1), (−1, 1): by
    // default the texture's (0, 0) at the top left (−1, 1), u along +x.
    std::array<float, 8> uv{0, 1, 1, 1, 1, 0, 0, 0};
    bool uvs = true;              // false: no TEXCOORD_0
    std::vector<float> uv1;       // TEXCOORD_1 of the corners, or none when empty
    std::vector<float> tangents;  // TANGENT (x, y, z, w per corner), or none when empty
    std::vector<std::string> extensionsUsed{"KHR_materials_specular"};
};

// Writes dir/name.gltf (and name.bin) and returns its path.
std::string writeQuad(const std::filesystem::path& dir, const std::string& name, const QuadFile& quad);

} // namespace wv::test
