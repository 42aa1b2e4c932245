#include "KernelBindings.h"

#include "HashGrid.h"

#include <algorithm>

namespace wv {

void bindBuffers(cl::Kernel& kernel, const KernelBuffers& buffers)
{
    cl_uint index = 0;
#define WV_BIND_BUFFER(space, type, name, perSlot) kernel.setArg(index++, buffers.name);
    RENDER_BUFFERS(WV_BIND_BUFFER)
#undef WV_BIND_BUFFER
}

void setLaunchParams(cl::Kernel& kernel, const LaunchParams& params)
{
    kernel.setArg(kRenderBufferCount, sizeof params, &params);
}

std::vector<cl::Kernel> renderKernels(const cl::Program& program)
{
    std::vector<cl::Kernel> all, out;
    cl::Program(program).createKernels(&all);
    const std::vector<std::string>& grid = HashGrid::kernelNames();
    for (cl::Kernel& k : all)
        if (std::find(grid.begin(), grid.end(), k.getInfo<CL_KERNEL_FUNCTION_NAME>()) == grid.end())
            out.push_back(k);
    return out;
}

} // namespace wv
