#include "PoclVectorizer.h"

#include <cstdio>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <set>
#include <sstream>
#include <vector>

#if defined(__linux__)
#include <dlfcn.h>
#include <link.h>
#endif

namespace wv {

namespace {

std::vector<std::string> splitOptions(const std::string& text)
{
    std::vector<std::string> options;
    std::istringstream in(text);
    for (std::string option; in >> option;) options.push_back(option);
    return options;
}

#if defined(__linux__)
// The paths of the libLLVM objects loaded into this process (PoCL's; Mesa's
// rusticl, where loaded, usually shares the same one).
std::set<std::string> loadedLlvmLibraries()
{
    std::set<std::string> paths;
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* data) {
            std::string path = info->dlpi_name ? info->dlpi_name : "";
            size_t slash = path.rfind('/');
            if (path.compare(slash == std::string::npos ? 0 : slash + 1, 7, "libLLVM") == 0)
                static_cast<std::set<std::string>*>(data)->insert(path);
            return 0;
        },
        &paths);
    return paths;
}

// LLVMParseCommandLineOptions in each loaded libLLVM; false if there is none.
bool setLlvmOptions(const std::vector<std::string>& options)
{
    using Parse = void (*)(int, const char* const*, const char*);
    std::vector<const char*> argv{"wavevcm"};
    for (const std::string& o : options) argv.push_back(o.c_str());
    bool set = false;
    for (const std::string& path : loadedLlvmLibraries()) {
        void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_NOLOAD);
        if (!library) continue;
        if (auto parse = reinterpret_cast<Parse>(dlsym(library, "LLVMParseCommandLineOptions"))) {
            parse(int(argv.size()), argv.data(), "wavevcm");
            set = true;
        }
        dlclose(library); // drops the reference RTLD_NOLOAD took; PoCL keeps its own
    }
    return set;
}
#else
bool setLlvmOptions(const std::vector<std::string>&) { return false; }
#endif

} // namespace

static cl_uint nativeFloatWidth(const DeviceInfo& device)
{
    return device.device.getInfo<CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT>();
}

// LLVM's options are the process's, and its parser takes each only once: the
// first call sets them, the rest find them set.
static std::mutex gMutex;
static bool gAttempted = false;
static std::string gKey; // llvmOptionsKey(), once set

bool enableWorkItemVectorization(const DeviceInfo& device)
{
    if (!device.isPocl() || !(device.type & CL_DEVICE_TYPE_CPU)) return false;
    std::lock_guard<std::mutex> lock(gMutex);
    if (gAttempted) return !gKey.empty();
    gAttempted = true;
    std::string text;
    if (const char* env = std::getenv("WAVEVCM_LLVM_OPTIONS")) {
        text = env;
    } else {
        // AVX2 (8 floats) or AVX-512 (16); narrower SIMD was not measured.
        cl_uint width = nativeFloatWidth(device);
        if (width < 8) return false;
        text = "-slp-threshold=1000000 -force-vector-width=" + std::to_string(width);
    }
    std::vector<std::string> options = splitOptions(text);
    if (options.empty() || !setLlvmOptions(options)) return false;
    char key[48];
    std::snprintf(key, sizeof key, " -DLLVM_OPTIONS_KEY=0x%llx",
                  static_cast<unsigned long long>(std::hash<std::string>{}(text) & 0xffffffffffffull));
    gKey = key;
    return true;
}

bool vectorizesShading(const DeviceInfo& device)
{
    return enableWorkItemVectorization(device) && nativeFloatWidth(device) >= 16;
}

std::string llvmOptionsKey()
{
    std::lock_guard<std::mutex> lock(gMutex);
    return gKey;
}

} // namespace wv
