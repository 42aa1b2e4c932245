// The host queue manager: owns the device program, the scene on the device
// and the path state, and runs iterations of the chosen algorithm as a chain
// of kernel launches.
#pragma once

#include "../cl/Program.h"
#include "../image/Image.h"
#include "Algorithm.h"
#include "PathState.h"
#include "SceneBuffers.h"

#include <cstdint>
#include <memory>

namespace wv {

struct RenderSettings {
    Algorithm algorithm = Algorithm::EyeLight;
    int width = 512, height = 512;
    int maxPathLength = 10;
    uint32_t seed = 0;
    int wavefront = 0; // path slots; 0 = the device type's default
};

class Renderer {
public:
    // Builds (or loads from the cache) the kernels for the scene's features and
    // uploads the scene. Throws wv::Error on any failure.
    Renderer(DeviceContext& device, const Scene& scene, const Bvh& bvh, const RenderSettings& settings);

    // Enqueues one iteration (one sample per pixel) without waiting for it.
    void enqueueIteration();
    // Waits for everything enqueued.
    void finish();

    int iterations() const { return iteration_; }
    Image image();
    uint64_t nonFiniteCount();
    const ProgramBuild& programBuild() const { return build_; }
    int wavefront() const { return paths_.capacity; }
    size_t deviceBytes() const { return sceneBuffers_.bytes + paths_.bytes + size_t(pixels_) * 16; }

    // The kernel files every render program is built from.
    static const std::vector<std::string>& kernelFiles();

private:
    void launch(cl::Kernel& kernel, int items);
    void iterateEyeLight();

    DeviceContext& device_;
    RenderSettings settings_;
    cl::Buffer camera_;
    SceneBuffers sceneBuffers_;
    PathState paths_;
    ProgramBuild build_;
    cl::Buffer framebuffer_; // float4 per pixel, running mean
    int pixels_ = 0;
    int iteration_ = 0;
    size_t localSize_ = 64;
    cl::Kernel generate_, extend_, shadeEyeLight_, accumulate_;
};

// Default wavefront capacity: ~256K paths on a CPU, 2M on a GPU, at most what
// a quarter of the device's memory holds.
int defaultWavefront(const DeviceInfo& device);

} // namespace wv
