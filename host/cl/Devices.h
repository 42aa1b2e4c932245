// OpenCL platforms and devices: enumeration, the `devices` listing and the
// choice made by `--device`.
#pragma once

#include "OpenCL.h"

#include <cstdint>
#include <string>
#include <vector>

namespace wv {

struct DeviceInfo {
    int index = 0; // position in enumerateDevices(), as `wavevcm devices` prints it
    cl::Platform platform;
    cl::Device device;
    std::string platformName, name, version, driverVersion;
    cl_device_type type = 0;
    unsigned computeUnits = 0;
    uint64_t globalMemory = 0, maxAllocation = 0, localMemory = 0;
    size_t maxWorkGroupSize = 0;
    // One of several render pipelines on `device` (pipelineDevices): then
    // `device` is an OpenCL sub-device with its share of the compute units,
    // or the whole device shared, and globalMemory is the pipeline's share.
    int pipeline = 0, pipelines = 1;

    std::string typeName() const; // "GPU", "CPU", ...
    bool isPocl() const;          // PoCL's platform ("Portable Computing Language")
    bool isRusticl() const;       // Mesa's rusticl platform ("rusticl")
    std::string label() const;    // the name, and "pipeline i of n" when split
};

// Every device of every platform, skipping platforms with no devices (Mesa's
// Clover). Throws wv::Error (exit code 2) naming the packages to install when
// there is none.
std::vector<DeviceInfo> enumerateDevices();

// `selector` is empty (first GPU, else first CPU, else the first device), an
// index from enumerateDevices(), or a case-insensitive substring of the device
// or platform name. Throws wv::Error when nothing matches.
const DeviceInfo& selectDevice(const std::vector<DeviceInfo>& devices, const std::string& selector);

// Several devices for one render: "all", or selectors as above separated by
// commas ("0,2", "pthread,rusticl"); one selector gives one device. A device
// named twice renders with two renderers of its own.
std::vector<DeviceInfo> selectDevices(const std::vector<DeviceInfo>& devices, const std::string& selectors);

// A device as `pipelines` independent render pipelines, each rendering whole
// iterations of its own (MultiDeviceRender), so that one pipeline's launch
// tails and host round trips overlap the other's work. Where the device can be
// partitioned (OpenCL sub-devices, e.g. PoCL's CPU devices), each pipeline
// gets its own share of the compute units; elsewhere they share the device.
// Each one's globalMemory is 1/pipelines of the device's, so every memory
// budget a renderer derives from it leaves room for the others.
std::vector<DeviceInfo> pipelineDevices(const DeviceInfo& device, int pipelines);

// How many pipelines a render uses on `device` when not told: 2 on a CPU
// device of 2 or more compute units that can be partitioned, else 1.
int defaultPipelines(const DeviceInfo& device);

} // namespace wv
