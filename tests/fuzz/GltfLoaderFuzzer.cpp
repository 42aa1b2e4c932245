// libFuzzer target for the glTF loader: any input must either load or fail
// with wv::Error (the message the user sees); anything else escaping --
// another exception, a crash, a hang, an out-of-bounds read that the
// address sanitizer catches -- is a bug. Inputs starting with the GLB magic
// are loaded as .glb, the rest as .gltf.
#include "Error.h"
#include "scene/GltfLoader.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const std::string stem = "/tmp/wavevcm-fuzz-" + std::to_string(::getpid());
    bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    std::string path = stem + (binary ? ".glb" : ".gltf");
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    try {
        wv::Scene scene = wv::loadGltf(path);
    } catch (const wv::Error&) {
        // A clear refusal is a correct answer.
    }
    std::remove(path.c_str());
    return 0;
}
