// The host queue manager: owns the device program, the scene on the device
// and the path state, and runs iterations of the chosen algorithm as rounds
// of kernel launches over the work queues.
#pragma once

#include "../cl/Program.h"
#include "../image/Image.h"
#include "Algorithm.h"
#include "LightTable.h"
#include "PathState.h"
#include "SceneBuffers.h"

#include <cstdint>
#include <map>

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
    // the algorithm, and uploads the scene. Throws wv::Error on any failure.
    Renderer(DeviceContext& device, const Scene& scene, const Bvh& bvh, const RenderSettings& settings);

    // Runs one iteration (one sample per pixel) to completion.
    void iterate();

    int iterations() const { return iteration_; }
    uint64_t raysTraced() const { return rays_; } // extended and shadow rays, all iterations
    Image image();
    uint64_t nonFiniteCount();
    const ProgramBuild& programBuild() const { return build_; }
    const LightTable& lights() const { return lights_; }
    int wavefront() const { return paths_.capacity; }
    size_t deviceBytes() const { return sceneBuffers_.bytes + paths_.bytes + size_t(pixels_) * 32; }

    // Device time per kernel so far, in seconds (needs a profiling queue,
    // see DeviceContext; empty otherwise).
    const std::map<std::string, double>& kernelSeconds() const { return kernelSeconds_; }

    // The kernel files of the program for an algorithm.
    static std::vector<std::string> kernelFiles(Algorithm algorithm);

private:
    void launch(cl::Kernel& kernel, size_t items);
    void collectProfile();
    void round(int parity, size_t generated, size_t issued, size_t rays);

    DeviceContext& device_;
    RenderSettings settings_;
    LightTable lights_;
    SceneBuffers sceneBuffers_;
    PathState paths_;
    ProgramBuild build_;
    cl::Buffer camera_;
    cl::Buffer pixelRadiance_; // float4 per pixel: this iteration's sample
    cl::Buffer framebuffer_;   // float4 per pixel: running mean
    int pixels_ = 0;
    int iteration_ = 0;
    uint64_t rays_ = 0;
    size_t localSize_ = 64;
    cl::Kernel generate_, extend_, shade_, escaped_, connect_, accumulate_;
    bool profiling_ = false;
    std::vector<std::pair<std::string, cl::Event>> pending_;
    std::map<std::string, double> kernelSeconds_;
};

// Default wavefront capacity: ~256K paths on a CPU, 2M on a GPU, at most what
// a quarter of the device's memory holds.
int defaultWavefront(const DeviceInfo& device);

} // namespace wv
