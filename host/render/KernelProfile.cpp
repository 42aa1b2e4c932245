#include "KernelProfile.h"

namespace wv {

void KernelProfile::record(const cl::Kernel& kernel, size_t items, const cl::Event& event)
{
    pending_.push_back({kernel.getInfo<CL_KERNEL_FUNCTION_NAME>(), items, event});
}

void KernelProfile::collect()
{
    for (PendingLaunch& launch : pending_) {
        cl_ulong start = launch.event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
        cl_ulong end = launch.event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        KernelStats& stats = stats_[launch.kernel];
        stats.seconds += double(end - start) * 1e-9;
        stats.items += launch.items;
    }
    pending_.clear();
}

} // namespace wv
