// The host side of kernels/interface/kernel_interface.h: every render kernel takes the
// buffers of RENDER_BUFFERS in order, then LaunchParams by value. Both sides
// expand the same lists, so the argument order is written nowhere else.
#pragma once

#include "../cl/OpenCL.h"

namespace wv {
// The element types the lists name, for their sizes on the host.
using float4 = cl_float4;
using float2 = cl_float2;
// TrianglePacket4 or TrianglePacket8 by the device's tree (SceneBuffers.h):
// the program picks one, the host sees bytes.
using TrianglePacket = unsigned char;
} // namespace wv

#include "../../kernels/interface/kernel_interface.h"

#include <cstddef>

namespace wv {

static_assert(sizeof(LaunchParams) % 4 == 0 && alignof(LaunchParams) == 4,
              "LaunchParams holds 4-byte scalars only (kernels/interface/kernel_interface.h)");

// One handle per buffer a render kernel takes, by the kernels' names. A
// buffer an algorithm does not use stays null (a null cl_mem argument).
struct KernelBuffers {
#define WV_KERNEL_BUFFER(space, type, name, perSlot) cl::Buffer name;
    RENDER_BUFFERS(WV_KERNEL_BUFFER)
#undef WV_KERNEL_BUFFER
};

// Arguments of every render kernel: the buffers, then the LaunchParams.
constexpr cl_uint kRenderBufferCount = 0
#define WV_COUNT_BUFFER(space, type, name, perSlot) +1
    RENDER_BUFFERS(WV_COUNT_BUFFER)
#undef WV_COUNT_BUFFER
    ;
constexpr cl_uint kRenderKernelArgCount = kRenderBufferCount + 1;

// Binds every buffer to `kernel` (arguments 0 .. kRenderBufferCount − 1).
void bindBuffers(cl::Kernel& kernel, const KernelBuffers& buffers);

// Sets the LaunchParams argument (the last one); copied at once.
void setLaunchParams(cl::Kernel& kernel, const LaunchParams& params);

// The kernels of a program that take the render interface: every kernel but
// the hash-grid build's (host/render/HashGrid.h), which has its own.
std::vector<cl::Kernel> renderKernels(const cl::Program& program);

} // namespace wv
