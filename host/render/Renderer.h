// The host queue manager: owns the device program, the scene on the device
// and the path state, and runs iterations of the chosen algorithm as phases
// (light paths, camera paths) of rounds of kernel launches over the work
// queues.
#pragma once

#include "../cl/Program.h"
#include "../image/Image.h"
#include "Algorithm.h"
#include "HashGrid.h"
#include "KernelBindings.h"
#include "KernelProfile.h"
#include "LightTable.h"
#include "PathState.h"
#include "SceneBuffers.h"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>

namespace wv {

// How vertex connection (bpt, vcm) finds out whether a camera vertex and a
// light vertex see each other (kernels/stages/connect_vertices.cl): each
// camera path's work-item traces its connections' shadow rays itself
// (Inline), or queues them for a kernel that traces one per work-item
// (Queued). Default: Queued on GPUs, Inline on other devices.
enum class VertexConnections { Default, Inline, Queued };

struct RenderSettings {
    Algorithm algorithm = Algorithm::EyeLight;
    int width = 512, height = 512;
    int maxPathLength = 10;
    uint32_t seed = 0;
    int wavefront = 0; // path slots; 0 = the device type's default
    // Most light vertices kept on the device at once (bidirectional); 0 = what
    // half the device memory (and its largest allocation) holds.
    size_t maxLightVertices = 0;
    // Vertex merging: r_1 = radiusFactor × the scene's bounding-sphere radius,
    // r_i = r_1 · i^((α − 1)/2) in iteration i = 1, 2, ...
    float radiusFactor = 0.003f;
    float radiusAlpha = 0.75f;
    // Also keep an image per technique family (techniqueImages()).
    bool techniques = false;
    // Rounds the host keeps enqueued beyond the one whose counters it waits
    // for (Renderer::runPhase); 0 waits after every round, the faster way on
    // PoCL and on the H200 alike.
    int roundsAhead = 0;
    // Camera samples per pixel in one iteration, K: more paths per launch
    // for a device that one sample of the image leaves idle. Sample k of
    // iteration i is sample i·K + k of the pixel, so for pt and el the image
    // after N iterations is that of N·K iterations of one sample. The
    // bidirectional algorithms and lt trace K light paths per pixel too, each
    // pass's camera paths connecting to its own light paths; lt and bpt then
    // give the image of N·K iterations as well (up to the order of float
    // adds), while merging (ppm, bpm, vcm) merges each camera path with all
    // K passes' light vertices at iteration i's radius: another estimator
    // of the same image.
    int samplesPerIteration = 1;
    VertexConnections vertexConnections = VertexConnections::Default;
};

class Renderer {
public:
    // Builds (or loads from the cache) the kernels for the scene's features and
    // the algorithm, and uploads the scene. Throws wv::Error on any failure.
    Renderer(DeviceContext& device, const Scene& scene, const Bvh& bvh, const RenderSettings& settings);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Runs one iteration (samplesPerIteration samples per pixel, and as many
    // light paths per pixel for lt and the bidirectional algorithms) to completion and folds it into the
    // image. `index` is its global index, 0, 1, 2, ...: its random numbers
    // and merge radius depend on it alone (MultiDeviceRender gives devices
    // different ones); without it, the next after this renderer's last.
    // `abandon`, if given, is asked after every round: when it says so, the
    // iteration is dropped unfinished (image() stays that of the iterations
    // before it) and iterate returns false.
    bool iterate(int index, const std::function<bool()>& abandon = nullptr);
    void iterate() { iterate(iteration_); }

    int iterations() const { return iteration_; } // iterations folded into image()
    int samplesPerIteration() const { return settings_.samplesPerIteration; } // per pixel
    uint64_t raysTraced() const { return rays_; } // extended and shadow rays, all iterations
    Image image();
    // The running means of the unidirectional (emission hits, next-event
    // estimation, background), vertex connection (connections and light
    // tracing) and vertex merging contributions; they sum to image(). Empty
    // images unless RenderSettings::techniques.
    std::array<Image, 3> techniqueImages();
    uint64_t nonFiniteCount();
    const ProgramBuild& programBuild() const { return build_; }
    const LightTable& lights() const { return lights_; }
    int wavefront() const { return paths_.capacity; }
    int roundsAhead() const { return roundsAhead_; }
    size_t deviceBytes() const;
    // Light paths per batch (bidirectional): all of the iteration's unless
    // the light vertices of that many paths do not fit on the device.
    int lightPathBatch() const { return batch_; }
    // Bidirectional iterations begun again because the light-path batch had
    // to shrink midway (renderBatches).
    int restartedIterations() const { return restartedIterations_; }
    // Whether vertex connections go through the connection queue.
    bool connectionQueue() const { return connectionQueue_; }
    // The merge radius of the last iteration (0 without merging).
    float mergeRadius() const { return radius_; }

    // Per kernel so far: device time (s) and work-items launched (queue
    // sizes: rays for extend and connect, path slots for generate and the
    // shade, connect and merge kernels, pixels for accumulate; with rounds
    // ahead, the upper bounds launched instead: the wavefront). Needs a
    // profiling queue (see DeviceContext); empty otherwise.
    // The hash grid's build kernels are among them (items: the light vertices
    // for grid_count and grid_scatter, the buckets + 1 for scan_add, the
    // chunks for scan_chunks, 1 for scan_totals); buffer fills are not.
    using KernelStats = KernelProfile::KernelStats;
    const std::map<std::string, KernelStats>& kernelStats() const { return profile_.stats(); }

    // The kernel files of the program for an algorithm.
    static std::vector<std::string> kernelFiles(Algorithm algorithm);
    // Their build options: the algorithm's defines, the scene's features, the
    // light selection's steps for a table of lightCount lights, and whether
    // vertex connections go through the connection queue.
    static std::string programOptions(Algorithm algorithm, const SceneFeatures& features, int lightCount,
                                      bool connectionQueue = false);
    // The options that depend on the device the program is built for (and on
    // the algorithm and the scene's lobes, which decide whether its shading
    // runs in SIMD there).
    static std::string deviceOptions(const DeviceInfo& device, const SceneFeatures& features, Algorithm algorithm);
    // Whether the connection queue is used on `device` (bpt and vcm only).
    static bool usesConnectionQueue(const RenderSettings& settings, const DeviceInfo& device);

private:
    // The kernels of one kind of sub-path, in the order a round runs them.
    struct Phase {
        bool cameraPaths = false;
        cl::Kernel generate, extend, connectVertices, merge, shade, escaped, connect, traceConnections;
        bool hasConnectVertices = false, hasMerge = false, hasConnect = false, hasTraceConnections = false;
    };

    cl::Kernel kernel(const char* name);
    void bindAll();
    void launch(cl::Kernel& kernel, size_t items);
    std::function<bool()> abandon_; // iterate()'s, asked once per round (runPhase)
    // False if abandon_ said to stop.
    bool runPhase(Phase& phase, int firstSample, int count);
    void round(Phase& phase, int parity, size_t fresh, size_t live, size_t connections);
    uint32_t readCounter(int counter); // blocking
    size_t queuedConnections(const std::vector<int>& counters) const;
    uint64_t raysTracedThisIteration();
    int lightVertexCount();
    void ensureLightVertexCapacity(size_t vertices);
    void setBatchConstants(int lightPaths);
    enum class Batches { Done, Restart, Abandoned };
    Batches renderBatches();
    void buildHashGrid();

    DeviceContext& device_;
    RenderSettings settings_;
    bool bidirectional_ = false;
    LightTable lights_;
    SceneBuffers sceneBuffers_;
    // Every buffer the render kernels take (kernels/interface/kernel_interface.h), and
    // the scalars of the next launch: the whole kernel interface.
    KernelBuffers buffers_;
    LaunchParams params_{};
    PathState paths_;
    ProgramBuild build_;
    std::vector<cl::Kernel> kernels_; // every render kernel made, for rebinding buffers
    size_t vertexCapacity_ = 0, vertexBudget_ = 0;
    // Bytes of one stored light vertex: a LightVertex where camera paths
    // connect to it, merging's MergeVertex with merging only
    // (StoredLightVertex in kernels/interface/shared_types.h).
    size_t storedVertexBytes_ = sizeof(LightVertex);
    bool useVC_ = false, useVM_ = false;
    // Light paths keep their vertices for connection and merging (not lt).
    bool storesLightVertices() const { return useVC_ || useVM_; }
    bool connectionQueue_ = false;
    size_t connectionCapacity_ = 0; // entries of the connection queue's buffers
    float sceneRadius_ = 0, radius_ = 0;
    std::unique_ptr<HashGrid> grid_; // merging only
    int batch_ = 0;
    int index_ = 0; // global index of the iteration in flight
    int restartedIterations_ = 0;
    int pixels_ = 0;
    int samples_ = 0; // of an iteration: pixels × samplesPerIteration (camera samples, and light paths)
    int iteration_ = 0;
    uint64_t rays_ = 0;
    size_t localSize_ = RENDER_GROUP_SIZE;
    Phase cameraPhase_, lightPhase_;
    cl::Kernel planRound_, accumulate_;
    int roundsAhead_ = 0;
    std::vector<int> phaseStartCounters_;             // the counters below COUNTER_PHASE_STATE at a phase's start
    std::vector<std::vector<int>> roundCounters_; // the same, as read after rounds (roundsAhead_ + 1 of them)
    bool profiling_ = false;
    KernelProfile profile_;
};

// Default wavefront capacity: ~256K paths on a CPU, 2M on a GPU, at most what
// a quarter of the device's memory holds.
int defaultWavefront(const DeviceInfo& device);
// -DLIGHT_SELECT_STEPS for a light table of lightCount lights.
std::string lightSelectOption(int lightCount);

} // namespace wv
