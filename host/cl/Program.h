// Kernel sources: finding them, inlining their #includes, building them for a
// device and caching the compiled binary on disk.
#pragma once

#include "Devices.h"

#include <string>
#include <vector>

namespace wv {

struct DeviceContext;

// The kernels/ directory: $WAVEVCM_KERNEL_DIR, else ../share/wavevcm/kernels
// next to the running binary (an installed wavevcm), else the source tree the
// binary was built from. Throws wv::Error if none holds the kernels.
std::string findKernelDir();

// The files (relative to kernelDir, or absolute) concatenated into one
// translation unit, every `#include "x"` inlined once (all headers are
// include-once) with #line directives, so compiler messages name the original
// file and line. Includes resolve against the including file's directory,
// then kernelDir.
std::string expandKernelSources(const std::string& kernelDir, const std::vector<std::string>& files);

// A build log with the lines it names in the whole expanded source
// ("<kernel>:4:12", as NVIDIA's compiler writes them: it ignores #line) turned
// into the kernel files' own ("broken.cl:3:12"). Logs that already name files
// (PoCL, rusticl) come back unchanged.
std::string attributeBuildLog(const std::string& log, const std::string& expandedSource);

struct ProgramBuild {
    // Which cache keeps the compiled program for the next run: wavevcm's, the
    // driver's own (PoCL's), or none (WAVEVCM_CACHE_DIR=off, or a driver that
    // cannot export binaries).
    enum class Cache { Wavevcm, Driver, None };
    cl::Program program;
    Cache cache = Cache::None;
    bool fromCache = false; // loaded from wavevcm's cache
    double seconds = 0;
    std::string options;   // the build options, wavevcm's and WAVEVCM_CL_OPTIONS
    std::string cacheFile; // wavevcm's cache file; empty when it is not used
    std::string log;       // the compiler's messages when built from source (a cached program has none)
};
const char* cacheName(ProgramBuild::Cache cache); // "wavevcm", "driver", "none"

// Builds `source` with `options`, or loads the binary cached under a key of
// source, options, platform, device and driver version. The cache lives in
// $WAVEVCM_CACHE_DIR, else $XDG_CACHE_HOME/wavevcm, else ~/.cache/wavevcm;
// WAVEVCM_CACHE_DIR=off disables it. PoCL with its own kernel cache on
// (POCL_KERNEL_CACHE unset or not 0) is left to that cache: exporting a
// binary from PoCL compiles every kernel of the program a second time. A
// failed build throws wv::Error with the device's build log.
ProgramBuild buildProgram(const cl::Context& context, const DeviceInfo& device, const std::string& source,
                          const std::string& options);

// buildProgram in `device`'s context, once per source and options: a later
// call with the same ones gets that build back (fromCache set, seconds the
// lookup's). Renderers made one after another in one context (the tests'
// seeds, the report's runs) then skip what even a cached build costs: PoCL
// preprocesses and hashes the whole source and reloads every kernel.
ProgramBuild buildProgramOnce(DeviceContext& device, const std::string& source, const std::string& options);

} // namespace wv
