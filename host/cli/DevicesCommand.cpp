#include "../cl/Devices.h"
#include "Commands.h"

#include <cstdio>

namespace wv {

int runDevices()
{
    std::vector<DeviceInfo> devices = enumerateDevices();
    const DeviceInfo& chosen = selectDevice(devices, "");
    std::printf("%-5s %-28s %-44s %-5s %4s %10s\n", "index", "platform", "device", "type", "CUs", "memory");
    for (const DeviceInfo& d : devices)
        std::printf("%-5d %-28.28s %-44.44s %-5s %4u %6llu MiB%s\n", d.index, d.platformName.c_str(), d.name.c_str(),
                    d.typeName().c_str(), d.computeUnits, static_cast<unsigned long long>(d.globalMemory >> 20),
                    d.index == chosen.index ? "  (default)" : "");
    return 0;
}

} // namespace wv
