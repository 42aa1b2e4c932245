// One device with its context and in-order command queue.
#pragma once

#include "Devices.h"

namespace wv {

struct DeviceContext {
    DeviceInfo info;
    cl::Context context;
    cl::CommandQueue queue;

    // `profiling` enables event timestamps (for per-kernel timing).
    explicit DeviceContext(const DeviceInfo& device, bool profiling = false)
        : info(device), context(device.device),
          queue(context, device.device, profiling ? CL_QUEUE_PROFILING_ENABLE : 0) {}
};

} // namespace wv
