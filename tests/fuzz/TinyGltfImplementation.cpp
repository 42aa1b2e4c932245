// tinygltf compiled into the fuzz target, so that the sanitizers and
// libFuzzer's coverage see its parser too (Debian's libtinygltf.so is not
// instrumented). Images are never decoded by wavevcm (its loader installs
// its own image callback), so CMakeLists.txt leaves stb_image out
// (TINYGLTF_NO_STB_IMAGE*, for every file of the target).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
