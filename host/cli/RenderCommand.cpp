#include "../Error.h"
#include "../bvh/Bvh.h"
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

int runRender(const RenderOptions& o)
{
    validateRenderOptions(o);
    parseAlgorithm(o.algorithm); // before anything else, as the other options
    // Check the output's format before the render, not after it.
    std::string ext = fs::path(o.output).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".exr" && ext != ".hdr" && ext != ".pfm" && ext != ".png" && ext != ".jpg" && ext != ".jpeg")
        throw Error(o.output + ": unsupported output format (use .exr, .hdr, .pfm, .png or .jpg)");
    checkWritable(o.output);
    if (!o.statsFile.empty()) checkWritable(o.statsFile);
    catchInterrupts();

    auto setupStart = std::chrono::steady_clock::now();
    std::string scenePath = o.scene.empty() ? defaultScenePath() : o.scene;
    Scene scene = prepareScene(o, scenePath);
    RenderSettings settings = renderSettings(o, scene);
    std::vector<DeviceInfo> chosen = selectDevices(enumerateDevices(), o.device);
    std::unique_ptr<ErrorLog> errorLog;
    if (!o.errorLog.empty()) {
        if (o.reference.empty()) throw Error("--error-log needs --reference");
        if (chosen.size() > 1) throw Error("--error-log needs a single device (-d)");
        errorLog = std::make_unique<ErrorLog>(o.errorLog, readImage(o.reference), o.reference);
        if (errorLog->width() != settings.width || errorLog->height() != settings.height)
            throw Error(o.reference + " is " + std::to_string(errorLog->width()) + "x" +
                        std::to_string(errorLog->height()) + " but the render is " + std::to_string(settings.width) +
                        "x" + std::to_string(settings.height) + " (set --width/--height)");
    }

    Bvh bvh = buildBvh(scene.vertices);
    std::vector<std::unique_ptr<DeviceContext>> contexts;
    std::vector<DeviceContext*> devices;
    for (const DeviceInfo& d : chosen) {
        contexts.push_back(std::make_unique<DeviceContext>(d, o.profile));
        devices.push_back(contexts.back().get());
    }
    MultiDeviceRender render(devices, scene, bvh, settings);
    double setupSeconds = since(setupStart);
    for (size_t i = 0; i < render.deviceCount() && !o.quiet; ++i)
        std::fprintf(stderr, "wavevcm: %s, %zu triangles, %dx%d, %s on %s (%s); setup %.2f s (kernels %.2f s%s)\n",
                     scenePath.c_str(), scene.triangleCount(), settings.width, settings.height, o.algorithm.c_str(),
                     chosen[i].name.c_str(), chosen[i].platformName.c_str(), setupSeconds,
                     render.renderer(i).programBuild().seconds,
                     render.renderer(i).programBuild().fromCache ? ", cached" : "");

    int spp = o.spp > 0 ? o.spp : (o.seconds > 0 ? 0 : 16);
    ProgressBar progress(!o.quiet && ::isatty(STDERR_FILENO), spp, o.seconds);
    // Render time excludes the error log's work (reading the image back and
    // comparing it), so the log's times are what the render alone took.
    render.run(spp, o.seconds, [] { return interruptSignal != 0; },
               [&](Renderer& renderer, int iterations, double seconds) {
                   if (errorLog) errorLog->add(seconds, iterations, renderer.image());
                   progress.update(iterations, seconds, double(settings.width) * settings.height);
               });
    const double renderSeconds = render.seconds();
    progress.finish();
    int exitCode = 0;
    int signal = interruptSignal;
    if (signal) {
        exitCode = 128 + signal;
        if (render.iterations() == 0) {
            std::fprintf(stderr, "wavevcm: interrupted (%s) before the first iteration: no image written\n",
                         strsignal(signal));
            return exitCode;
        }
        std::fprintf(stderr, "wavevcm: interrupted (%s): writing the %d iterations rendered so far\n",
                     strsignal(signal), render.iterations());
    }
    WritingFiles writing;

    Image image = render.image();
    uint64_t nonFinite = render.nonFiniteCount();
    writeImage(o.output, image);
    if (settings.techniques) {
        fs::path stem = fs::path(o.output).parent_path() / fs::path(o.output).stem();
        writeTechniqueImages(stem.string(), render.techniqueImages());
    }
    double samplesPerSecond = double(settings.width) * settings.height * render.iterations() / renderSeconds;
    double raysPerSecond = double(render.raysTraced()) / renderSeconds;
    if (!o.quiet)
        std::fprintf(stderr, "wavevcm: %d iterations in %.2f s (%.3g samples/s, %.3g rays/s) -> %s\n",
                     render.iterations(), renderSeconds, samplesPerSecond, raysPerSecond, o.output.c_str());
    for (size_t i = 0; i < render.deviceCount() && o.profile; ++i) {
        const Renderer& renderer = render.renderer(i);
        double total = 0;
        for (const auto& [name, stats] : renderer.kernelStats()) total += stats.seconds;
        if (render.deviceCount() > 1) std::fprintf(stderr, "wavevcm: on %s:\n", chosen[i].name.c_str());
        for (const auto& [name, stats] : renderer.kernelStats())
            std::fprintf(stderr, "wavevcm: kernel %-20s %8.3f s  %5.1f %%  %10.3g items/s\n", name.c_str(),
                         stats.seconds, 100 * stats.seconds / total, double(stats.items) / stats.seconds);
    }
    if (nonFinite > 0)
        std::fprintf(stderr, "wavevcm: warning: %llu samples were NaN or Inf and were dropped\n",
                     static_cast<unsigned long long>(nonFinite));

    if (!o.statsFile.empty()) {
        nlohmann::json stats = {
            {"scene", scenePath},
            {"device", chosen[0].name},
            {"platform", chosen[0].platformName},
            {"algorithm", o.algorithm},
            {"width", settings.width},
            {"height", settings.height},
            {"iterations", render.iterations()},
            {"render_seconds", renderSeconds},
            {"setup_seconds", setupSeconds},
            {"samples_per_second", samplesPerSecond},
            {"rays_per_second", raysPerSecond},
            {"nan_count", nonFinite},
            {"triangles", scene.triangleCount()},
            {"bvh_nodes", bvh.nodes.size()},
            {"bvh_depth", bvh.depth},
            {"bvh_triangle_packets", bvh.packets.size()},
            {"bvh_sah_cost", bvh.sahCost},
            {"bvh_build_seconds", bvh.buildSeconds},
            {"kernel_build_seconds", render.renderer(0).programBuild().seconds},
            {"kernel_cache_hit", render.renderer(0).programBuild().fromCache},
            {"wavefront", render.renderer(0).wavefront()},
            {"merge_radius", render.renderer(0).mergeRadius()},
            {"scene_origin", {scene.origin[0], scene.origin[1], scene.origin[2]}},
            {"device_bytes", render.renderer(0).deviceBytes()},
        };
        // Each device's share (several with -d 0,2 or -d all).
        stats["devices"] = nlohmann::json::array();
        for (size_t i = 0; i < render.deviceCount(); ++i)
            stats["devices"].push_back(
                {{"device", chosen[i].name},
                 {"platform", chosen[i].platformName},
                 {"iterations", render.renderer(i).iterations()},
                 {"samples_per_second",
                  double(settings.width) * settings.height * render.renderer(i).iterations() / renderSeconds}});
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
