// KHR_draco_mesh_compression: a primitive's compressed bufferView decoded by
// Google's Draco library (Debian's libdraco-dev). Built without it
// (WAVEVCM_HAVE_DRACO undefined), dracoSupported() is false and decoding
// throws, naming the package.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace wv {

struct DracoMesh {
    std::vector<uint32_t> indices;                  // three per triangle, counter-clockwise as encoded
    std::map<int, std::vector<float>> attributes;   // Draco attribute id → components × points floats
    size_t points = 0;
};

bool dracoSupported();

// Decodes `size` bytes; `components` names, per Draco attribute id that the
// glTF primitive maps, how many float components its accessor has (2, 3 or
// 4). Integer attributes come out as floats, normalized ones in [0, 1] or
// [−1, 1]. Throws std::runtime_error saying what is wrong.
DracoMesh decodeDraco(const unsigned char* data, size_t size, const std::map<int, int>& components);

} // namespace wv
