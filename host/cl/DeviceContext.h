// One device with its context and in-order command queue.
#pragma once

#include "Devices.h"
#include "Program.h"

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace wv {

struct DeviceContext {
    DeviceInfo info;
    cl::Context context;
    cl::CommandQueue queue;
    // The programs built in this context by buildProgramOnce, by options and source.
    struct BuiltPrograms {
        std::mutex mutex;
        std::map<std::string, ProgramBuild> builds;
    };
    std::shared_ptr<BuiltPrograms> builtPrograms = std::make_shared<BuiltPrograms>();

    // `profiling` enables event timestamps (for per-kernel timing).
    explicit DeviceContext(const DeviceInfo& device, bool profiling = false)
        : info(device), context(device.device),
          queue(context, device.device, profiling ? CL_QUEUE_PROFILING_ENABLE : 0) {}
};

} // namespace wv
