#include "Renderer.h"

#include "../../kernels/queue_ids.h"
#include "../Error.h"

#include <algorithm>

namespace wv {

const std::vector<std::string>& Renderer::kernelFiles()
{
    static const std::vector<std::string> files{"generate.cl", "extend.cl", "connect.cl", "shade_eyelight.cl",
                                                "accumulate.cl"};
    return files;
}

int defaultWavefront(const DeviceInfo& device)
{
    size_t wanted = (device.type & CL_DEVICE_TYPE_GPU) ? (size_t(1) << 21) : (size_t(1) << 18);
    size_t fits = device.globalMemory / 4 / PathState::bytesPerPath();
    return int(std::max<size_t>(1024, std::min(wanted, fits)));
}

static int roundUp(int x, int multiple) { return (x + multiple - 1) / multiple * multiple; }

static PathState makePathState(DeviceContext& device, const RenderSettings& s)
{
    int wavefront = s.wavefront > 0 ? s.wavefront : defaultWavefront(device.info);
    // Launches cover the whole capacity in work-groups of 64 (kernels return
    // early past a queue's size), so the capacity is a multiple of 64, and no
    // larger than the image needs.
    wavefront = std::min(wavefront, s.width * s.height);
    return PathState(device, roundUp(wavefront, 64));
}

Renderer::Renderer(DeviceContext& device, const Scene& scene, const Bvh& bvh, const RenderSettings& settings)
    : device_(device), settings_(settings), sceneBuffers_(device, scene, bvh),
      paths_(makePathState(device, settings))
{
    if (!isImplemented(settings.algorithm))
        throw Error("algorithm '" + algorithmName(settings.algorithm) + "' is not implemented yet");
    pixels_ = settings.width * settings.height;
    Camera camera = makeCamera(scene.camera, settings.width, settings.height);
    camera_ = uploadBuffer(device, &camera, sizeof camera, "the camera");
    framebuffer_ = deviceBuffer(device, size_t(pixels_) * 16, "the framebuffer");
    device.queue.enqueueFillBuffer(framebuffer_, 0.0f, 0, size_t(pixels_) * 16);
    device.queue.enqueueFillBuffer(paths_.counters, 0, 0, COUNTER_COUNT * sizeof(int));

    std::string source = expandKernelSources(findKernelDir(), kernelFiles());
    std::string options = "-cl-std=CL1.2" + scene.features().buildOptions();
    build_ = buildProgram(device.context, device.info, source, options);

    // Fixed local size: PoCL compiles a work-group function per local size,
    // and local size 1 is several times slower there.
    localSize_ = std::min<size_t>(64, device.info.maxWorkGroupSize);
    generate_ = cl::Kernel(build_.program, "generate");
    extend_ = cl::Kernel(build_.program, "extend");
    shadeEyeLight_ = cl::Kernel(build_.program, "shade_eyelight");
    accumulate_ = cl::Kernel(build_.program, "accumulate");

    const PathState& p = paths_;
    generate_.setArg(0, camera_);
    generate_.setArg(1, settings.seed);
    generate_.setArg(4, p.rayOrigins);
    generate_.setArg(5, p.rayDirections);
    generate_.setArg(6, p.pathPixels);
    generate_.setArg(7, p.queueItems);
    generate_.setArg(8, p.counters);

    extend_.setArg(0, sceneBuffers_.nodes);
    extend_.setArg(1, sceneBuffers_.triVertices);
    extend_.setArg(2, p.queueItems);
    extend_.setArg(3, p.counters);
    extend_.setArg(4, p.rayOrigins);
    extend_.setArg(5, p.rayDirections);
    extend_.setArg(6, p.hitT);
    extend_.setArg(7, p.hitTriangle);
    extend_.setArg(8, p.hitBary);

    shadeEyeLight_.setArg(0, sceneBuffers_.triVertices);
    shadeEyeLight_.setArg(1, sceneBuffers_.triNormals);
    shadeEyeLight_.setArg(2, p.queueItems);
    shadeEyeLight_.setArg(3, p.counters);
    shadeEyeLight_.setArg(4, p.rayDirections);
    shadeEyeLight_.setArg(5, p.hitTriangle);
    shadeEyeLight_.setArg(6, p.hitBary);
    shadeEyeLight_.setArg(7, p.sampleRadiance);

    accumulate_.setArg(0, p.pathPixels);
    accumulate_.setArg(1, p.sampleRadiance);
    accumulate_.setArg(3, framebuffer_);
    accumulate_.setArg(4, p.counters);
}

void Renderer::launch(cl::Kernel& kernel, int items)
{
    try {
        device_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(size_t(items)),
                                           cl::NDRange(localSize_));
    } catch (const cl::Error& e) {
        throw Error("launching kernel " + kernel.getInfo<CL_KERNEL_FUNCTION_NAME>() + " on " + device_.info.name +
                    " failed: " + clErrorName(e.err()));
    }
}

void Renderer::enqueueIteration()
{
    switch (settings_.algorithm) {
    case Algorithm::EyeLight: iterateEyeLight(); break;
    default: throw Error("algorithm '" + algorithmName(settings_.algorithm) + "' is not implemented yet");
    }
    ++iteration_;
}

// One camera sample per pixel, a wavefront of pixels at a time:
// generate → extend → shade_eyelight → accumulate.
void Renderer::iterateEyeLight()
{
    for (int first = 0; first < pixels_; first += paths_.capacity) {
        // Reset the queue counters only; the statistics counters after them run on.
        device_.queue.enqueueFillBuffer(paths_.counters, 0, 0, COUNTER_NONFINITE * sizeof(int));
        generate_.setArg(2, uint32_t(iteration_));
        generate_.setArg(3, first);
        launch(generate_, paths_.capacity);
        launch(extend_, paths_.capacity);
        launch(shadeEyeLight_, paths_.capacity);
        accumulate_.setArg(2, uint32_t(iteration_));
        launch(accumulate_, paths_.capacity);
    }
}

void Renderer::finish() { device_.queue.finish(); }

Image Renderer::image()
{
    std::vector<float> rgba(size_t(pixels_) * 4);
    device_.queue.enqueueReadBuffer(framebuffer_, CL_TRUE, 0, rgba.size() * sizeof(float), rgba.data());
    Image out(settings_.width, settings_.height);
    for (int p = 0; p < pixels_; ++p)
        for (int c = 0; c < 3; ++c) out.rgb[3 * size_t(p) + c] = rgba[4 * size_t(p) + c];
    return out;
}

uint64_t Renderer::nonFiniteCount()
{
    int counters[COUNTER_COUNT];
    device_.queue.enqueueReadBuffer(paths_.counters, CL_TRUE, 0, sizeof counters, counters);
    return uint64_t(uint32_t(counters[COUNTER_NONFINITE]));
}

} // namespace wv
