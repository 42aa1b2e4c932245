// SIMD across work-items on PoCL's CPU devices.
//
// PoCL runs a work-group as a loop over its work-items and leaves SIMD to
// LLVM's loop vectorizer, in the LLVM library loaded into this process. Two
// of LLVM's defaults keep the shading kernels at one work-item per
// instruction, and no OpenCL build option reaches them (PoCL rejects -mllvm):
// the SLP vectorizer, which runs first and packs adjacent floats into
// <2 x float> values that the loop vectorizer then refuses, and the loop
// vectorizer's cost model, which rates the gathers and scatters of a
// work-item loop dearer than they run. enableWorkItemVectorization() sets
// -slp-threshold=1000000 -force-vector-width=W in that LLVM, once per
// process, where the device's native float vector width W is 8 (AVX2) or 16
// (AVX-512), through LLVM's C API (LLVMParseCommandLineOptions in the libLLVM
// already loaded). The kernels are written for it (kernels/core/simd.h);
// docs/performance.md, "Vectorization on PoCL", has the measurements.
//
// WAVEVCM_LLVM_OPTIONS replaces the options (space-separated LLVM
// command-line options; empty: none, the kernels then as on other devices).
// An option LLVM does not know ends the process (LLVM's parser exits).
#pragma once

#include "Devices.h"

#include <string>

namespace wv {

// For a PoCL CPU device: sets the options above in PoCL's LLVM (the first
// call in the process; later calls find them set) and says whether they are
// in force. False for another platform or device type, a SIMD width under
// 8, WAVEVCM_LLVM_OPTIONS empty, or no shared libLLVM in the process.
bool enableWorkItemVectorization(const DeviceInfo& device);

// Whether the shade kernels may run in SIMD too: the options are in force
// and the device has 16 float lanes (AVX-512). With AVX2's 8, shade_light
// ran 0.6-0.8x as fast in SIMD and shade and shade_bidirectional no faster
// (docs/performance.md, "Vectorization on PoCL"): straight-line kernels gain,
// shading, which pays for every branch in every lane, does not.
bool vectorizesShading(const DeviceInfo& device);

// " -DLLVM_OPTIONS_KEY=<hash of the options>" once they are set in this
// process, else "": appended to every render program's build options
// (Renderer::deviceOptions), so that no program cache (wavevcm's or PoCL's,
// keyed by source and build options) hands out a render program compiled
// under other LLVM options.
std::string llvmOptionsKey();

} // namespace wv
