// Kernel micro-benchmarks (Google Benchmark). Each reports the natural rate
// of one kernel on one scene and device as items_per_second:
//   Extend/Connect   rays/s, on coherent camera rays and on incoherent rays
//                    (random origins inside the scene, random directions);
//                    with Embree found at build time, the same rays traced by
//                    Embree too, after each of wavevcm's launches: counters
//                    embree_rays_per_s, vs_embree (the median over the launches
//                    of wavevcm's rate / Embree's) and embree_mismatch (fraction
//                    of rays whose hit or occlusion differs);
//   Kernel/<name>    the render kernels inside real iterations, from OpenCL
//                    profiling events: path slots/s for generate and the
//                    shade, connect and merge kernels, pixels/s for accumulate;
//   HashGridBuild    light vertices/s;
//   BvhBuild         triangles/s for generated meshes up to 4M triangles;
//   ProgramBuild     kernel build time of vcm, cold (cached:0) and from
//                    the program cache (cached:1): wavevcm's, or PoCL's own.
// The first argument of the ray and kernel benchmarks is the wavefront size.
// Scene: $WAVEVCM_BENCH_SCENE (default scenes/cornell-box.gltf); device:
// $WAVEVCM_BENCH_DEVICE (as `render --device`). Counters: bytes_per_path
// and bytes_per_light_vertex of device memory.
#include "bvh/Bvh.h"
#include "cl/Program.h"
#include "render/HashGrid.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"
#ifdef WAVEVCM_HAVE_EMBREE
#include "EmbreeReference.h"
#endif

#include "../kernels/interface/queue_ids.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>

namespace wv {
namespace {

std::string env(const char* name, const std::string& fallback)
{
    const char* v = std::getenv(name);
    return v && *v ? v : fallback;
}

// The scene, its BVH and the device, loaded once for all benchmarks.
struct Fixture {
    Scene scene;
    std::vector<DeviceInfo> devices;
    DeviceInfo device;
    Bvh bvh; // of the device's packet width

    Fixture()
        : scene(loadGltf(env("WAVEVCM_BENCH_SCENE", std::string(WAVEVCM_SOURCE_DIR) + "/scenes/cornell-box.gltf"))),
          devices(enumerateDevices()), device(selectDevice(devices, env("WAVEVCM_BENCH_DEVICE", ""))),
          bvh(buildBvh(scene.vertices, trianglePacketWidth(device)))
    {
    }
    static Fixture& get()
    {
        static Fixture f;
        return f;
    }
#ifdef WAVEVCM_HAVE_EMBREE
    const EmbreeReference& embree()
    {
        static EmbreeReference reference(scene.vertices);
        return reference;
    }
#endif
};

using Float4 = std::array<float, 4>; // as in EmbreeReference.h

// Rays for the ray benchmarks: coherent camera rays over the image, or
// incoherent rays from random points in the scene's bounds.
void makeRays(const Scene& scene, size_t n, bool coherent, bool shadow, std::vector<Float4>* origins,
              std::vector<Float4>* directions)
{
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0, 1);
    Bounds b = scene.bounds();
    int side = int(std::ceil(std::sqrt(double(n))));
    Camera cam = makeCamera(scene.camera, side, side);
    auto v3 = [](const float* f) { return Vec3(f[0], f[1], f[2]); };
    for (size_t i = 0; i < n; ++i) {
        Vec3 o, d;
        if (coherent) {
            float sx = 2 * (float(i % side) + 0.5f) / side - 1, sy = 1 - 2 * (float(i / side) + 0.5f) / side;
            o = v3(cam.position);
            d = normalize(v3(cam.forward) + v3(cam.right) * sx + v3(cam.up) * sy);
        } else {
            o = b.lo + Vec3(b.extent().x * u(rng), b.extent().y * u(rng), b.extent().z * u(rng));
            float z = 1 - 2 * u(rng), r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * float(M_PI) * u(rng);
            d = Vec3(r * std::cos(phi), r * std::sin(phi), z);
        }
        float tMax = shadow ? length(b.extent()) * u(rng) : INFINITY;
        origins->push_back({o.x, o.y, o.z, 0});
        directions->push_back({d.x, d.y, d.z, tMax});
    }
}

// extend (closest hit) or the any-hit traversal of connect, over one
// wavefront of rays in the ray queue.
void rays(benchmark::State& state, bool coherent, bool anyHit)
{
    Fixture& f = Fixture::get();
    DeviceContext device(f.device);
    LightTable lights = buildLightTable(f.scene, f.bvh);
    SceneBuffers scene(device, f.scene, f.bvh, lights);
    size_t n = size_t(state.range(0));
    std::vector<Float4> origins, directions;
    makeRays(f.scene, n, coherent, anyHit, &origins, &directions);
    std::string source = expandKernelSources(findKernelDir(), {"stages/extend.cl", "stages/connect.cl"});
    std::string options =
        "-cl-std=CL1.2 -DTRIANGLE_PACKET_WIDTH=" + std::to_string(scene.packetWidth) +
        Renderer::deviceOptions(f.device, f.scene.features(), Algorithm::PathTracing);
    cl::Program program = buildProgram(device.context, f.device, source, options).program;
    cl::Buffer o = uploadBuffer(device, origins.data(), n * 16, "origins");
    cl::Buffer d = uploadBuffer(device, directions.data(), n * 16, "directions");
    std::vector<int> items(QUEUE_COUNT * n), counters(COUNTER_INDEX(COUNTER_COUNT));
    int queue = anyHit ? QUEUE_SHADOW : QUEUE_RAYS(0);
    for (size_t i = 0; i < n; ++i) items[queue * n + i] = int(i);
    counters[COUNTER_INDEX(queue)] = int(n);
    cl::Buffer itemBuffer = uploadBuffer(device, items.data(), items.size() * 4, "queues");
    cl::Buffer counterBuffer = deviceBuffer(device, counters.size() * 4, "counters");
    // connect adds a contribution of one to its own pixel for every
    // unoccluded ray, so the radiance afterwards says which rays were.
    std::vector<int> ownPixel(n);
    for (size_t i = 0; i < n; ++i) ownPixel[i] = int(i);
    std::vector<Float4> ones(n, Float4{1, 1, 1, 1});
    cl::Buffer t = deviceBuffer(device, n * 4, "hit distances"), tri = deviceBuffer(device, n * 4, "triangles"),
               bary = deviceBuffer(device, n * 8, "barycentrics"),
               contribution = uploadBuffer(device, ones.data(), n * 16, "contributions"),
               pixels = uploadBuffer(device, ownPixel.data(), n * 4, "pixels"),
               radiance = deviceBuffer(device, n * 16, "radiance");
    device.queue.enqueueFillBuffer(radiance, 0.0f, 0, n * 16);
    cl::Kernel k(program, anyHit ? "connect" : "extend");
    KernelBuffers buffers;
    scene.bind(buffers);
    buffers.queueItems = itemBuffer;
    buffers.queueCounters = counterBuffer;
    (anyHit ? buffers.shadowOrigins : buffers.rayOrigins) = o;
    (anyHit ? buffers.shadowDirections : buffers.rayDirections) = d;
    buffers.shadowContribution = contribution;
    buffers.pathPixel = pixels;
    buffers.pixelRadiance = radiance;
    buffers.hitT = t;
    buffers.hitTriangle = tri;
    buffers.hitBary = bary;
    LaunchParams params{};
    params.capacity = int(n);
    params.rayQueue = QUEUE_RAYS(0);
    bindBuffers(k, buffers);
    setLaunchParams(k, params);
    size_t global = (n + 63) / 64 * 64;
    // One untimed launch: PoCL compiles the work-group function at the first.
    device.queue.enqueueWriteBuffer(counterBuffer, CL_FALSE, 0, counters.size() * 4, counters.data());
    device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(64));
    device.queue.finish();
#ifdef WAVEVCM_HAVE_EMBREE
    // Embree traces the same rays after each of wavevcm's launches, so that
    // both see the machine in the same state: its speed drifts by 10-20 %
    // over seconds, which made the ratio of two separately timed means move
    // by as much. vs_embree is the median of the paired ratios.
    std::vector<float> reference;
    f.embree().trace(origins, directions, anyHit, &reference); // warm-up
    std::vector<double> pairedRatios;
    double embreeSeconds = 0;
#endif
    for (auto _ : state) {
        // extend pushes to the hit/escaped queues: reset their counters.
        device.queue.enqueueWriteBuffer(counterBuffer, CL_FALSE, 0, counters.size() * 4, counters.data());
        auto start = std::chrono::steady_clock::now();
        device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(64));
        device.queue.finish();
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        state.SetIterationTime(s);
#ifdef WAVEVCM_HAVE_EMBREE
        double e = f.embree().trace(origins, directions, anyHit, &reference);
        embreeSeconds += e;
        pairedRatios.push_back(e / s);
#endif
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(n));
#ifdef WAVEVCM_HAVE_EMBREE
    std::sort(pairedRatios.begin(), pairedRatios.end());
    size_t m = pairedRatios.size();
    state.counters["embree_rays_per_s"] = double(m) * double(n) / embreeSeconds;
    state.counters["vs_embree"] = m % 2 ? pairedRatios[m / 2] : 0.5 * (pairedRatios[m / 2 - 1] + pairedRatios[m / 2]);
    // Where the two disagree: hit versus miss, or a distance off by more than
    // float rounding over the traversal (relative 1e-4).
    std::vector<float> ours(n);
    if (anyHit) {
        std::vector<Float4> r(n);
        device.queue.enqueueReadBuffer(radiance, CL_TRUE, 0, n * 16, r.data());
        for (size_t i = 0; i < n; ++i) ours[i] = r[i][0] > 0 ? INFINITY : 0.0f;
    } else {
        device.queue.enqueueReadBuffer(t, CL_TRUE, 0, n * 4, ours.data());
    }
    size_t mismatches = 0;
    for (size_t i = 0; i < n; ++i) {
        bool hitA = std::isfinite(ours[i]), hitB = std::isfinite(reference[i]);
        if (hitA != hitB || (hitA && std::fabs(ours[i] - reference[i]) > 1e-4f * std::max(1.0f, reference[i])))
            ++mismatches;
    }
    state.counters["embree_mismatch"] = double(mismatches) / double(n);
#endif
}

void BM_ExtendCoherent(benchmark::State& s) { rays(s, true, false); }
void BM_ExtendIncoherent(benchmark::State& s) { rays(s, false, false); }
void BM_ConnectCoherent(benchmark::State& s) { rays(s, true, true); }
void BM_ConnectIncoherent(benchmark::State& s) { rays(s, false, true); }
BENCHMARK(BM_ExtendCoherent)->Arg(1 << 16)->Arg(1 << 18)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ExtendIncoherent)->Arg(1 << 16)->Arg(1 << 18)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConnectCoherent)->Arg(1 << 16)->Arg(1 << 18)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConnectIncoherent)->Arg(1 << 16)->Arg(1 << 18)->UseManualTime()->Unit(benchmark::kMillisecond);

// One render kernel inside real iterations of `algorithm` (128×128), timed
// by OpenCL profiling events.
void renderKernel(benchmark::State& state, Algorithm algorithm, const std::string& kernel)
{
    Fixture& f = Fixture::get();
    DeviceContext device(f.device, true);
    RenderSettings s;
    s.algorithm = algorithm;
    s.width = s.height = 128;
    s.wavefront = int(state.range(0));
    s.roundsAhead = 0; // launches sized by the queues: items/s counts work, not upper bounds
    Renderer renderer(device, f.scene, f.bvh, s);
    renderer.iterate(); // warm-up: first launches compile work-group functions
    Renderer::KernelStats before = renderer.kernelStats().at(kernel);
    for (auto _ : state) {
        renderer.iterate();
        Renderer::KernelStats now = renderer.kernelStats().at(kernel);
        state.SetIterationTime(now.seconds - before.seconds);
        state.SetItemsProcessed(state.items_processed() + int64_t(now.items - before.items));
        before = now;
    }
    state.counters["bytes_per_path"] = double(PathState::bytesPerPath());
    state.counters["bytes_per_light_vertex"] = double(sizeof(LightVertex));
}

#define KERNEL_BENCHMARK(name, algorithm, kernel)                                                              \
    void BM_Kernel_##name(benchmark::State& s) { renderKernel(s, algorithm, kernel); }                        \
    BENCHMARK(BM_Kernel_##name)->Arg(1 << 14)->Arg(1 << 16)->UseManualTime()->Unit(benchmark::kMillisecond)
KERNEL_BENCHMARK(generate, Algorithm::PathTracing, "generate");
KERNEL_BENCHMARK(extend, Algorithm::PathTracing, "extend");
KERNEL_BENCHMARK(shade, Algorithm::PathTracing, "shade");
KERNEL_BENCHMARK(connect, Algorithm::PathTracing, "connect");
KERNEL_BENCHMARK(accumulate, Algorithm::PathTracing, "accumulate");
KERNEL_BENCHMARK(shade_light, Algorithm::VertexConnectionMerging, "shade_light");
KERNEL_BENCHMARK(shade_bidirectional, Algorithm::VertexConnectionMerging, "shade_bidirectional");
KERNEL_BENCHMARK(connect_vertices, Algorithm::VertexConnectionMerging, "connect_vertices");
KERNEL_BENCHMARK(merge, Algorithm::VertexConnectionMerging, "merge");

// The hash grid over N random light vertices (radius 0.01 in a unit cube).
void BM_HashGridBuild(benchmark::State& state)
{
    Fixture& f = Fixture::get();
    DeviceContext device(f.device);
    std::string source = expandKernelSources(findKernelDir(), {"stages/hash_grid.cl"});
    // vcm's build: from LightVertex records (StoredLightVertex).
    cl::Program program = buildProgram(device.context, f.device, source, "-cl-std=CL1.2 -DVERTEX_CONNECTION").program;
    size_t n = size_t(state.range(0));
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<LightVertex> vertices(n);
    for (LightVertex& v : vertices)
        for (float& c : v.surface.position) c = u(rng);
    cl::Buffer buffer = uploadBuffer(device, vertices.data(), n * sizeof(LightVertex), "vertices");
    HashGrid grid(device, program);
    grid.reserve(n);
    for (auto _ : state) {
        auto start = std::chrono::steady_clock::now();
        grid.build(buffer, int(n), 0.01f);
        device.queue.finish();
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(n));
}
BENCHMARK(BM_HashGridBuild)->Arg(1 << 16)->Arg(1 << 20)->Arg(1 << 22)->UseManualTime()->Unit(benchmark::kMillisecond);

// The BVH build over N triangles of a tessellated sphere; counter sah_cost:
// the binary tree's SAH cost (Bvh::sahCost).
void BM_BvhBuild(benchmark::State& state)
{
    int n = int(state.range(0));
    int rings = int(std::sqrt(n / 2.0)), segments = std::max(3, n / (2 * rings));
    std::vector<Vec3> v;
    for (int r = 0; r < rings; ++r)
        for (int g = 0; g < segments; ++g) {
            auto p = [&](int a, int b) {
                float t = float(M_PI) * a / rings, ph = 2 * float(M_PI) * b / segments;
                return Vec3(std::sin(t) * std::cos(ph), std::cos(t), std::sin(t) * std::sin(ph));
            };
            for (Vec3 q : {p(r, g), p(r, g + 1), p(r + 1, g), p(r, g + 1), p(r + 1, g + 1), p(r + 1, g)}) v.push_back(q);
        }
    double sahCost = 0;
    for (auto _ : state) {
        Bvh bvh = buildBvh(v);
        sahCost = bvh.sahCost;
        benchmark::DoNotOptimize(bvh);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(v.size() / 3));
    state.counters["sah_cost"] = sahCost;
}
BENCHMARK(BM_BvhBuild)->Arg(1 << 12)->Arg(1 << 16)->Arg(1 << 20)->Arg(1 << 22)->Unit(benchmark::kMillisecond);

// Building the vcm program (kernel sources expanded, options of the scene):
// cold (argument 0: wavevcm's cache off, and a declaration unique to each
// build so that the driver's own cache, PoCL's, misses too) or cached (1:
// from wavevcm's cache, or on PoCL from PoCL's, which wavevcm leaves it to).
// clBuildProgram only: PoCL compiles each kernel's work-group function at
// its first launch, which the first iteration pays (see the README).
void BM_ProgramBuild(benchmark::State& state)
{
    Fixture& f = Fixture::get();
    DeviceContext device(f.device);
    bool cached = state.range(0) != 0;
    std::string source = expandKernelSources(findKernelDir(), Renderer::kernelFiles(Algorithm::VertexConnectionMerging));
    std::string options = "-cl-std=CL1.2 -DBIDIRECTIONAL" + f.scene.features().buildOptions();
    // Cached builds use a cache of their own, filled first, whatever
    // WAVEVCM_CACHE_DIR says (it may be off).
    std::string savedCacheDir = env("WAVEVCM_CACHE_DIR", "");
    std::string cacheDir = (std::filesystem::temp_directory_path() / "wavevcm-bench-cache").string();
    setenv("WAVEVCM_CACHE_DIR", cached ? cacheDir.c_str() : "off", 1);
    if (cached) buildProgram(device.context, f.device, source, options);
    for (auto _ : state) {
        // A declaration, not a comment: PoCL keys its cache on the
        // preprocessed source, from which comments are gone.
        std::string unique = cached ? "" : "\n__constant int wavevcm_cold_build_" +
            std::to_string(std::chrono::system_clock::now().time_since_epoch().count()) + " = 0;\n";
        benchmark::DoNotOptimize(buildProgram(device.context, f.device, source + unique, options));
    }
    if (savedCacheDir.empty())
        unsetenv("WAVEVCM_CACHE_DIR");
    else
        setenv("WAVEVCM_CACHE_DIR", savedCacheDir.c_str(), 1);
}
BENCHMARK(BM_ProgramBuild)->ArgName("cached")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(2);

} // namespace
} // namespace wv

BENCHMARK_MAIN();
