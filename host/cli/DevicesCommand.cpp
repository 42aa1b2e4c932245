#include "../cl/Devices.h"
#include "Commands.h"

#include <algorithm>
#include <cstdio>

namespace wv {

int runDevices()
{
    std::vector<DeviceInfo> devices = enumerateDevices();
    const DeviceInfo& chosen = selectDevice(devices, "");
    size_t platformWidth = 8;
    for (const DeviceInfo& d : devices) platformWidth = std::max(platformWidth, d.platformName.size());
    // pipelines: how many a render runs on the device when not told (--pipelines).
    std::printf("%-5s  %-*s  %-11s  %4s  %10s  %9s  %s\n", "index", int(platformWidth), "platform", "type", "CUs",
                "memory", "pipelines", "device");
    for (const DeviceInfo& d : devices)
        std::printf("%-5d  %-*s  %-11s  %4u  %6llu MiB  %9d  %s%s\n", d.index, int(platformWidth),
                    d.platformName.c_str(), d.typeName().c_str(), d.computeUnits,
                    static_cast<unsigned long long>(d.globalMemory >> 20), defaultPipelines(d), d.name.c_str(),
                    d.index == chosen.index ? "  (default)" : "");
    return 0;
}

} // namespace wv
