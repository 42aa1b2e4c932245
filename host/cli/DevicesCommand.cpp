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
    std::printf("%-5s  %-*s  %-11s  %4s  %10s  %s\n", "index", int(platformWidth), "platform", "type", "CUs", "memory",
                "device");
    for (const DeviceInfo& d : devices)
        std::printf("%-5d  %-*s  %-11s  %4u  %6llu MiB  %s%s\n", d.index, int(platformWidth), d.platformName.c_str(),
                    d.typeName().c_str(), d.computeUnits, static_cast<unsigned long long>(d.globalMemory >> 20),
                    d.name.c_str(), d.index == chosen.index ? "  (default)" : "");
    return 0;
}

} // namespace wv
