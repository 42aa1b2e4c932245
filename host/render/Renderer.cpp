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
    device.queue.enqueueFillBuffer(paths_.counters, 0, 0, kCounterBytes);

    std::string source = expandKernelSources(findKernelDir(), kernelFiles(settings.algorithm));
    std::string options = "-cl-std=CL1.2" + scene.features().buildOptions() + (eyeLight ? " -DEYE_LIGHT" : "");
    build_ = buildProgram(device.context, device.info, source, options);

    // One fixed local size: PoCL compiles a work-group function per local
    // size, and local size 1 is several times slower there.
    localSize_ = std::min<size_t>(64, device.info.maxWorkGroupSize);
    profiling_ = (device.queue.getInfo<CL_QUEUE_PROPERTIES>() & CL_QUEUE_PROFILING_ENABLE) != 0;
    const PathState& p = paths_;
    const SceneBuffers& s = sceneBuffers_;
    int capacity = p.capacity;
    generate_ = cl::Kernel(build_.program, "generate");
    setArgs(generate_, camera_, settings.seed, 0u, capacity, 0, 0, 0, 0, 0, p.queueItems, p.counters, p.rayOrigins,
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
        cl::Event event;
        device_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(roundUp(items, localSize_)),
                                           cl::NDRange(localSize_), nullptr, profiling_ ? &event : nullptr);
        if (profiling_) pending_.push_back({kernel.getInfo<CL_KERNEL_FUNCTION_NAME>(), event});
    } catch (const cl::Error& e) {
        throw Error("launching kernel " + kernel.getInfo<CL_KERNEL_FUNCTION_NAME>() + " on " + device_.info.name +
                    " failed: " + clErrorName(e.err()));
    }
}

// One round: `generated` new paths into free slots, then every live path
// (`live` of them at most) advances one segment. Consumes RAYS(parity) and
// FREE(parity), fills the other pair.
void Renderer::round(int parity, size_t generated, size_t issued, size_t rays)
{
    int next = 1 - parity;
    auto counterOffset = [](int c) { return size_t(COUNTER_INDEX(c)) * sizeof(int); };
    auto clearCounters = [&](int first, int count) {
        device_.queue.enqueueFillBuffer(paths_.counters, 0, counterOffset(first), counterOffset(count));
    };
    clearCounters(QUEUE_HITS, 3); // hits, escaped, shadow
    clearCounters(QUEUE_RAYS(next), 2);
    setArgs(generate_, camera_, settings_.seed, uint32_t(iteration_), paths_.capacity, QUEUE_FREE(parity),
            QUEUE_RAYS(parity), int(generated), int(issued), int(rays));
    extend_.setArg(3, QUEUE_RAYS(parity));
    escaped_.setArg(3, QUEUE_FREE(next));
    size_t live = rays + generated;
    launch(generate_, std::max<size_t>(generated, 1)); // item 0 also sets the ray queue's length
    launch(extend_, live);
    if (settings_.algorithm == Algorithm::EyeLight) {
        shade_.setArg(3, QUEUE_FREE(next));
    } else {
        shade_.setArg(12, QUEUE_RAYS(next));
        shade_.setArg(13, QUEUE_FREE(next));
    }
    launch(shade_, live);
    launch(escaped_, live);
    if (settings_.algorithm != Algorithm::EyeLight) launch(connect_, live);
}

void Renderer::iterate()
{
    if (settings_.algorithm != Algorithm::EyeLight) shade_.setArg(9, uint32_t(iteration_));
    // Every slot starts free.
    std::vector<int> counters(COUNTER_INDEX(COUNTER_NONFINITE), 0);
    counters[COUNTER_INDEX(QUEUE_FREE(0))] = paths_.capacity;
    device_.queue.enqueueWriteBuffer(paths_.counters, CL_TRUE, 0, counters.size() * sizeof(int), counters.data());
    device_.queue.enqueueCopyBuffer(paths_.slotIndices, paths_.queueItems, 0,
                                    size_t(QUEUE_FREE(0)) * paths_.capacity * sizeof(int),
                                    size_t(paths_.capacity) * sizeof(int));
    // The host reads the counters once per round, to size the next round's
    // launches (OpenCL 1.2 has no indirect dispatch) and to see when the
    // iteration is over. Launching over the full capacity instead, with
    // kernels returning past their queue's size, cost more on PoCL than the
    // ~70 µs synchronisation: most rounds have few live paths.
    size_t rays = 0, free = size_t(paths_.capacity), issued = 0;
    std::vector<int> now(COUNTER_INDEX(COUNTER_COUNT));
    for (int parity = 0;; parity = 1 - parity) {
        size_t generated = std::min(free, size_t(pixels_) - issued);
        if (rays + generated == 0) break;
        round(parity, generated, issued, rays);
        issued += generated;
        rays_ += rays + generated;
        device_.queue.enqueueReadBuffer(paths_.counters, CL_TRUE, 0, now.size() * sizeof(int), now.data());
        rays = size_t(now[COUNTER_INDEX(QUEUE_RAYS(1 - parity))]);
        free = size_t(now[COUNTER_INDEX(QUEUE_FREE(1 - parity))]);
        rays_ += size_t(now[COUNTER_INDEX(QUEUE_SHADOW)]);
    }
    accumulate_.setArg(2, uint32_t(iteration_));
    launch(accumulate_, size_t(pixels_));
    device_.queue.finish();
    if (profiling_) collectProfile();
    ++iteration_;
}

void Renderer::collectProfile()
{
    for (auto& [name, event] : pending_) {
        cl_ulong start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
        cl_ulong end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        kernelSeconds_[name] += double(end - start) * 1e-9;
    }
    pending_.clear();
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
    int count = 0;
    device_.queue.enqueueReadBuffer(paths_.counters, CL_TRUE, size_t(COUNTER_INDEX(COUNTER_NONFINITE)) * sizeof(int),
                                    sizeof count, &count);
    return uint64_t(uint32_t(count));
}

} // namespace wv
