// One device with its context and in-order command queue.
#pragma once

#include "Devices.h"

namespace wv {

struct DeviceContext {
    DeviceInfo info;
    cl::Context context;
    cl::CommandQueue queue;

    explicit DeviceContext(const DeviceInfo& device)
        : info(device), context(device.device), queue(context, device.device) {}
};

} // namespace wv
