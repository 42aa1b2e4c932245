// Kernel sources: finding them, inlining their #includes, building them for a
// device and caching the compiled binary on disk.
#pragma once

#include "Devices.h"

#include <string>
#include <vector>

namespace wv {

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

struct ProgramBuild {
    cl::Program program;
    bool fromCache = false;
    double seconds = 0;
    std::string cacheFile; // empty when caching is off
};

// Builds `source` with `options`, or loads the binary cached under a key of
// source, options, platform, device and driver version. The cache lives in
// $WAVEVCM_CACHE_DIR, else $XDG_CACHE_HOME/wavevcm, else ~/.cache/wavevcm;
// WAVEVCM_CACHE_DIR=off disables it. A failed build throws wv::Error with the
// device's build log.
ProgramBuild buildProgram(const cl::Context& context, const DeviceInfo& device, const std::string& source,
                          const std::string& options);

} // namespace wv
