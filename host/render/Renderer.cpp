#include "Renderer.h"

#include "../../kernels/interface/queue_ids.h"
#include "../Error.h"
#include "../cl/PoclVectorizer.h"

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

bool Renderer::usesConnectionQueue(const RenderSettings& settings, const DeviceInfo& device)
{
    if (settings.algorithm != Algorithm::Bidirectional && settings.algorithm != Algorithm::VertexConnectionMerging)
        return false;
    if (settings.vertexConnections == VertexConnections::Default) return (device.type & CL_DEVICE_TYPE_GPU) != 0;
    return settings.vertexConnections == VertexConnections::Queued;
}

std::string Renderer::programOptions(Algorithm algorithm, const SceneFeatures& features, int lightCount,
                                     bool connectionQueue)
{
    bool bidirectional = algorithm != Algorithm::EyeLight && algorithm != Algorithm::PathTracing;
    bool mergingOnly =
        algorithm == Algorithm::ProgressivePhotonMapping || algorithm == Algorithm::BidirectionalPhotonMapping;
    std::string options = "-cl-std=CL1.2" + features.buildOptions() + lightSelectOption(lightCount);
    if (algorithm == Algorithm::EyeLight) options += " -DEYE_LIGHT";
    if (bidirectional) options += " -DBIDIRECTIONAL";
    if (algorithm == Algorithm::LightTracing) options += " -DLIGHT_TRACING";
    if (mergingOnly) options += " -DVERTEX_MERGING_ONLY";
    if (bidirectional && !mergingOnly && algorithm != Algorithm::LightTracing) options += " -DVERTEX_CONNECTION";
    if (algorithm == Algorithm::ProgressivePhotonMapping) options += " -DPPM";
    if (connectionQueue) options += " -DCONNECTION_QUEUE";
    options += " -DHOST_STRUCT_LAYOUT=" + std::to_string(STRUCT_LAYOUT) + "u";
    return options;
}

std::string Renderer::deviceOptions(const DeviceInfo& device, const SceneFeatures& features, Algorithm algorithm)
{
    // Work-items in SIMD (kernels/core/simd.h) where PoCL's LLVM takes the options (cl/PoclVectorizer.h):
    // generate, generate_light and shade_eyelight always; the shade kernels with AVX-512 only, and there
    // by what was measured (Intel AVX-512, docs/performance.md, "Vectorization on PoCL"). A vectorized
    // loop runs every branch for every lane, so each hit pays for every lobe and every outcome in the
    // program, where one work-item at a time skips to the end of the cheap ones. In scenes with a GGX
    // lobe (the caustics scene, the textured room): shade_light ran 0.55-0.83x as fast in SIMD;
    // shade_bidirectional 1.08-1.34x under vcm and bpt but 0.75-0.85x under ppm, whose camera paths end
    // at their first non-delta hit; pt's shade 1.09x. Without GGX all gain. lt's camera paths do next to
    // nothing (in SIMD, while its scalar shade_light also lost its per-item pushes, lt ran 0.95-0.96x).
    bool simdShading = vectorizesShading(device);
    // The coat's GGX lobe and the sheen (a table lookup and a pow per evaluation) are taken to cost as
    // GGX does; not measured separately.
    bool glossy = (features.lobes & (LOBE_GGX_REFLECTION | LOBE_GGX_TRANSMISSION | LOBE_GGX_COAT | LOBE_SHEEN)) != 0;
    bool cameraWork = algorithm != Algorithm::ProgressivePhotonMapping && algorithm != Algorithm::LightTracing;
    bool simdCamera = simdShading && (!glossy || cameraWork);
    bool simdLight = simdShading && !glossy;
    // kernels/core/queues.h, pushes_per_item: where the device has one compute unit, the kernels that run
    // one work-item at a time push by an atomic per item, there cheaper than the work-group's barriers
    // (PoCL may still run its groups on other threads: atomics); SIMD kernels through the group. Also on
    // rusticl's llvmpipe, which runs a kernel with barriers as coroutines: there per-item pushes made pt and
    // vcm 1.03-1.11x as fast (128x128, three interleaved pairs each, AMD EPYC).
    bool cpu = (device.type & CL_DEVICE_TYPE_CPU) != 0;
    bool perItem = cpu && (device.computeUnits == 1 || device.isRusticl());
    return std::string(simdCamera ? " -DSIMD_CAMERA_SHADING=1" : "") + (simdLight ? " -DSIMD_LIGHT_SHADING=1" : "") +
           (perItem ? " -DPUSH_PER_ITEM" : "") + llvmOptionsKey();
}

// The light selection's binary search as a fixed number of steps
// (kernels/lights/lights.h, binarySearchSteps).
std::string lightSelectOption(int lightCount)
{
    return " -DLIGHT_SELECT_STEPS=" + std::to_string(binarySearchSteps(lightCount));
}

int defaultWavefront(const DeviceInfo& device)
{
    size_t wanted = (device.type & CL_DEVICE_TYPE_GPU) ? (size_t(1) << 21) : (size_t(1) << 18);
    size_t fits = device.globalMemory / 4 / PathState::bytesPerPath();
    return int(std::max<size_t>(1024, std::min(wanted, fits)));
}

// A connection queue entry: its ray's origin and direction, its contribution.
constexpr size_t kBytesPerConnection = 3 * sizeof(cl_float4);

static size_t roundUp(size_t x, size_t multiple) { return (x + multiple - 1) / multiple * multiple; }

static PathState makePathState(DeviceContext& device, const RenderSettings& s, KernelBuffers& buffers)
{
    int wavefront = s.wavefront > 0 ? s.wavefront : defaultWavefront(device.info);
    // Launches cover queue sizes in work-groups of 64, so the capacity is a
    // multiple of 64, and no larger than one iteration needs.
    wavefront = int(std::min<int64_t>(wavefront, int64_t(s.width) * s.height * s.samplesPerIteration));
    return PathState(device, int(roundUp(size_t(wavefront), 64)), buffers);
}

Renderer::Renderer(DeviceContext& device, const Scene& scene, const Bvh& bvh, const RenderSettings& settings)
    : device_(device), settings_(settings), lights_(buildLightTable(scene, bvh)),
      sceneBuffers_(device, scene, bvh, lights_), paths_(makePathState(device, settings, buffers_))
{
    Algorithm algorithm = settings.algorithm;
    bidirectional_ = algorithm != Algorithm::EyeLight && algorithm != Algorithm::PathTracing;
    if (settings.samplesPerIteration < 1)
        throw Error("--samples-per-iteration " + std::to_string(settings.samplesPerIteration) + ": at least 1");
    // The kernels index float4 arrays by sample with 32-bit offsets, 4 · sample.
    if (int64_t(settings.width) * settings.height * settings.samplesPerIteration >= (int64_t(1) << 29))
        throw Error(std::to_string(settings.width) + "x" + std::to_string(settings.height) + " with " +
                    std::to_string(settings.samplesPerIteration) +
                    " samples per iteration: 2^29 or more samples in one iteration (the kernels' 32-bit offsets)");
    // Which techniques the bidirectional algorithms combine (SmallVCM's useVC/useVM).
    useVC_ = algorithm == Algorithm::Bidirectional || algorithm == Algorithm::VertexConnectionMerging;
    useVM_ = algorithm == Algorithm::ProgressivePhotonMapping || algorithm == Algorithm::BidirectionalPhotonMapping ||
             algorithm == Algorithm::VertexConnectionMerging;
    bool lightTracing = algorithm == Algorithm::LightTracing;
    // An orthographic camera sees along one direction only: no light path can
    // connect to it (kernels/lights/camera.h), and light tracing has nothing else.
    if (lightTracing && scene.camera.orthographic)
        throw Error(scene.path + ": light tracing (-a lt) cannot render through an orthographic camera, "
                                 "which no light path can reach; use pt, bpt, vcm, ppm or bpm");
    connectionQueue_ = usesConnectionQueue(settings, device.info);
    sceneRadius_ = lights_.info.radius;
    pixels_ = settings.width * settings.height;
    samples_ = pixels_ * settings.samplesPerIteration;

    KernelBuffers& b = buffers_;
    sceneBuffers_.bind(b);
    Camera camera = makeCamera(scene.camera, settings.width, settings.height);
    b.camera = uploadBuffer(device, &camera, sizeof camera, "the camera");
    size_t imageBytes = size_t(pixels_) * 16, samplesBytes = imageBytes * size_t(settings.samplesPerIteration);
    b.pixelRadiance = deviceBuffer(device, samplesBytes, "the iteration's radiance");
    // Per sample for the bidirectional algorithms (accumulate.cl); pt and el leave them empty.
    size_t bidirectionalBytes = bidirectional_ ? samplesBytes : imageBytes;
    b.connectionRadiance = deviceBuffer(device, bidirectionalBytes, "the iteration's radiance");
    b.mergingRadiance = deviceBuffer(device, bidirectionalBytes, "the iteration's radiance");
    b.splatRadiance = deviceBuffer(device, imageBytes, "the light-tracing splats");
    b.framebuffer = deviceBuffer(device, imageBytes, "the framebuffer");
    device.queue.enqueueFillBuffer(b.pixelRadiance, 0.0f, 0, samplesBytes);
    for (cl::Buffer* i : {&b.connectionRadiance, &b.mergingRadiance})
        device.queue.enqueueFillBuffer(*i, 0.0f, 0, bidirectionalBytes);
    for (cl::Buffer* i : {&b.splatRadiance, &b.framebuffer}) device.queue.enqueueFillBuffer(*i, 0.0f, 0, imageBytes);
    if (settings.techniques) {
        b.familyMeans = deviceBuffer(device, 3 * imageBytes, "the technique images");
        device.queue.enqueueFillBuffer(b.familyMeans, 0.0f, 0, 3 * imageBytes);
    }
    device.queue.enqueueFillBuffer(b.queueCounters, 0, 0, kCounterBytes);

    std::string source = expandKernelSources(findKernelDir(), kernelFiles(algorithm));
    build_ = buildProgramOnce(device, source,
                              programOptions(algorithm, scene.features(), lights_.info.lightCount, connectionQueue_) +
                                  " -DTRIANGLE_PACKET_WIDTH=" + std::to_string(sceneBuffers_.packetWidth) +
                                  deviceOptions(device.info, scene.features(), algorithm));

    // One fixed local size: PoCL compiles a work-group function per local
    // size, and local size 1 is several times slower there.
    localSize_ = std::min<size_t>(RENDER_GROUP_SIZE, device.info.maxWorkGroupSize);
    profiling_ = (device.queue.getInfo<CL_QUEUE_PROPERTIES>() & CL_QUEUE_PROFILING_ENABLE) != 0;

    // What holds for the whole render; the rest is set per batch
    // (setBatchConstants) and per round.
    params_.capacity = paths_.capacity;
    params_.seed = settings.seed;
    params_.maxPathLength = settings.maxPathLength;
    params_.lightTracePaths = float(pixels_); // light paths per pass of the iteration (path_state.h)
    params_.pixels = pixels_;
    params_.samplesPerIteration = settings.samplesPerIteration;
    params_.techniques = settings.techniques ? 1 : 0;

    // The rounds: plan_round, and the host's view of the counters.
    planRound_ = kernel("plan_round");
    roundsAhead_ = settings.roundsAhead;
    phaseStartCounters_.assign(COUNTER_INDEX(COUNTER_PHASE_STATE), 0);
    roundCounters_.assign(size_t(roundsAhead_) + 1, std::vector<int>(COUNTER_INDEX(COUNTER_PHASE_STATE)));

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
        batch_ = samples_;
        b.lightPathHead = deviceBuffer(device, size_t(samples_) * sizeof(int), "the light path heads");
        storedVertexBytes_ = useVC_ ? sizeof(LightVertex) : sizeof(MergeVertex);
        size_t bytesPerVertex = storedVertexBytes_ + (useVM_ ? HashGrid::kBytesPerVertex : 0) +
                                (connectionQueue_ ? kBytesPerConnection : 0);
        vertexBudget_ = std::min<size_t>(device.info.maxAllocation / storedVertexBytes_,
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
        if (connectionQueue_) {
            c.traceConnections = kernel("trace_connections");
            c.hasTraceConnections = true;
        }
        if (useVM_) {
            c.merge = kernel("merge");
            c.hasMerge = true;
            grid_ = std::make_unique<HashGrid>(device, build_.program, profiling_ ? &profile_ : nullptr);
        }
        if (storesLightVertices()) ensureLightVertexCapacity(size_t(samples_) * 2);
    }
    bindAll();
}

// Reads of the counters may still be in flight after an exception ended a
// phase: they write roundCounters_, which must outlive them.
Renderer::~Renderer()
{
    try {
        device_.queue.finish();
    } catch (const cl::Error&) {
        // The device failed: nothing more will be written.
    }
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
    return sceneBuffers_.bytes + paths_.bytes +
           size_t(pixels_) * (settings_.techniques ? 128 : 80) +
           size_t(pixels_) * 16 * (settings_.samplesPerIteration - 1) * (bidirectional_ ? 3 : 1) +
           (bidirectional_ ? vertexCapacity_ * storedVertexBytes_ + size_t(samples_) * sizeof(int) : 0) +
           (grid_ ? vertexCapacity_ * HashGrid::kBytesPerVertex : 0) + connectionCapacity_ * kBytesPerConnection;
}

// Makes room for at least `vertices` light vertices (storedVertexBytes_ each), within
// the device's limits, and as many entries of the connection queue (a round
// queues at most one connection per stored vertex: a camera path connects
// only to its own light path, once per round); the kernels that write and
// read them get the new buffers.
void Renderer::ensureLightVertexCapacity(size_t vertices)
{
    vertices = std::min(vertices, vertexBudget_);
    if (vertices <= vertexCapacity_ && buffers_.lightVertices()) return;
    vertexCapacity_ = vertices;
    buffers_.lightVertices = deviceBuffer(device_, vertexCapacity_ * storedVertexBytes_, "the light vertices");
    params_.vertexCapacity = int(vertexCapacity_);
    if (grid_) {
        grid_->reserve(vertexCapacity_);
        buffers_.bucketStarts = grid_->bucketStarts();
        buffers_.bucketVertices = grid_->bucketVertices();
        params_.cellCount = grid_->buckets();
    }
    if (connectionQueue_) {
        connectionCapacity_ = vertexCapacity_;
        for (cl::Buffer* b : {&buffers_.connectionOrigins, &buffers_.connectionDirections,
                              &buffers_.connectionContribution})
            *b = deviceBuffer(device_, connectionCapacity_ * sizeof(cl_float4), "the connection queue");
        params_.connectionCapacity = int(connectionCapacity_);
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

// The vertex connections a round queued, as counted after it. A round
// queues at most one per stored light vertex (connect_vertices.cl), so more
// than the queue holds is a bug, not a case to handle.
size_t Renderer::queuedConnections(const std::vector<int>& counters) const
{
    size_t n = size_t(counters[COUNTER_INDEX(COUNTER_CONNECTIONS)]);
    if (n > connectionCapacity_)
        throw Error("internal error: " + std::to_string(n) + " vertex connections queued in one round, room for " +
                    std::to_string(connectionCapacity_));
    return n;
}

uint32_t Renderer::readCounter(int counter)
{
    uint32_t value = 0;
    device_.queue.enqueueReadBuffer(buffers_.queueCounters, CL_TRUE, size_t(COUNTER_INDEX(counter)) * sizeof value,
                                    sizeof value, &value);
    return value;
}

int Renderer::lightVertexCount() { return int(readCounter(COUNTER_LIGHT_VERTICES)); }

// plan_round's count, 64 bits. In an abandoned iteration it lacks the last
// round's shadow rays: no round after it counted them.
uint64_t Renderer::raysTracedThisIteration()
{
    uint64_t rays = 0;
    device_.queue.enqueueReadBuffer(buffers_.queueCounters, CL_TRUE,
                                    size_t(COUNTER_INDEX(COUNTER_RAYS_TRACED)) * sizeof(int), sizeof rays, &rays);
    return rays;
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
        if (profiling_) profile_.record(kernel, items, event);
    } catch (const cl::Error& e) {
        throw Error("launching kernel " + kernel.getInfo<CL_KERNEL_FUNCTION_NAME>() + " on " + device_.info.name +
                    " failed: " + clErrorName(e.err()));
    }
}

// One round: the vertex connections the last round queued are traced (as
// many as `connections`, or an upper bound of them), plan_round decides on
// the device how many new paths start (as many as there are slots after the
// last round's hits and samples left: kernels/transport/path_state.h), then
// every live path advances one segment. Launches cover
// `fresh` new paths and `live` paths in all: the actual numbers, or upper
// bounds of them (kernels skip the items past their queue's size on the
// device). With live = 0, the last round's connections and the plan alone:
// it counts the last round's shadow rays. Consumes RAYS(parity), fills
// RAYS(1 - parity).
void Renderer::round(Phase& phase, int parity, size_t fresh, size_t live, size_t connections)
{
    // The last round's queued vertex connections, before plan_round empties the queue.
    if (phase.hasTraceConnections && connections > 0) launch(phase.traceConnections, connections);
    params_.rayQueue = QUEUE_RAYS(parity);
    params_.nextRayQueue = QUEUE_RAYS(1 - parity);
    launch(planRound_, 1);
    if (live == 0) return;
    if (fresh > 0) launch(phase.generate, fresh);
    launch(phase.extend, live);
    if (phase.hasConnectVertices) launch(phase.connectVertices, live);
    if (phase.hasMerge) launch(phase.merge, live);
    launch(phase.shade, live);
    launch(phase.escaped, live);
    if (phase.hasConnect) launch(phase.connect, live);
}

// Runs paths for samples [firstSample, firstSample + count) to completion,
// in rounds. The host needs the counters to see when the phase is over, and
// reads them in one of two ways (RenderSettings::roundsAhead):
// - 0 (the default): after every round, blocking, and sizes the next round's
//   launches by them (OpenCL 1.2 has no indirect dispatch).
// - N > 0: it enqueues round r and a non-blocking read of its counters, then
//   waits for round r − N's, so N rounds stay queued while the host waits.
//   Launches cover upper bounds. The N rounds enqueued after the last live
//   one are cheap: the first one traces the last live round's queued
//   connections and its plan counts that round's shadow rays; the rest only
//   launch trace_connections over an empty queue and plan_round. abandon_ is asked as each round
//   is enqueued, before it has run.
// Measured, N = 0 is faster on both devices there are figures for: on PoCL
// (N = 2: 0.8x) every launched work-item costs, most rounds have few live
// paths; on the H200 (N = 1-8: 0.67-0.92x for pt, 0.74-0.88x for vcm) the
// GPU is idle between rounds either way at 512 x 512 (docs/gpu.md).
bool Renderer::runPhase(Phase& phase, int firstSample, int count)
{
    params_.cameraPaths = phase.cameraPaths ? 1 : 0;
    params_.firstSample = firstSample;
    params_.samples = count;
    // Every queue empty.
    device_.queue.enqueueWriteBuffer(buffers_.queueCounters, CL_FALSE, 0, phaseStartCounters_.size() * sizeof(int),
                                     phaseStartCounters_.data());
    size_t capacity = size_t(paths_.capacity);
    // Paths alive at the start of the round after the one these counters
    // were read after, and of them how many are new (plan_round's rule).
    auto nextRound = [&](const std::vector<int>& now, int parity, size_t* fresh) {
        size_t free = capacity - size_t(now[COUNTER_INDEX(QUEUE_HITS)]);
        *fresh = std::min(free, size_t(count - now[COUNTER_INDEX(COUNTER_ISSUED)]));
        return size_t(now[COUNTER_INDEX(QUEUE_RAYS(1 - parity))]) + *fresh;
    };
    size_t ahead = size_t(roundsAhead_);
    if (ahead == 0) {
        std::vector<int>& now = roundCounters_[0];
        size_t fresh = std::min(capacity, size_t(count)), live = fresh, connections = 0;
        for (int parity = 0;; parity = 1 - parity) {
            round(phase, parity, fresh, live, connections);
            if (live == 0) return true;
            device_.queue.enqueueReadBuffer(buffers_.queueCounters, CL_TRUE, 0, now.size() * sizeof(int), now.data());
            live = nextRound(now, parity, &fresh);
            connections = queuedConnections(now);
            if (abandon_ && abandon_()) return false;
        }
    }
    // roundCounters_ has ahead + 1 entries: round r's read goes to r mod (ahead + 1).
    std::vector<cl::Event> reads(ahead + 1);
    size_t freshBound = std::min(capacity, size_t(count));
    bool finished = false;
    // A live path queues at most maxPathLength - 2 connections per round.
    size_t connectionBound =
        std::min(connectionCapacity_, capacity * size_t(std::max(0, settings_.maxPathLength - 2)));
    for (size_t r = 0; !finished; ++r) {
        int parity = int(r % 2);
        round(phase, parity, freshBound, capacity, r > 0 ? connectionBound : 0);
        std::vector<int>& counters = roundCounters_[r % (ahead + 1)];
        device_.queue.enqueueReadBuffer(buffers_.queueCounters, CL_FALSE, 0, counters.size() * sizeof(int),
                                        counters.data(), nullptr, &reads[r % (ahead + 1)]);
        if (r >= ahead) {
            size_t q = r - ahead, fresh = 0;
            reads[q % (ahead + 1)].wait();
            finished = nextRound(roundCounters_[q % (ahead + 1)], int(q % 2), &fresh) == 0;
            queuedConnections(roundCounters_[q % (ahead + 1)]);
        }
        if (!finished && abandon_ && abandon_()) return false;
    }
    return true; // the reads still in flight write roundCounters_, which stays
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
    int splatted = splats ? 0 : samples_;
    for (int first = 0; first < samples_;) {
        int count = 0, lightFirst = 0, lightCount = 0;
        auto placeBatch = [&] {
            count = std::min(batch_, samples_ - first);
            lightFirst = std::max(0, std::min(first, samples_ - batch_));
            lightCount = std::min(batch_, samples_ - lightFirst);
        };
        placeBatch();
        for (;;) {
            params_.firstLightPath = lightFirst;
            params_.firstSplatPath = splatted;
            setBatchConstants(lightCount);
            device_.queue.enqueueFillBuffer(buffers_.queueCounters, 0,
                                            size_t(COUNTER_INDEX(COUNTER_LIGHT_VERTICES)) * sizeof(int), sizeof(int));
            if (!runPhase(lightPhase_, lightFirst, lightCount)) return Batches::Abandoned;
            splatted = std::max(splatted, lightFirst + lightCount);
            size_t wanted = storesLightVertices() ? size_t(lightVertexCount()) : 0;
            if (wanted <= vertexCapacity_) break;
            if (wanted <= vertexBudget_) {
                ensureLightVertexCapacity(wanted + wanted / 4);
                continue;
            }
            if (lightCount == 1)
                throw Error("the light vertices of a single light path do not fit on " + device_.info.name);
            batch_ = lightCount / 2;
            if (first > 0) return Batches::Restart;
            // Only this first batch has run, and its light paths splatted
            // with its η: they splat again, with the smaller batch's.
            if (splats) {
                splatted = 0;
                device_.queue.enqueueFillBuffer(buffers_.splatRadiance, 0.0f, 0, size_t(pixels_) * 16);
            }
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
    params_.accumulated = iteration_ * settings_.samplesPerIteration;
    abandon_ = abandon;
    device_.queue.enqueueFillBuffer(buffers_.queueCounters, 0, size_t(COUNTER_INDEX(COUNTER_RAYS_TRACED)) * sizeof(int),
                                    sizeof(uint64_t));
    // This iteration's contributions so far, before accumulate folds them in.
    auto clearRadiance = [&] {
        size_t bytes = size_t(pixels_) * 16, samplesBytes = size_t(samples_) * 16;
        device_.queue.enqueueFillBuffer(buffers_.pixelRadiance, 0.0f, 0, samplesBytes);
        for (cl::Buffer* b : {&buffers_.connectionRadiance, &buffers_.mergingRadiance})
            device_.queue.enqueueFillBuffer(*b, 0.0f, 0, bidirectional_ ? samplesBytes : bytes);
        device_.queue.enqueueFillBuffer(buffers_.splatRadiance, 0.0f, 0, bytes);
    };
    Batches done = Batches::Done;
    if (!bidirectional_) {
        done = runPhase(cameraPhase_, 0, samples_) ? Batches::Done : Batches::Abandoned;
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
        rays_ += raysTracedThisIteration();
        if (profiling_) profile_.collect();
        return false;
    }
    launch(accumulate_, size_t(pixels_));
    device_.queue.finish();
    rays_ += raysTracedThisIteration();
    if (profiling_) profile_.collect();
    ++iteration_;
    return true;
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

uint64_t Renderer::nonFiniteCount() { return readCounter(COUNTER_NONFINITE); }

} // namespace wv
