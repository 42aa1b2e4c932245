// The render kernels' interface is declared once (kernels/interface/kernel_interface.h):
// every kernel of every algorithm's program takes exactly the buffers of
// RENDER_BUFFERS, by those names and in that order, then the LaunchParams,
// as the host binds them (host/render/KernelBindings.h). A kernel written with
// its own parameter list, or a list edited on one side only, fails here.
#include "TestDevices.h"
#include "render/KernelBindings.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

namespace wv {
namespace {

std::vector<std::string> declaredArgumentNames()
{
    std::vector<std::string> names;
#define WV_NAME(space, type, name, perSlot) names.push_back(#name);
    RENDER_BUFFERS(WV_NAME)
#undef WV_NAME
    names.push_back("params");
    return names;
}

TEST(KernelInterface, EveryRenderKernelTakesTheDeclaredArguments)
{
    std::vector<DeviceInfo> devices = test::devicesUnderTest();
    ASSERT_FALSE(devices.empty());
    DeviceContext device(devices.front());
    Scene scene = loadGltf(test::cornellBoxPath());
    int lightCount = buildLightTable(scene, buildBvh(scene.vertices)).info.lightCount;
    const std::vector<std::string> names = declaredArgumentNames();
    ASSERT_EQ(names.size(), kRenderKernelArgCount);
    KernelBuffers buffers; // all null: binding needs no allocation
    LaunchParams params{};
    for (Algorithm a : {Algorithm::EyeLight, Algorithm::PathTracing, Algorithm::LightTracing, Algorithm::Bidirectional,
                        Algorithm::ProgressivePhotonMapping, Algorithm::BidirectionalPhotonMapping,
                        Algorithm::VertexConnectionMerging}) {
        SCOPED_TRACE(algorithmName(a));
        std::string source = expandKernelSources(findKernelDir(), Renderer::kernelFiles(a));
        // Argument names are only reported with -cl-kernel-arg-info; a fresh
        // build, so the cache's binary (built without it) is not used.
        cl::Program program(device.context, source);
        program.build({device.info.device},
                      (Renderer::programOptions(a, scene.features(), lightCount) + " -cl-kernel-arg-info").c_str());
        std::vector<cl::Kernel> kernels = renderKernels(program);
        EXPECT_GE(kernels.size(), 5u);
        for (cl::Kernel& k : kernels) {
            std::string name = k.getInfo<CL_KERNEL_FUNCTION_NAME>();
            SCOPED_TRACE(name);
            ASSERT_EQ(k.getInfo<CL_KERNEL_NUM_ARGS>(), kRenderKernelArgCount);
            for (cl_uint i = 0; i < kRenderKernelArgCount; ++i) {
                std::string arg = k.getArgInfo<CL_KERNEL_ARG_NAME>(i);
                arg.erase(arg.find_last_not_of('\0') + 1);
                EXPECT_EQ(arg, names[i]) << "argument " << i;
            }
            EXPECT_NO_THROW(bindBuffers(k, buffers));
            EXPECT_NO_THROW(setLaunchParams(k, params));
        }
    }
}

} // namespace
} // namespace wv
