// Device time per kernel, from the profiling events of a profiling queue
// (DeviceContext): launches are recorded once enqueued and their times read
// once the queue has finished them, so profiling adds no wait.
#pragma once

#include "../cl/OpenCL.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace wv {

class KernelProfile {
public:
    struct KernelStats {
        double seconds = 0;
        uint64_t items = 0;
    };

    // A launch of `kernel` over `items` work items, enqueued with `event`.
    void record(const cl::Kernel& kernel, size_t items, const cl::Event& event);
    // Adds the recorded launches' times; the queue must have finished them.
    void collect();
    const std::map<std::string, KernelStats>& stats() const { return stats_; }

private:
    struct PendingLaunch {
        std::string kernel;
        size_t items;
        cl::Event event;
    };
    std::vector<PendingLaunch> pending_;
    std::map<std::string, KernelStats> stats_;
};

} // namespace wv
