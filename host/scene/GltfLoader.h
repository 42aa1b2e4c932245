// glTF 2.0 (.gltf, .glb) to Scene, through tinygltf. See docs/scenes.md for
// what is supported and how materials and lights map.
#pragma once

#include "Scene.h"

#include <string>

namespace wv {

// Throws wv::Error naming the file and the problem for anything malformed or
// unsupported that would change the picture; milder problems become
// Scene::warnings.
Scene loadGltf(const std::string& path);

} // namespace wv
