#include "Renderer.h"

#include "../../kernels/interface/queue_ids.h"
#include "../Error.h"

#include <algorithm>
#include <cmath>

namespace wv {

std::vector<std::string> Renderer::kernelFiles(Algorithm algorithm)
{
    std::vector<std::string> stages;
    switch (algorithm) {
    case Algorithm::EyeLight:
        stages = {"generate", "extend", "shade_eyelight", "escaped", "accumulate"};
        break;
    case Algorithm::PathTracing:
        stages = {"generate", "extend", "shade", "escaped", "connect", "accumulate"};
        break;
    default:
        stages = {"generate", "extend",  "shade_light", "hash_grid", "connect_vertices", "merge", "shade_bidirectional",
                  "escaped",  "connect", "accumulate"};
    }
    for (std::string& s : stages) s = "stages/" + s + ".cl";
    return stages;
}

std::string Renderer::programOptions(Algorithm algorithm, const SceneFeatures& features, int lightCount)
{
    bool bidirectional = algorithm != Algorithm::EyeLight && algorithm != Algorithm::PathTracing;
    bool mergingOnly =
        algorithm == Algorithm::ProgressivePhotonMapping || algorithm == Algorithm::BidirectionalPhotonMapping;
    std::string options = "-cl-std=CL1.2" + features.buildOptions() + lightSelectOption(lightCount);
    if (algorithm == Algorithm::EyeLight) options += " -DEYE_LIGHT";
    if (bidirectional) options += " -DBIDIRECTIONAL";
    if (algorithm == Algorithm::LightTracing) options += " -DLIGHT_TRACING";
    if (mergingOnly) options += " -DVERTEX_MERGING_ONLY";
    if (algorithm == Algorithm::ProgressivePhotonMapping) options += " -DPPM";
    return options;
}

// The binary search of light selection as a fixed number of steps
// (kernels/lights/lights.h): the bits of the largest light index, rounded up
// to a multiple of 4, so that scenes whose light counts differ a little share
// one program and its cache entries; a step costs a few instructions, where
// the 31 steps that cover any table cost shade 3-5 % of its rate.
std::string lightSelectOption(int lightCount)
{
    int steps = 0;
    while (steps < 31 && (1 << steps) < lightCount) ++steps;
    steps = std::min(31, (steps + 3) / 4 * 4);
    return " -DLIGHT_SELECT_STEPS=" + std::to_string(steps);
}

int defaultWavefront(const DeviceInfo& device)
{
    size_t wanted = (device.type & CL_DEVICE_TYPE_GPU) ? (size_t(1) << 21) : (size_t(1) << 18);
    size_t fits = device.globalMemory / 4 / PathState::bytesPerPath();
    return int(std::max<size_t>(1024, std::min(wanted, fits)));
}

static size_t roundUp(size_t x, size_t multiple) { return (x + multiple - 1) / multiple * multiple; }

static PathState makePathState(DeviceContext& device, const RenderSettings& s, KernelBuffers& buffers)
{
    int wavefront = s.wavefront > 0 ? s.wavefront : defaultWavefront(device.info);
    // Launches cover queue sizes in work-groups of 64, so the capacity is a
    // multiple of 64, and no larger than one iteration needs.
    wavefront = std::min(wavefront, s.width * s.height);
    return PathState(device, int(roundUp(size_t(wavefront), 64)), buffers);
}

Renderer::Renderer(DeviceContext& device, const Scene& scene, const Bvh& bvh, const RenderSettings& settings)
    : device_(device), settings_(settings), lights_(buildLightTable(scene, bvh)),
      sceneBuffers_(device, scene, bvh, lights_), paths_(makePathState(device, settings, buffers_))
{
    Algorithm algorithm = settings.algorithm;
    bidirectional_ = algorithm != Algorithm::EyeLight && algorithm != Algorithm::PathTracing;
    // Which techniques the bidirectional algorithms combine (SmallVCM's useVC/useVM).
    useVC_ = algorithm == Algorithm::Bidirectional || algorithm == Algorithm::VertexConnectionMerging;
    useVM_ = algorithm == Algorithm::ProgressivePhotonMapping || algorithm == Algorithm::BidirectionalPhotonMapping ||
             algorithm == Algorithm::VertexConnectionMerging;
    bool lightTracing = algorithm == Algorithm::LightTracing;
    sceneRadius_ = lights_.info.radius;
    pixels_ = settings.width * settings.height;

    KernelBuffers& b = buffers_;
    sceneBuffers_.bind(b);
    Camera camera = makeCamera(scene.camera, settings.width, settings.height);
    b.camera = uploadBuffer(device, &camera, sizeof camera, "the camera");
    size_t imageBytes = size_t(pixels_) * 16;
    b.pixelRadiance = deviceBuffer(device, imageBytes, "the iteration's radiance");
    b.connectionRadiance = deviceBuffer(device, imageBytes, "the iteration's radiance");
    b.mergingRadiance = deviceBuffer(device, imageBytes, "the iteration's radiance");
    b.splatRadiance = deviceBuffer(device, imageBytes, "the light-tracing splats");
    b.framebuffer = deviceBuffer(device, imageBytes, "the framebuffer");
    for (cl::Buffer* i : {&b.pixelRadiance, &b.connectionRadiance, &b.mergingRadiance, &b.splatRadiance,
                          &b.framebuffer})
        device.queue.enqueueFillBuffer(*i, 0.0f, 0, imageBytes);
    if (settings.techniques) {
        b.familyMeans = deviceBuffer(device, 3 * imageBytes, "the technique images");
        device.queue.enqueueFillBuffer(b.familyMeans, 0.0f, 0, 3 * imageBytes);
    }
    device.queue.enqueueFillBuffer(b.queueCounters, 0, 0, kCounterBytes);

    std::string source = expandKernelSources(findKernelDir(), kernelFiles(algorithm));
    build_ = buildProgram(device.context, device.info, source,
                          programOptions(algorithm, scene.features(), lights_.info.lightCount));

    // One fixed local size: PoCL compiles a work-group function per local
    // size, and local size 1 is several times slower there.
    localSize_ = std::min<size_t>(64, device.info.maxWorkGroupSize);
    profiling_ = (device.queue.getInfo<CL_QUEUE_PROPERTIES>() & CL_QUEUE_PROFILING_ENABLE) != 0;

    // What holds for the whole render; the rest is set per batch
    // (setBatchConstants) and per round.
    params_.capacity = paths_.capacity;
    params_.seed = settings.seed;
    params_.maxPathLength = settings.maxPathLength;
    params_.lightTracePaths = float(pixels_); // light paths per iteration
    params_.pixels = pixels_;
    params_.techniques = settings.techniques ? 1 : 0;
    params_.storeVertices = useVC_ || useVM_ ? 1 : 0;

    // Camera sub-paths.
    Phase& c = cameraPhase_;
    c.cameraPaths = true;
    c.generate = kernel("generate");
    c.extend = kernel("extend");
    c.escaped = kernel("escaped");
    c.shade = kernel(algorithm == Algorithm::EyeLight      ? "shade_eyelight"
                     : algorithm == Algorithm::PathTracing ? "shade"
                                                           : "shade_bidirectional");
    if (algorithm == Algorithm::PathTracing || useVC_) {
        c.connect = kernel("connect");
        c.hasConnect = true;
    }
    accumulate_ = kernel("accumulate");
    if (bidirectional_) {
        // Light sub-paths, and the light vertices camera paths connect to.
        batch_ = pixels_;
        b.lightPathHead = deviceBuffer(device, size_t(pixels_) * sizeof(int), "the light path heads");
        size_t bytesPerVertex = sizeof(LightVertex) + (useVM_ ? HashGrid::kBytesPerVertex : 0);
        vertexBudget_ = std::min<size_t>(device.info.maxAllocation / sizeof(LightVertex),
                                         device.info.globalMemory / 2 / bytesPerVertex);
        if (settings.maxLightVertices > 0) vertexBudget_ = std::min(vertexBudget_, settings.maxLightVertices);
        Phase& l = lightPhase_;
        l.generate = kernel("generate_light");
        l.extend = kernel("extend");
        l.shade = kernel("shade_light");
        l.escaped = kernel("escaped");
        l.connect = kernel("connect_splat");
        l.hasConnect = lightTracing || useVC_;
        if (useVC_) {
            c.connectVertices = kernel("connect_vertices");
            c.hasConnectVertices = true;
        }
        if (useVM_) {
            c.merge = kernel("merge");
            c.hasMerge = true;
            grid_ = std::make_unique<HashGrid>(device, build_.program);
        }
        if (params_.storeVertices) ensureLightVertexCapacity(size_t(pixels_) * 2);
    }
    bindAll();
}

cl::Kernel Renderer::kernel(const char* name)
{
    cl::Kernel k(build_.program, name);
    kernels_.push_back(k);
    return k;
}

// Every render kernel gets the current buffers; called when one is replaced.
void Renderer::bindAll()
{
    for (cl::Kernel& k : kernels_) bindBuffers(k, buffers_);
}

size_t Renderer::deviceBytes() const
{
    return sceneBuffers_.bytes + paths_.bytes + size_t(pixels_) * (settings_.techniques ? 128 : 80) +
           (bidirectional_ ? vertexCapacity_ * sizeof(LightVertex) + size_t(pixels_) * sizeof(int) : 0) +
           (grid_ ? vertexCapacity_ * HashGrid::kBytesPerVertex : 0);
}

// Makes room for at least `vertices` light vertices (80 bytes each), within
// the device's limits; the kernels that write and read them get the new buffer.
void Renderer::ensureLightVertexCapacity(size_t vertices)
{
    vertices = std::min(vertices, vertexBudget_);
    if (vertices <= vertexCapacity_ && buffers_.lightVertices()) return;
    vertexCapacity_ = vertices;
    buffers_.lightVertices = deviceBuffer(device_, vertexCapacity_ * sizeof(LightVertex), "the light vertices");
    params_.vertexCapacity = int(vertexCapacity_);
    if (grid_) {
        grid_->reserve(vertexCapacity_);
        buffers_.bucketStarts = grid_->bucketStarts();
        buffers_.bucketVertices = grid_->bucketVertices();
        params_.cellCount = grid_->buckets();
    }
    bindAll();
}

// Per batch: the merge radius of this iteration and the MIS constants that
// depend on it (Georgiev's report, eq. 20): η_VCM = π r² N_light, the VM
// weight factor η_VCM, the VC weight factor 1/η_VCM, and merging's
// normalisation 1/(π r² N_light), N_light the light paths whose vertices
// are in the grid. The techniques an algorithm lacks get factor 0.
void Renderer::setBatchConstants(int lightPaths)
{
    float r1 = settings_.radiusFactor * sceneRadius_;
    radius_ = useVM_ ? std::max(r1 * std::pow(float(index_ + 1), 0.5f * (settings_.radiusAlpha - 1.0f)),
                                1e-7f * sceneRadius_)
                     : 0.0f;
    float eta = float(M_PI) * radius_ * radius_ * float(lightPaths);
    params_.mergeRadius = radius_;
    params_.vmWeightFactor = useVM_ ? eta : 0.0f;
    params_.vcWeightFactor = useVM_ && useVC_ ? 1.0f / eta : 0.0f;
    params_.vmNormalization = useVM_ ? 1.0f / eta : 0.0f;
}

int Renderer::lightVertexCount()
{
    int count = 0;
    device_.queue.enqueueReadBuffer(buffers_.queueCounters, CL_TRUE,
                                    size_t(COUNTER_INDEX(COUNTER_LIGHT_VERTICES)) * sizeof(int), sizeof count, &count);
    return count;
}

void Renderer::buildHashGrid()
{
    grid_->build(buffers_.lightVertices, int(std::min(size_t(lightVertexCount()), vertexCapacity_)), radius_);
}

void Renderer::launch(cl::Kernel& kernel, size_t items)
{
    try {
        setLaunchParams(kernel, params_);
        cl::Event event;
        device_.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(roundUp(items, localSize_)),
                                           cl::NDRange(localSize_), nullptr, profiling_ ? &event : nullptr);
        if (profiling_) pending_.push_back({kernel.getInfo<CL_KERNEL_FUNCTION_NAME>(), items, event});
    } catch (const cl::Error& e) {
        throw Error("launching kernel " + kernel.getInfo<CL_KERNEL_FUNCTION_NAME>() + " on " + device_.info.name +
                    " failed: " + clErrorName(e.err()));
    }
}

// One round: `generated` new paths into free slots, then every live path
// (`rays` continuing ones plus the new ones) advances one segment. Consumes
// RAYS(parity) and FREE(parity), fills the other pair.
void Renderer::round(Phase& phase, int parity, size_t generated, size_t issued, size_t rays)
{
    int next = 1 - parity;
    auto counterOffset = [](int c) { return size_t(COUNTER_INDEX(c)) * sizeof(int); };
    auto clearCounters = [&](int first, int count) {
        device_.queue.enqueueFillBuffer(buffers_.queueCounters, 0, counterOffset(first), counterOffset(count));
    };
    clearCounters(QUEUE_HITS, 3); // hits, escaped, shadow
    clearCounters(QUEUE_RAYS(next), 2);
    params_.rayQueue = QUEUE_RAYS(parity);
    params_.freeQueue = QUEUE_FREE(parity);
    params_.nextRayQueue = QUEUE_RAYS(next);
    params_.nextFreeQueue = QUEUE_FREE(next);
    params_.generateCount = int(generated);
    params_.firstSample = int(issued);
    params_.rayQueueLength = int(rays);
    size_t live = rays + generated;
    launch(phase.generate, std::max<size_t>(generated, 1)); // item 0 also sets the ray queue's length
    launch(phase.extend, live);
    if (phase.hasConnectVertices) launch(phase.connectVertices, live);
    if (phase.hasMerge) launch(phase.merge, live);
    launch(phase.shade, live);
    launch(phase.escaped, live);
    if (phase.hasConnect) launch(phase.connect, live);
}

// Runs paths for samples [firstSample, firstSample + count) to completion.
// The host reads the counters once per round, to size the next round's
// launches (OpenCL 1.2 has no indirect dispatch) and to see when the phase is
// over. Launching over the full capacity instead, with kernels returning past
// their queue's size, cost more on PoCL than the ~70 µs synchronisation:
// most rounds have few live paths.
bool Renderer::runPhase(Phase& phase, int firstSample, int count)
{
    params_.cameraPaths = phase.cameraPaths ? 1 : 0;
    // Every slot starts free.
    std::vector<int> counters(COUNTER_INDEX(COUNTER_LIGHT_VERTICES), 0);
    counters[COUNTER_INDEX(QUEUE_FREE(0))] = paths_.capacity;
    device_.queue.enqueueWriteBuffer(buffers_.queueCounters, CL_TRUE, 0, counters.size() * sizeof(int),
                                     counters.data());
    device_.queue.enqueueCopyBuffer(paths_.slotIndices, buffers_.queueItems, 0,
                                    size_t(QUEUE_FREE(0)) * paths_.capacity * sizeof(int),
                                    size_t(paths_.capacity) * sizeof(int));
    size_t rays = 0, free = size_t(paths_.capacity), issued = 0;
    std::vector<int> now(COUNTER_INDEX(COUNTER_COUNT));
    for (int parity = 0;; parity = 1 - parity) {
        size_t generated = std::min(free, size_t(count) - issued);
        if (rays + generated == 0) break;
        round(phase, parity, generated, size_t(firstSample) + issued, rays);
        issued += generated;
        rays_ += rays + generated;
        device_.queue.enqueueReadBuffer(buffers_.queueCounters, CL_TRUE, 0, now.size() * sizeof(int), now.data());
        rays = size_t(now[COUNTER_INDEX(QUEUE_RAYS(1 - parity))]);
        free = size_t(now[COUNTER_INDEX(QUEUE_FREE(1 - parity))]);
        rays_ += size_t(now[COUNTER_INDEX(QUEUE_SHADOW)]);
        if (abandon_ && abandon_()) return false;
    }
    return true;
}

// The bidirectional algorithms' iteration: light paths go in batches of
// batch_ whose vertices fit on the device; camera paths [first, first +
// count) then connect to the light path of their own index and merge with
// the batch's. The last batch holds batch_ light paths too, starting before
// `first` (it retraces some of the batch before it; light path i is the same
// in any batch): so N_light, and η_VCM = π r² N_light with it, is the same
// for every camera path, as the weights of light tracing's splats, which land
// on any pixel, need. Each light path splats once: those below `splatted`
// have. Restart when the batch had to shrink after camera paths were shaded
// with the larger one's η: the iteration starts again.
Renderer::Batches Renderer::renderBatches()
{
    bool splats = settings_.algorithm == Algorithm::LightTracing || useVC_;
    int splatted = splats ? 0 : pixels_;
    for (int first = 0; first < pixels_;) {
        int count = 0, lightFirst = 0, lightCount = 0;
        auto placeBatch = [&] {
            count = std::min(batch_, pixels_ - first);
            lightFirst = std::max(0, std::min(first, pixels_ - batch_));
            lightCount = std::min(batch_, pixels_ - lightFirst);
        };
        placeBatch();
        for (;;) {
            params_.firstLightPath = lightFirst;
            params_.firstSplatPath = splatted;
            setBatchConstants(lightCount);
            int zero = 0;
            device_.queue.enqueueWriteBuffer(buffers_.queueCounters, CL_TRUE,
                                             size_t(COUNTER_INDEX(COUNTER_LIGHT_VERTICES)) * sizeof(int),
                                             sizeof zero, &zero);
            if (!runPhase(lightPhase_, lightFirst, lightCount)) return Batches::Abandoned;
            splatted = std::max(splatted, lightFirst + lightCount);
            size_t wanted = params_.storeVertices ? size_t(lightVertexCount()) : 0;
            if (wanted <= vertexCapacity_) break;
            if (wanted <= vertexBudget_) {
                ensureLightVertexCapacity(wanted + wanted / 4);
                continue;
            }
            if (lightCount == 1)
                throw Error("the light vertices of a single light path do not fit on " + device_.info.name);
            batch_ = lightCount / 2;
            if (first > 0) return Batches::Restart;
            placeBatch();
        }
        if (useVM_) buildHashGrid();
        if (!runPhase(cameraPhase_, first, count)) return Batches::Abandoned;
        first += count;
    }
    return Batches::Done;
}

bool Renderer::iterate(int index, const std::function<bool()>& abandon)
{
    index_ = index;
    params_.iteration = uint32_t(index);
    params_.accumulated = iteration_;
    abandon_ = abandon;
    // This iteration's contributions so far, before accumulate folds them in.
    auto clearRadiance = [&] {
        size_t bytes = size_t(pixels_) * 16;
        for (cl::Buffer* b : {&buffers_.pixelRadiance, &buffers_.connectionRadiance, &buffers_.mergingRadiance,
                              &buffers_.splatRadiance})
            device_.queue.enqueueFillBuffer(*b, 0.0f, 0, bytes);
    };
    Batches done = Batches::Done;
    if (!bidirectional_) {
        done = runPhase(cameraPhase_, 0, pixels_) ? Batches::Done : Batches::Abandoned;
    } else {
        while ((done = renderBatches()) == Batches::Restart) {
            ++restartedIterations_;
            clearRadiance();
        }
    }
    abandon_ = nullptr;
    if (done == Batches::Abandoned) {
        clearRadiance(); // the running means keep the iterations before it
        device_.queue.finish();
        if (profiling_) collectProfile();
        return false;
    }
    launch(accumulate_, size_t(pixels_));
    device_.queue.finish();
    if (profiling_) collectProfile();
    ++iteration_;
    return true;
}

void Renderer::collectProfile()
{
    for (PendingLaunch& launch : pending_) {
        cl_ulong start = launch.event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
        cl_ulong end = launch.event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        KernelStats& stats = kernelStats_[launch.kernel];
        stats.seconds += double(end - start) * 1e-9;
        stats.items += launch.items;
    }
    pending_.clear();
}

std::array<Image, 3> Renderer::techniqueImages()
{
    std::array<Image, 3> out;
    if (!settings_.techniques) return out;
    std::vector<float> rgba(size_t(pixels_) * 12);
    device_.queue.enqueueReadBuffer(buffers_.familyMeans, CL_TRUE, 0, rgba.size() * sizeof(float), rgba.data());
    for (int f = 0; f < 3; ++f) {
        out[f] = Image(settings_.width, settings_.height);
        for (int p = 0; p < pixels_; ++p)
            for (int c = 0; c < 3; ++c) out[f].rgb[3 * size_t(p) + c] = rgba[(3 * size_t(p) + f) * 4 + c];
    }
    return out;
}

Image Renderer::image()
{
    std::vector<float> rgba(size_t(pixels_) * 4);
    device_.queue.enqueueReadBuffer(buffers_.framebuffer, CL_TRUE, 0, rgba.size() * sizeof(float), rgba.data());
    Image out(settings_.width, settings_.height);
    for (int p = 0; p < pixels_; ++p)
        for (int c = 0; c < 3; ++c) out.rgb[3 * size_t(p) + c] = rgba[4 * size_t(p) + c];
    return out;
}

uint64_t Renderer::nonFiniteCount()
{
    int count = 0;
    device_.queue.enqueueReadBuffer(buffers_.queueCounters, CL_TRUE,
                                    size_t(COUNTER_INDEX(COUNTER_NONFINITE)) * sizeof(int),
                                    sizeof count, &count);
    return uint64_t(uint32_t(count));
}

} // namespace wv
