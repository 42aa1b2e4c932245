#include "Devices.h"

#include "../Error.h"

#include <algorithm>
#include <cctype>

namespace wv {

std::string DeviceInfo::typeName() const
{
    if (type & CL_DEVICE_TYPE_GPU) return "GPU";
    if (type & CL_DEVICE_TYPE_CPU) return "CPU";
    if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

bool DeviceInfo::isPocl() const { return platformName == "Portable Computing Language"; }
bool DeviceInfo::isRusticl() const { return platformName == "rusticl"; }

std::string DeviceInfo::label() const
{
    if (pipelines <= 1) return name;
    return name + " (pipeline " + std::to_string(pipeline + 1) + " of " + std::to_string(pipelines) + ")";
}

static std::string trimmed(std::string s)
{
    // Some drivers pad names with spaces or a trailing NUL.
    while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
    size_t start = 0;
    while (start < s.size() && std::isspace(static_cast<unsigned char>(s[start]))) ++start;
    return s.substr(start);
}

static const char* kInstallHint =
    "no OpenCL device found. Install an OpenCL driver: `apt-get install pocl-opencl-icd` for the CPU, "
    "or your GPU vendor's OpenCL ICD; Mesa's rusticl (`mesa-opencl-icd`) also needs RUSTICL_ENABLE=llvmpipe";

std::vector<DeviceInfo> enumerateDevices()
{
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        // CL_PLATFORM_NOT_FOUND_KHR from the ICD loader: no driver installed.
    }
    std::vector<DeviceInfo> out;
    for (const cl::Platform& platform : platforms) {
        std::vector<cl::Device> devices;
        try {
            platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            continue; // CL_DEVICE_NOT_FOUND: e.g. Clover with no supported GPU
        }
        for (const cl::Device& device : devices) {
            DeviceInfo d;
            d.index = int(out.size());
            d.platform = platform;
            d.device = device;
            d.platformName = trimmed(platform.getInfo<CL_PLATFORM_NAME>());
            d.name = trimmed(device.getInfo<CL_DEVICE_NAME>());
            d.version = trimmed(device.getInfo<CL_DEVICE_VERSION>());
            d.driverVersion = trimmed(device.getInfo<CL_DRIVER_VERSION>());
            d.type = device.getInfo<CL_DEVICE_TYPE>();
            d.computeUnits = device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
            d.globalMemory = device.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
            d.maxAllocation = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
            d.localMemory = device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
            d.maxWorkGroupSize = device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
            out.push_back(d);
        }
    }
    if (out.empty()) throw Error(kInstallHint, 2);
    return out;
}

static std::string lower(std::string s)
{
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

const DeviceInfo& selectDevice(const std::vector<DeviceInfo>& devices, const std::string& selector)
{
    if (selector.empty()) {
        for (cl_device_type want : {cl_device_type(CL_DEVICE_TYPE_GPU), cl_device_type(CL_DEVICE_TYPE_CPU)})
            for (const DeviceInfo& d : devices)
                if (d.type & want) return d;
        return devices.front();
    }
    if (std::all_of(selector.begin(), selector.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
        size_t index = selector.size() < 9 ? std::stoul(selector) : devices.size();
        if (index >= devices.size())
            throw Error("device index " + selector + " out of range: there are " + std::to_string(devices.size()) +
                        " devices (see `wavevcm devices`)");
        return devices[index];
    }
    std::string want = lower(selector);
    for (const DeviceInfo& d : devices)
        if (lower(d.name).find(want) != std::string::npos) return d;
    for (const DeviceInfo& d : devices)
        if (lower(d.platformName).find(want) != std::string::npos) return d;
    throw Error("no device matches '" + selector + "' (see `wavevcm devices`)");
}

std::vector<DeviceInfo> selectDevices(const std::vector<DeviceInfo>& devices, const std::string& selectors)
{
    if (lower(selectors) == "all") return devices;
    std::vector<DeviceInfo> out;
    size_t start = 0;
    for (;;) {
        size_t comma = selectors.find(',', start);
        std::string one = selectors.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (one.empty() && comma != std::string::npos) throw Error("-d " + selectors + ": an empty device selector");
        out.push_back(selectDevice(devices, one));
        if (comma == std::string::npos) return out;
        start = comma + 1;
    }
}

static bool partitionsByCounts(const DeviceInfo& d)
{
    try {
        for (cl_device_partition_property p : d.device.getInfo<CL_DEVICE_PARTITION_PROPERTIES>())
            if (p == CL_DEVICE_PARTITION_BY_COUNTS) return true;
    } catch (const cl::Error&) {
        // An OpenCL 1.1 device: no sub-devices.
    }
    return false;
}

int defaultPipelines(const DeviceInfo& device)
{
    return (device.type & CL_DEVICE_TYPE_CPU) && device.computeUnits >= 2 && partitionsByCounts(device) ? 2 : 1;
}

std::vector<DeviceInfo> pipelineDevices(const DeviceInfo& device, int pipelines)
{
    if (pipelines <= 1) return {device};
    std::vector<cl::Device> subDevices;
    if (device.computeUnits >= unsigned(pipelines) && partitionsByCounts(device)) {
        // The compute units as evenly as they divide: 5 into 2 pipelines as 3 + 2.
        std::vector<cl_device_partition_property> counts{CL_DEVICE_PARTITION_BY_COUNTS};
        for (int i = 0; i < pipelines; ++i)
            counts.push_back(cl_device_partition_property(device.computeUnits / unsigned(pipelines) +
                                                          (unsigned(i) < device.computeUnits % unsigned(pipelines))));
        counts.push_back(CL_DEVICE_PARTITION_BY_COUNTS_LIST_END);
        counts.push_back(0);
        try {
            cl::Device(device.device).createSubDevices(counts.data(), &subDevices);
        } catch (const cl::Error&) {
            subDevices.clear(); // the driver declined: share the whole device
        }
        if (subDevices.size() != size_t(pipelines)) subDevices.clear();
    }
    std::vector<DeviceInfo> out;
    for (int i = 0; i < pipelines; ++i) {
        DeviceInfo d = device;
        d.pipeline = i;
        d.pipelines = pipelines;
        d.globalMemory = device.globalMemory / uint64_t(pipelines);
        d.maxAllocation = std::min(d.maxAllocation, d.globalMemory);
        if (!subDevices.empty()) {
            d.device = subDevices[size_t(i)];
            d.computeUnits = d.device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
        }
        out.push_back(d);
    }
    return out;
}

} // namespace wv
