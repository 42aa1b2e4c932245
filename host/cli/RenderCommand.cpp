#include "../Error.h"
#include "../bvh/Bvh.h"
#include "../cluster/Cluster.h"
#include "../image/TechniqueImages.h"
#include "../render/MultiDeviceRender.h"
#include "../render/Renderer.h"
#include "../scene/GltfLoader.h"
#include "Commands.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace wv {

std::string defaultScenePath()
{
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        fs::path installed = exe.parent_path().parent_path() / "share" / "wavevcm" / "scenes" / "cornell-box.gltf";
        if (fs::exists(installed, ec)) return installed.string();
    }
    return (fs::path(WAVEVCM_SOURCE_DIR) / "scenes" / "cornell-box.gltf").string();
}

// One line on stderr, redrawn after each iteration (at most 10 times a
// second): iterations, samples/s, elapsed and remaining time.
class ProgressBar {
public:
    ProgressBar(bool enabled, int iterations, double seconds) : enabled_(enabled), iterations_(iterations), seconds_(seconds) {}

    void update(int done, double elapsed, double samplesPerIteration)
    {
        if (!enabled_ || (elapsed - lastDraw_ < 0.1 && done != iterations_)) return;
        lastDraw_ = elapsed;
        double fraction = iterations_ > 0 ? double(done) / iterations_ : 0.0;
        if (seconds_ > 0) fraction = std::max(fraction, std::min(1.0, elapsed / seconds_));
        double remaining = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0.0;
        const int width = 20;
        int filled = int(fraction * width);
        std::string bar = std::string(filled, '=') + std::string(width - filled, ' ');
        // Short enough for an 80-column terminal, or \r cannot redraw it.
        std::fprintf(stderr, "\r[%s] %d it %.2g samples/s %.1fs, %.1fs left  ", bar.c_str(), done,
                     done * samplesPerIteration / elapsed, elapsed, remaining);
        std::fflush(stderr);
        drawn_ = true;
    }
    void finish()
    {
        if (drawn_) std::fputc('\n', stderr);
    }

private:
    bool enabled_, drawn_ = false;
    int iterations_;
    double seconds_, lastDraw_ = -1;
};

// The --error-log CSV: one row per iteration.
class ErrorLog {
public:
    ErrorLog(const std::string& path, Image reference, const std::string& referencePath)
        : path_(path), reference_(std::move(reference)), out_(path)
    {
        if (!out_) throw Error(path + ": cannot write");
        out_ << "# reference: " << referencePath << "\nseconds,iterations,rmse,relmse\n";
    }
    int width() const { return reference_.width; }
    int height() const { return reference_.height; }
    void add(double seconds, int iterations, const Image& image)
    {
        ImageDifference d = compareImages(image, reference_);
        out_ << seconds << "," << iterations << "," << d.rmse << "," << d.relMse << "\n";
        if (!out_) throw Error(path_ + ": cannot write");
    }

private:
    std::string path_;
    Image reference_;
    std::ofstream out_;
};

static double since(std::chrono::steady_clock::time_point t)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Ctrl-C (SIGINT) or SIGTERM during a render: the step in flight (setup,
// or the current iteration) finishes, the image so far is written, and the
// exit status is 128 + the signal. The handler is reset on delivery
// (SA_RESETHAND), so a second Ctrl-C ends the process at once, except while
// files are written (WritingFiles), so that none is left half-written.
static std::atomic<int> interruptSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "set from a signal handler");

extern "C" void onInterrupt(int signal)
{
    interruptSignal = signal;
    // write(2), not stdio: the only output that is safe in a signal handler.
    static const char message[] = "\nwavevcm: interrupted: finishing the step in flight (again to stop at once)\n";
    ssize_t ignored = ::write(STDERR_FILENO, message, sizeof message - 1);
    (void)ignored;
}

static void catchInterrupts()
{
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    action.sa_flags = SA_RESETHAND | SA_RESTART;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

// SIGINT and SIGTERM ignored while it lives: the files are written (a
// moment) and the process ends right after. Ignoring, not blocking: a
// blocked signal would still reach the driver's threads.
class WritingFiles {
public:
    WritingFiles()
    {
        struct sigaction ignore {};
        ignore.sa_handler = SIG_IGN;
        sigemptyset(&ignore.sa_mask);
        sigaction(SIGINT, &ignore, &savedInt_);
        sigaction(SIGTERM, &ignore, &savedTerm_);
    }
    ~WritingFiles()
    {
        sigaction(SIGINT, &savedInt_, nullptr);
        sigaction(SIGTERM, &savedTerm_, nullptr);
    }
    WritingFiles(const WritingFiles&) = delete;
    WritingFiles& operator=(const WritingFiles&) = delete;

private:
    struct sigaction savedInt_ {}, savedTerm_ {};
};

// What the ranks of a job rendered together (a lone process is a job of
// one rank): images summed over the ranks by iteration count, in double, on
// rank 0; the counts on every rank.
struct JobResult {
    Image image;
    std::array<Image, 3> techniques; // RenderSettings::techniques
    int iterations = 0;
    uint64_t nonFinite = 0, rays = 0;
};

// Collective: every rank calls it at the same point.
static JobResult gatherJob(MultiDeviceRender& render, const RenderSettings& settings)
{
    const int local = render.iterations();
    std::vector<Image> images{render.image()};
    if (settings.techniques) {
        std::array<Image, 3> families = render.techniqueImages();
        images.insert(images.end(), families.begin(), families.end());
    }
    const size_t pixels = size_t(settings.width) * size_t(settings.height) * 3;
    // Each rank's images are means of its own iterations: sum mean × count,
    // and the counts, in one reduction; counts below 2^53 are exact in double.
    std::vector<double> sums(images.size() * pixels + 3, 0.0);
    for (size_t k = 0; k < images.size(); ++k)
        if (images[k].rgb.size() == pixels)
            for (size_t i = 0; i < pixels; ++i) sums[k * pixels + i] = double(images[k].rgb[i]) * local;
    sums[images.size() * pixels] = local;
    sums[images.size() * pixels + 1] = double(render.nonFiniteCount());
    sums[images.size() * pixels + 2] = double(render.raysTraced());
    cluster::sumOnRoot(sums);

    JobResult job;
    job.iterations = int(sums[images.size() * pixels]);
    job.nonFinite = uint64_t(sums[images.size() * pixels + 1]);
    job.rays = uint64_t(sums[images.size() * pixels + 2]);
    if (cluster::rank() != 0 || job.iterations == 0) return job;
    auto mean = [&](size_t k) {
        Image out(settings.width, settings.height);
        for (size_t i = 0; i < pixels; ++i) out.rgb[i] = float(sums[k * pixels + i] / job.iterations);
        return out;
    };
    job.image = mean(0);
    if (settings.techniques)
        for (size_t k = 0; k < 3; ++k)
            if (images[k + 1].rgb.size() == pixels) job.techniques[k] = mean(k + 1);
    return job;
}

static void writeOutputs(const RenderOptions& o, const RenderSettings& settings, const JobResult& job)
{
    writeImage(o.output, job.image);
    if (settings.techniques) {
        fs::path stem = fs::path(o.output).parent_path() / fs::path(o.output).stem();
        writeTechniqueImages(stem.string(), job.techniques);
    }
}

int runRender(const RenderOptions& o)
{
    const int rank = cluster::rank(), ranks = cluster::size();
    const bool root = rank == 0;
    const bool quiet = o.quiet || !root; // the other ranks print errors only
    validateRenderOptions(o);
    parseAlgorithm(o.algorithm); // before anything else, as the other options
    // Check the output's format before the render, not after it.
    checkOutputFormat(o.output);
    if (!o.aov.empty() && !haveImageLibrary()) // --aov writes STEM.techniques.exr
        checkOutputFormat((fs::path(o.output).parent_path() / fs::path(o.output).stem()).string() + ".techniques.exr");
    if (ranks > 1 && !o.errorLog.empty())
        throw Error("--error-log needs a single process, not an MPI job of " + std::to_string(ranks) + " ranks");
    if (root) { // rank 0 writes every file; the others none
        checkWritable(o.output);
        if (!o.statsFile.empty()) checkWritable(o.statsFile);
    }
    catchInterrupts();

    auto setupStart = std::chrono::steady_clock::now();
    std::string scenePath = o.scene.empty() ? defaultScenePath() : o.scene;
    Scene scene = prepareScene(o, scenePath);
    RenderSettings settings = renderSettings(o, scene);
    std::vector<DeviceInfo> selected = selectDevices(enumerateDevices(), o.device);
    std::unique_ptr<ErrorLog> errorLog;
    if (!o.errorLog.empty()) {
        if (o.reference.empty()) throw Error("--error-log needs --reference");
        errorLog = std::make_unique<ErrorLog>(o.errorLog, readImage(o.reference), o.reference);
        if (errorLog->width() != settings.width || errorLog->height() != settings.height)
            throw Error(o.reference + " is " + std::to_string(errorLog->width()) + "x" +
                        std::to_string(errorLog->height()) + " but the render is " + std::to_string(settings.width) +
                        "x" + std::to_string(settings.height) + " (set --width/--height)");
    }

    // The job's iterations: -n counts their samples per pixel
    // (--samples-per-iteration in each), whichever rank renders them; rank r
    // of R takes the global indices r, r + R, r + 2R, … (so the random
    // numbers and merge radii are those of one process rendering them all).
    // -t is the job's budget: every rank renders until it is spent, from the
    // moment all of them are ready.
    const int perIteration = settings.samplesPerIteration;
    int spp = o.spp > 0 ? o.spp : (o.seconds > 0 ? 0 : 16);
    if (spp % perIteration != 0) {
        if (o.spp > 0)
            throw Error("--spp " + std::to_string(spp) + " is not a multiple of --samples-per-iteration " +
                        std::to_string(perIteration));
        spp += perIteration - spp % perIteration; // the default 16, rounded up
    }
    const int iterationsWanted = spp / perIteration;

    // Each selected device as its pipelines (one renderer each); a job of
    // under 4 iterations per rank keeps one, since an iteration is never
    // split and one on half of the cores takes ~1.6x as long as on all.
    auto pipelinesOf = [&](const DeviceInfo& d) {
        if (o.pipelines > 0) return o.pipelines;
        return iterationsWanted > 0 && iterationsWanted < 4 * ranks ? 1 : defaultPipelines(d);
    };
    std::vector<DeviceInfo> chosen;
    for (const DeviceInfo& d : selected)
        for (const DeviceInfo& p : pipelineDevices(d, pipelinesOf(d))) chosen.push_back(p);

    const std::vector<Bvh> trees = buildBvhs(scene.vertices, chosen);
    const Bvh& bvh = bvhFor(trees, chosen[0]); // for the statistics
    DeviceContexts contexts(chosen, o.profile);
    MultiDeviceRender render(contexts.pointers, scene, trees, settings);
    double setupSeconds = since(setupStart);
    for (size_t i = 0; i < render.deviceCount() && !quiet; ++i)
        std::fprintf(stderr, "wavevcm: %s, %zu triangles, %dx%d, %s on %s (%s); setup %.2f s (kernels %.2f s%s)\n",
                     scenePath.c_str(), scene.triangleCount(), settings.width, settings.height, o.algorithm.c_str(),
                     chosen[i].label().c_str(), chosen[i].platformName.c_str(), setupSeconds,
                     render.renderer(i).programBuild().seconds,
                     render.renderer(i).programBuild().fromCache                               ? ", cached"
                     : render.renderer(i).programBuild().cache == ProgramBuild::Cache::Driver ? ", driver's cache"
                                                                                               : "");
    if (ranks > 1 && !quiet)
        std::fprintf(stderr, "wavevcm: MPI job of %d ranks; rank 0 on %s writes the outputs\n", ranks,
                     cluster::hostName().c_str());

    const IterationSchedule schedule{rank, ranks, iterationsWanted};
    ProgressBar progress(!quiet && ::isatty(STDERR_FILENO), iterationsWanted, o.seconds);
    std::vector<int> iterationsByRank(size_t(ranks), 0);
    // Render time excludes the error log's work (reading the image back and
    // comparing it; with K pipelines 1/K of it, the others rendering
    // meanwhile), so the log's times are what the render took.
    auto iterationDone = [&](Renderer& renderer, int iterations, double seconds) {
        if (errorLog) errorLog->add(seconds, iterations, render.runningImage(renderer));
        cluster::reportProgress(iterations);
        if (!root) return;
        cluster::readProgress(iterationsByRank);
        iterationsByRank[0] = iterations;
        int job = 0;
        for (int n : iterationsByRank) job += n;
        progress.update(job, seconds, double(settings.width) * settings.height * settings.samplesPerIteration);
    };
    // Before each iteration: this process interrupted (then the other ranks
    // are told), or another rank was.
    auto stop = [] {
        if (interruptSignal != 0) cluster::requestStop();
        return interruptSignal != 0 || cluster::stopRequested();
    };
    cluster::barrier();
    const auto jobStart = std::chrono::steady_clock::now();
    // In pieces between checkpoints; after each, the ranks agree whether the
    // job is over: when all have rendered their share or spent the budget,
    // or one was interrupted (mpirun signals every rank).
    JobResult job;
    bool interrupted = false;
    for (int checkpoint = 1;; ++checkpoint) {
        double until = o.seconds;
        if (o.checkpoint > 0 && (until == 0 || checkpoint * o.checkpoint < until)) until = checkpoint * o.checkpoint;
        double budget = until > 0 ? std::max(until - since(jobStart), 1e-9) : 0.0;
        // In a job, an interrupt drops the iterations in flight: mpirun sends
        // SIGTERM to every rank and SIGKILL a second later
        // (odls_base_sigkill_timeout), too soon to finish a large iteration.
        render.run(schedule, budget, stop, iterationDone, ranks > 1 ? std::function<bool()>(stop) : nullptr);
        bool finished = (schedule.count() >= 0 && render.iterations() >= schedule.count()) ||
                        (o.seconds > 0 && since(jobStart) >= o.seconds);
        interrupted = cluster::anyRank(stop());
        bool over = interrupted || !cluster::anyRank(!finished);
        job = gatherJob(render, settings);
        if (over) break;
        if (root && job.iterations > 0) {
            WritingFiles writing;
            writeOutputs(o, settings, job);
            if (!quiet)
                std::fprintf(stderr, "%swavevcm: checkpoint after %.1f s: %d iterations -> %s\n",
                             ::isatty(STDERR_FILENO) ? "\n" : "", since(jobStart), job.iterations, o.output.c_str());
        }
    }
    const double renderSeconds = cluster::maxOverRanks(render.seconds());
    const std::vector<int> rankIterations = cluster::gatherInts(render.iterations());
    const std::vector<double> rankSeconds = cluster::gatherDoubles(render.seconds());
    std::string deviceNames;
    for (size_t i = 0; i < chosen.size(); ++i) deviceNames += (i ? "\n" : "") + chosen[i].label();
    const std::vector<std::string> rankDevices = cluster::gatherStrings(deviceNames);
    const std::vector<std::string> rankHosts = cluster::gatherStrings(cluster::hostName());
    progress.finish();
    // Interrupted: 128 + the signal, on every rank (another rank's, if this
    // one got none).
    const int signal = interruptSignal != 0 ? int(interruptSignal) : SIGINT;
    const int exitCode = interrupted ? 128 + signal : 0;
    if (!root) return exitCode;
    if (interrupted) {
        if (job.iterations == 0) {
            std::fprintf(stderr, "wavevcm: interrupted (%s) before the first iteration: no image written\n",
                         interruptSignal != 0 ? strsignal(signal) : "on another rank");
            return exitCode;
        }
        std::fprintf(stderr, "wavevcm: interrupted (%s): writing the %d iterations rendered so far\n",
                     interruptSignal != 0 ? strsignal(signal) : "on another rank", job.iterations);
    }
    WritingFiles writing;
    writeOutputs(o, settings, job);
    // Camera samples: per pixel, iterations × samples per iteration.
    const double samplesPerIterationOfImage = double(settings.width) * settings.height * perIteration;
    double samplesPerSecond = samplesPerIterationOfImage * job.iterations / renderSeconds;
    double raysPerSecond = double(job.rays) / renderSeconds;
    if (!quiet) {
        std::string spp = perIteration > 1 ? " (" + std::to_string(job.iterations * perIteration) +
                                                 " samples per pixel)"
                                           : "";
        std::fprintf(stderr, "wavevcm: %d iterations%s in %.2f s (%.3g samples/s, %.3g rays/s) -> %s\n",
                     job.iterations, spp.c_str(), renderSeconds, samplesPerSecond, raysPerSecond, o.output.c_str());
    }
    for (size_t i = 0; i < render.deviceCount() && o.profile; ++i) {
        const Renderer& renderer = render.renderer(i);
        double total = 0;
        for (const auto& [name, stats] : renderer.kernelStats()) total += stats.seconds;
        if (render.deviceCount() > 1 || ranks > 1)
            std::fprintf(stderr, "wavevcm: on %s%s:\n", chosen[i].label().c_str(), ranks > 1 ? " (rank 0)" : "");
        for (const auto& [name, stats] : renderer.kernelStats())
            std::fprintf(stderr, "wavevcm: kernel %-20s %8.3f s  %5.1f %%  %10.3g items/s\n", name.c_str(),
                         stats.seconds, 100 * stats.seconds / total, double(stats.items) / stats.seconds);
    }
    if (job.nonFinite > 0)
        std::fprintf(stderr, "wavevcm: warning: %llu samples were NaN or Inf and were dropped\n",
                     static_cast<unsigned long long>(job.nonFinite));

    if (!o.statsFile.empty()) {
        size_t deviceBytes = 0; // every renderer's buffers
        for (size_t i = 0; i < render.deviceCount(); ++i) deviceBytes += render.renderer(i).deviceBytes();
        nlohmann::json stats = {
            {"scene", scenePath},
            {"device", chosen[0].name},
            {"platform", chosen[0].platformName},
            {"algorithm", o.algorithm},
            {"width", settings.width},
            {"height", settings.height},
            {"iterations", job.iterations},
            {"render_seconds", renderSeconds},
            {"setup_seconds", setupSeconds},
            {"samples_per_second", samplesPerSecond},
            {"rays_per_second", raysPerSecond},
            {"nan_count", job.nonFinite},
            {"triangles", scene.triangleCount()},
            {"bvh_nodes", bvh.nodes.size()},
            {"bvh_depth", bvh.depth},
            {"bvh_triangle_packets", bvh.packetCount()},
            {"bvh_packet_width", bvh.packetWidth()},
            {"bvh_sah_cost", bvh.sahCost},
            {"bvh_build_seconds", bvh.buildSeconds},
            {"kernel_build_seconds", render.renderer(0).programBuild().seconds},
            {"kernel_cache", cacheName(render.renderer(0).programBuild().cache)},
            {"kernel_cache_hit", render.renderer(0).programBuild().fromCache},
            {"kernel_build_options", render.renderer(0).programBuild().options},
            {"wavefront", render.renderer(0).wavefront()},
            {"rounds_ahead", render.renderer(0).roundsAhead()},
            {"samples_per_iteration", perIteration},
            {"merge_radius", render.renderer(0).mergeRadius()},
            {"scene_origin", {scene.origin[0], scene.origin[1], scene.origin[2]}},
            {"device_bytes", deviceBytes},
            {"ranks", ranks},
            {"pipelines", chosen.size()},
        };
        // Each device's share (several with -d 0,2 or -d all), of this process (rank 0).
        stats["devices"] = nlohmann::json::array();
        for (size_t i = 0; i < render.deviceCount(); ++i) {
            stats["devices"].push_back(
                {{"device", chosen[i].name},
                 {"platform", chosen[i].platformName},
                 {"pipeline", chosen[i].pipeline},
                 {"compute_units", chosen[i].computeUnits},
                 {"iterations", render.renderer(i).iterations()},
                 {"device_bytes", render.renderer(i).deviceBytes()},
                 {"samples_per_second", samplesPerIterationOfImage * render.renderer(i).iterations() / renderSeconds}});
            if (o.profile) // the figures --profile prints, exact, for scripts (e.g. instructions per item)
                for (const auto& [name, kernel] : render.renderer(i).kernelStats())
                    stats["devices"].back()["kernels"][name] = {{"seconds", kernel.seconds}, {"items", kernel.items}};
        }
        // Each rank's share of the job (one entry without mpirun).
        stats["rank_stats"] = nlohmann::json::array();
        for (int r = 0; r < ranks; ++r) {
            nlohmann::json names = nlohmann::json::array();
            std::stringstream list(rankDevices[size_t(r)]);
            for (std::string name; std::getline(list, name);) names.push_back(name);
            stats["rank_stats"].push_back(
                {{"rank", r},
                 {"host", rankHosts[size_t(r)]},
                 {"devices", names},
                 {"iterations", rankIterations[size_t(r)]},
                 {"render_seconds", rankSeconds[size_t(r)]},
                 {"samples_per_second", samplesPerIterationOfImage * rankIterations[size_t(r)] /
                                            std::max(rankSeconds[size_t(r)], 1e-9)}});
        }
        // Device memory per texture (one float4 per texel).
        size_t textureBytes = 0;
        stats["textures"] = nlohmann::json::array();
        for (const Texture& t : scene.textures) {
            size_t bytes = size_t(t.image.width) * size_t(t.image.height) * 16;
            textureBytes += bytes;
            stats["textures"].push_back({{"name", t.name}, {"width", t.image.width}, {"height", t.image.height},
                                         {"bytes", bytes}});
        }
        stats["texture_bytes"] = textureBytes;
        std::ofstream out(o.statsFile);
        out << stats.dump(2) << "\n";
        if (!out) throw Error(o.statsFile + ": cannot write");
    }
    return exitCode;
}

} // namespace wv
