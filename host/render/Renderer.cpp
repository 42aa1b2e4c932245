#include "Renderer.h"

#include "../../kernels/queue_ids.h"
#include "../Error.h"

#include <algorithm>

namespace wv {

std::vector<std::string> Renderer::kernelFiles(Algorithm algorithm)
{
    if (algorithm == Algorithm::EyeLight)
        return {"generate.cl", "extend.cl", "shade_eyelight.cl", "escaped.cl", "accumulate.cl"};
    return {"generate.cl", "extend.cl", "shade.cl", "escaped.cl", "connect.cl", "accumulate.cl"};
}

int defaultWavefront(const DeviceInfo& device)
{
    size_t wanted = (device.type & CL_DEVICE_TYPE_GPU) ? (size_t(1) << 21) : (size_t(1) << 18);
    size_t fits = device.globalMemory / 4 / PathState::bytesPerPath();
    return int(std::max<size_t>(1024, std::min(wanted, fits)));
}

static size_t roundUp(size_t x, size_t multiple) { return (x + multiple - 1) / multiple * multiple; }

static PathState makePathState(DeviceContext& device, const RenderSettings& s)
{
    int wavefront = s.wavefront > 0 ? s.wavefront : defaultWavefront(device.info);
    // Launches cover the whole capacity in work-groups of 64 (kernels return
    // past a queue's size), so the capacity is a multiple of 64 and no larger
    // than one iteration needs.
    wavefront = std::min(wavefront, s.width * s.height);
    return PathState(device, int(roundUp(size_t(wavefront), 64)));
}

template <typename... Args> static void setArgs(cl::Kernel& kernel, const Args&... args)
{
    cl_uint index = 0;
    (kernel.setArg(index++, args), ...);
}

Renderer::Renderer(DeviceContext& device, const Scene& scene, const Bvh& bvh, const RenderSettings& settings)
    : device_(device), settings_(settings), lights_(buildLightTable(scene, bvh)),
      sceneBuffers_(device, scene, bvh, lights_), paths_(makePathState(device, settings))
{
    if (!isImplemented(settings.algorithm))
        throw Error("algorithm '" + algorithmName(settings.algorithm) + "' is not implemented yet");
    bool eyeLight = settings.algorithm == Algorithm::EyeLight;
    pixels_ = settings.width * settings.height;
    Camera camera = makeCamera(scene.camera, settings.width, settings.height);
    camera_ = uploadBuffer(device, &camera, sizeof camera, "the camera");
    size_t imageBytes = size_t(pixels_) * 16;
    pixelRadiance_ = deviceBuffer(device, imageBytes, "the iteration's radiance");
    framebuffer_ = deviceBuffer(device, imageBytes, "the framebuffer");
    device.queue.enqueueFillBuffer(pixelRadiance_, 0.0f, 0, imageBytes);
    device.queue.enqueueFillBuffer(framebuffer_, 0.0f, 0, imageBytes);
    device.queue.enqueueFillBuffer(paths_.counters, 0, 0, COUNTER_COUNT * sizeof(int));

    std::string source = expandKernelSources(findKernelDir(), kernelFiles(settings.algorithm));
    std::string options = "-cl-std=CL1.2" + scene.features().buildOptions() + (eyeLight ? " -DEYE_LIGHT" : "");
    build_ = buildProgram(device.context, device.info, source, options);

    // One fixed local size: PoCL compiles a work-group function per local
    // size, and local size 1 is several times slower there.
    localSize_ = std::min<size_t>(64, device.info.maxWorkGroupSize);
    const PathState& p = paths_;
    const SceneBuffers& s = sceneBuffers_;
    int capacity = p.capacity;
    generate_ = cl::Kernel(build_.program, "generate");
    setArgs(generate_, camera_, settings.seed, 0u, capacity, 0, 0, p.queueItems, p.counters, p.rayOrigins,
            p.rayDirections, p.pathPixel, p.pathDepth, p.pathThroughput, p.pathPrevPdf);
    extend_ = cl::Kernel(build_.program, "extend");
    setArgs(extend_, s.nodes, s.triVertices, capacity, 0, p.queueItems, p.counters, p.rayOrigins, p.rayDirections,
            p.hitT, p.hitTriangle, p.hitBary);
    escaped_ = cl::Kernel(build_.program, "escaped");
    setArgs(escaped_, s.lights, s.sceneInfo, capacity, 0, p.queueItems, p.counters, p.pathPixel, p.pathThroughput,
            p.pathPrevPdf, pixelRadiance_);
    accumulate_ = cl::Kernel(build_.program, "accumulate");
    setArgs(accumulate_, pixelRadiance_, pixels_, 0u, framebuffer_, p.counters);
    if (eyeLight) {
        shade_ = cl::Kernel(build_.program, "shade_eyelight");
        setArgs(shade_, s.triVertices, s.triNormals, capacity, 0, p.queueItems, p.counters, p.rayDirections,
                p.hitTriangle, p.hitBary, p.pathPixel, pixelRadiance_);
    } else {
        shade_ = cl::Kernel(build_.program, "shade");
        setArgs(shade_, s.triVertices, s.triNormals, s.triMaterials, s.materials, s.lights, s.lightCdf,
                s.triangleLight, s.sceneInfo, settings.seed, 0u, settings.maxPathLength, capacity, 0, 0,
                p.queueItems, p.counters, p.rayOrigins, p.rayDirections, p.hitT, p.hitTriangle, p.hitBary,
                p.pathPixel, p.pathDepth, p.pathThroughput, p.pathPrevPdf, p.shadowOrigins, p.shadowDirections,
                p.shadowContribution, pixelRadiance_);
        connect_ = cl::Kernel(build_.program, "connect");
        setArgs(connect_, s.nodes, s.triVertices, capacity, p.queueItems, p.counters, p.shadowOrigins,
                p.shadowDirections, p.shadowContribution, p.pathPixel, pixelRadiance_);
    }
}

void Renderer::launch(cl::Kernel& kernel, size_t items)
{
    try {
        device_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(roundUp(items, localSize_)),
                                           cl::NDRange(localSize_));
    } catch (const cl::Error& e) {
        throw Error("launching kernel " + kernel.getInfo<CL_KERNEL_FUNCTION_NAME>() + " on " + device_.info.name +
                    " failed: " + clErrorName(e.err()));
    }
}

// One round: new paths into free slots, then every live path advances one
// segment. Consumes RAYS(parity) and FREE(parity), fills the other pair.
void Renderer::round(int parity)
{
    int next = 1 - parity;
    device_.queue.enqueueFillBuffer(paths_.counters, 0, 0, 3 * sizeof(int)); // hits, escaped, shadow
    device_.queue.enqueueFillBuffer(paths_.counters, 0, QUEUE_RAYS(next) * sizeof(int), 2 * sizeof(int));
    generate_.setArg(4, QUEUE_FREE(parity));
    generate_.setArg(5, QUEUE_RAYS(parity));
    extend_.setArg(3, QUEUE_RAYS(parity));
    escaped_.setArg(3, QUEUE_FREE(next));
    size_t capacity = size_t(paths_.capacity);
    launch(generate_, capacity);
    launch(extend_, capacity);
    if (settings_.algorithm == Algorithm::EyeLight) {
        shade_.setArg(3, QUEUE_FREE(next));
        launch(shade_, capacity);
        launch(escaped_, capacity);
    } else {
        shade_.setArg(12, QUEUE_RAYS(next));
        shade_.setArg(13, QUEUE_FREE(next));
        launch(shade_, capacity);
        launch(escaped_, capacity);
        launch(connect_, capacity);
    }
}

void Renderer::iterate()
{
    generate_.setArg(2, uint32_t(iteration_));
    if (settings_.algorithm != Algorithm::EyeLight) shade_.setArg(9, uint32_t(iteration_));
    // Every slot starts free; no sample handed out yet.
    int counters[COUNTER_NONFINITE] = {};
    counters[QUEUE_FREE(0)] = paths_.capacity;
    device_.queue.enqueueWriteBuffer(paths_.counters, CL_TRUE, 0, sizeof counters, counters);
    device_.queue.enqueueCopyBuffer(paths_.slotIndices, paths_.queueItems, 0,
                                    size_t(QUEUE_FREE(0)) * paths_.capacity * sizeof(int),
                                    size_t(paths_.capacity) * sizeof(int));
    // The host reads the counters back only to decide when the iteration is
    // over (no rays left, every sample handed out), every second round: a
    // read costs a device synchronisation (~70 µs on PoCL, more on GPUs),
    // an extra round with empty queues only its launches.
    int parity = 0;
    for (int r = 1;; ++r) {
        round(parity);
        parity = 1 - parity;
        if (r % 2 != 0) continue;
        int now[COUNTER_COUNT];
        device_.queue.enqueueReadBuffer(paths_.counters, CL_TRUE, 0, sizeof now, now);
        if (now[QUEUE_RAYS(parity)] == 0 && now[COUNTER_NEXT_SAMPLE] >= pixels_) {
            // The counters are reset per iteration, so 32 bits suffice.
            rays_ += uint64_t(uint32_t(now[COUNTER_RAYS])) + uint64_t(uint32_t(now[COUNTER_SHADOW_RAYS]));
            break;
        }
    }
    accumulate_.setArg(2, uint32_t(iteration_));
    launch(accumulate_, size_t(pixels_));
    device_.queue.finish();
    ++iteration_;
}

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
