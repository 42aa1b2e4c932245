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

    std::string typeName() const; // "GPU", "CPU", ...
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

} // namespace wv
