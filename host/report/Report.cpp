#include "Report.h"

#include "Error.h"
#include "bvh/Bvh.h"
#include "cl/Devices.h"
#include "image/Image.h"
#include "image/TechniqueImages.h"
#include "render/MultiDeviceRender.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <unistd.h>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace wv {
namespace {

// One line on stderr over the whole report: the fraction of its render time
// spent, and what it is rendering.
class ReportProgress {
public:
    ReportProgress(bool enabled, double totalSeconds) : enabled_(enabled), total_(totalSeconds) {}
    void update(double doneSeconds, const std::string& what)
    {
        if (!enabled_) return;
        auto now = std::chrono::steady_clock::now();
        if (drawn_ && std::chrono::duration<double>(now - lastDraw_).count() < 0.1) return;
        lastDraw_ = now;
        double fraction = std::min(1.0, doneSeconds / total_);
        const int width = 20;
        int filled = int(fraction * width);
        std::fprintf(stderr, "\r[%s%s] %3.0f%% %-40.40s", std::string(filled, '=').c_str(),
                     std::string(width - filled, ' ').c_str(), 100 * fraction, what.c_str());
        std::fflush(stderr);
        drawn_ = true;
    }
    void finish()
    {
        if (drawn_) std::fputc('\n', stderr);
        drawn_ = false;
    }

private:
    bool enabled_, drawn_ = false;
    double total_;
    std::chrono::steady_clock::time_point lastDraw_;
};

struct LogPoint {
    double seconds;
    int iterations;
    double rmse, relMse;
};

struct AlgorithmResult {
    std::string name;
    int iterations = 0;
    double seconds = 0, samplesPerSecond = 0;
    ImageDifference error;
    double slope = std::numeric_limits<double>::quiet_NaN();
    double efficiency = 0; // 1 / (relMSE × seconds), relative to the first reference algorithm
    std::vector<LogPoint> log;
    Image image;
};

struct SceneResult {
    std::string path, name;
    int width = 0, height = 0;
    std::string reference; // how it was made
    int cropX = 0, cropY = 0, cropSize = 0;
    std::vector<AlgorithmResult> algorithms;
    bool techniques = false; // vcm's technique images exist
};

// Least-squares slope of log relMSE against log time over the points past
// a tenth of the render time (the first iterations are start-up); −1 for an
// unbiased estimator whose samples cost the same throughout.
double fittedSlope(const std::vector<LogPoint>& log, double seconds)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (const LogPoint& p : log) {
        if (p.seconds < 0.1 * seconds || !(p.relMse > 0)) continue;
        double x = std::log(p.seconds), y = std::log(p.relMse);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
        ++n;
    }
    double d = n * sxx - sx * sx;
    return n >= 2 && d > 0 ? (n * sxy - sx * sy) / d : std::numeric_limits<double>::quiet_NaN();
}

std::string escape(const std::string& s)
{
    std::string out;
    for (char c : s) {
        if (c == '&') out += "&amp;";
        else if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

std::string number(double v)
{
    if (!std::isfinite(v)) return "n/a";
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

const char* colorOf(const std::string& algorithm)
{
    static const std::map<std::string, const char*> colors{{"pt", "#1f77b4"},  {"lt", "#ff7f0e"},
                                                           {"bpt", "#2ca02c"}, {"ppm", "#d62728"},
                                                           {"bpm", "#9467bd"}, {"vcm", "#8c564b"}};
    auto it = colors.find(algorithm);
    return it == colors.end() ? "#333333" : it->second;
}

// relMSE against time of every algorithm on log-log axes, decade grid
// lines, each line's fitted slope in the legend.
void writeErrorPlot(const std::string& path, const SceneResult& scene)
{
    double t0 = 1e300, t1 = 0, e0 = 1e300, e1 = 0;
    for (const AlgorithmResult& a : scene.algorithms)
        for (const LogPoint& p : a.log)
            if (p.seconds > 0 && p.relMse > 0) {
                t0 = std::min(t0, p.seconds), t1 = std::max(t1, p.seconds);
                e0 = std::min(e0, p.relMse), e1 = std::max(e1, p.relMse);
            }
    if (!(t1 > 0)) t0 = 0.1, t1 = 1, e0 = 0.1, e1 = 1;
    double lt0 = std::floor(std::log10(t0)), lt1 = std::max(lt0 + 1, std::ceil(std::log10(t1)));
    double le0 = std::floor(std::log10(e0)), le1 = std::max(le0 + 1, std::ceil(std::log10(e1)));
    const double W = 680, H = 420, left = 70, right = 190, top = 20, bottom = 50;
    auto X = [&](double t) { return left + (std::log10(t) - lt0) / (lt1 - lt0) * (W - left - right); };
    auto Y = [&](double e) { return top + (le1 - std::log10(e)) / (le1 - le0) * (H - top - bottom); };
    std::ostringstream s;
    s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
      << " " << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    for (double k = lt0; k <= lt1; ++k)
        s << "<line x1=\"" << X(std::pow(10, k)) << "\" y1=\"" << top << "\" x2=\"" << X(std::pow(10, k)) << "\" y2=\""
          << H - bottom << "\" stroke=\"#ddd\"/><text x=\"" << X(std::pow(10, k)) << "\" y=\"" << H - bottom + 16
          << "\" text-anchor=\"middle\">1e" << k << "</text>\n";
    for (double k = le0; k <= le1; ++k)
        s << "<line x1=\"" << left << "\" y1=\"" << Y(std::pow(10, k)) << "\" x2=\"" << W - right << "\" y2=\""
          << Y(std::pow(10, k)) << "\" stroke=\"#ddd\"/><text x=\"" << left - 6 << "\" y=\"" << Y(std::pow(10, k)) + 4
          << "\" text-anchor=\"end\">1e" << k << "</text>\n";
    s << "<text x=\"" << (left + W - right) / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">render time (s)</text>\n"
      << "<text x=\"16\" y=\"" << (top + H - bottom) / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 16 "
      << (top + H - bottom) / 2 << ")\">relMSE</text>\n";
    int row = 0;
    for (const AlgorithmResult& a : scene.algorithms) {
        s << "<polyline fill=\"none\" stroke-width=\"2\" stroke=\"" << colorOf(a.name) << "\" points=\"";
        for (const LogPoint& p : a.log)
            if (p.seconds > 0 && p.relMse > 0) s << X(p.seconds) << "," << Y(p.relMse) << " ";
        s << "\"/>\n";
        double y = top + 10 + 18 * row++;
        s << "<line x1=\"" << W - right + 10 << "\" y1=\"" << y << "\" x2=\"" << W - right + 30 << "\" y2=\"" << y
          << "\" stroke-width=\"2\" stroke=\"" << colorOf(a.name) << "\"/><text x=\"" << W - right + 36 << "\" y=\""
          << y + 4 << "\">" << escape(a.name) << " (slope " << number(a.slope) << ")</text>\n";
    }
    s << "</svg>\n";
    std::ofstream out(path);
    out << s.str();
    if (!out) throw Error(path + ": cannot write");
}

// The square block (an eighth of the image's smaller side, at least 4
// pixels) with the highest relMSE summed over the algorithms.
void findHardestRegion(SceneResult& scene, const Image& reference)
{
    int b = std::max(4, std::min(scene.width, scene.height) / 8);
    b = std::min({b, scene.width, scene.height});
    double best = -1;
    for (int y0 = 0; y0 + b <= scene.height; y0 += b)
        for (int x0 = 0; x0 + b <= scene.width; x0 += b) {
            double sum = 0;
            for (const AlgorithmResult& a : scene.algorithms)
                for (int y = y0; y < y0 + b; ++y)
                    for (int x = x0; x < x0 + b; ++x)
                        for (int c = 0; c < 3; ++c) {
                            size_t i = 3 * (size_t(y) * size_t(scene.width) + size_t(x)) + size_t(c);
                            double r = reference.rgb[i], d = a.image.rgb[i] - r;
                            sum += d * d / (r * r + 0.01);
                        }
            if (sum > best) best = sum, scene.cropX = x0, scene.cropY = y0;
        }
    scene.cropSize = b;
}

// The crop, enlarged by repeating pixels to about 160 pixels across.
Image crop(const Image& image, int x0, int y0, int size)
{
    int scale = std::max(1, 160 / size);
    Image out(size * scale, size * scale);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < 3; ++c)
                out.rgb[3 * (size_t(y) * size_t(out.width) + size_t(x)) + size_t(c)] =
                    image.rgb[3 * (size_t(y0 + y / scale) * size_t(image.width) + size_t(x0 + x / scale)) + size_t(c)];
    return out;
}

json toJson(const SceneResult& s)
{
    json algorithms = json::array();
    for (const AlgorithmResult& a : s.algorithms) {
        json log = json::array();
        for (const LogPoint& p : a.log) log.push_back({p.seconds, p.iterations, p.rmse, p.relMse});
        algorithms.push_back({{"algorithm", a.name},
                              {"iterations", a.iterations},
                              {"seconds", a.seconds},
                              {"samples_per_second", a.samplesPerSecond},
                              {"rmse", a.error.rmse},
                              {"relmse", a.error.relMse},
                              {"slope", std::isfinite(a.slope) ? json(a.slope) : json(nullptr)},
                              {"efficiency", a.efficiency},
                              {"image", a.name + ".png"},
                              {"exr", a.name + ".exr"},
                              {"log", log}});
    }
    return {{"scene", s.path},
            {"directory", s.name},
            {"width", s.width},
            {"height", s.height},
            {"reference", s.reference},
            {"crop", {s.cropX, s.cropY, s.cropSize}},
            {"algorithms", algorithms}};
}

std::string figure(const std::string& image, const std::string& link, const std::string& caption,
                   const char* kind = "")
{
    return std::string("<figure") + (*kind ? std::string(" class=\"") + kind + "\"" : "") + "><a href=\"" + escape(link) + "\"><img src=\"" + escape(image) + "\" alt=\"" + escape(caption) +
           "\"></a><figcaption>" + caption + "</figcaption></figure>\n";
}

std::string sceneHtml(const SceneResult& s, const std::string& baseline)
{
    const std::string d = s.name + "/";
    std::ostringstream h;
    h << "<section>\n<h2>" << escape(fs::path(s.path).filename().string()) << "</h2>\n<p>" << s.width << "×"
      << s.height << "; reference: " << escape(s.reference) << ".</p>\n<div class=\"row\">\n";
    for (const AlgorithmResult& a : s.algorithms)
        h << figure(d + a.name + ".png", d + a.name + ".exr",
                    "<b>" + escape(a.name) + "</b>: " + std::to_string(a.iterations) + " iterations, relMSE " +
                        number(a.error.relMse));
    h << figure(d + "reference.png", d + "reference.exr", "<b>reference</b>") << "</div>\n";
    h << "<h3>Hardest region</h3>\n<p>Pixels " << s.cropX << "–" << s.cropX + s.cropSize - 1 << " × " << s.cropY
      << "–" << s.cropY + s.cropSize - 1 << ", where relMSE summed over the algorithms is highest, enlarged:</p>\n"
      << "<div class=\"row\">\n";
    for (const AlgorithmResult& a : s.algorithms)
        h << figure(d + "crop-" + a.name + ".png", d + a.name + ".exr", escape(a.name), "crop");
    h << figure(d + "crop-reference.png", d + "reference.exr", "reference", "crop") << "</div>\n";
    h << "<h3>Error against time</h3>\n<p><img src=\"" << escape(d) << "error-vs-time.svg\" alt=\"relMSE against "
      << "render time\"></p>\n";
    if (s.techniques) {
        h << "<h3>vcm by technique</h3>\n<p>Each pixel's shares of vcm's image (red: unidirectional, green: vertex "
             "connection, blue: vertex merging), then each family's own image.</p>\n<div class=\"row\">\n"
          << figure(d + "vcm.techniques.png", d + "vcm.techniques.exr", "shares");
        for (const char* f : {"unidirectional", "connection", "merging"})
            h << figure(d + "vcm." + f + ".png", d + "vcm.techniques.exr", f);
        h << "</div>\n";
    }
    h << "<h3>Summary</h3>\n<table>\n<tr><th>algorithm</th><th>iterations</th><th>seconds</th><th>samples/s</th>"
      << "<th>relMSE</th><th>RMSE</th><th>slope</th><th>efficiency ÷ " << escape(baseline) << "'s</th></tr>\n";
    for (const AlgorithmResult& a : s.algorithms)
        h << "<tr><td>" << escape(a.name) << "</td><td>" << a.iterations << "</td><td>" << number(a.seconds)
          << "</td><td>" << number(a.samplesPerSecond) << "</td><td>" << number(a.error.relMse) << "</td><td>"
          << number(a.error.rmse) << "</td><td>" << number(a.slope) << "</td><td>" << number(a.efficiency)
          << "</td></tr>\n";
    h << "</table>\n</section>\n";
    return h.str();
}

void writePage(const ReportOptions& o, const std::vector<SceneResult>& scenes, const std::string& device,
               const std::string& baseline, bool complete)
{
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>wavevcm report</title>\n"
      << "<style>body{font-family:sans-serif;margin:2em;max-width:1400px}.row{display:flex;flex-wrap:wrap;gap:12px}"
         "figure{margin:0}figure img{display:block;width:256px;image-rendering:pixelated}figure.crop img{width:"
         "160px}figcaption{font-size:0.9em}table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}"
         "td:first-child{text-align:left}</style>\n</head>\n<body>\n<h1>wavevcm: algorithms at equal time</h1>\n"
      << "<p>Every algorithm rendered each scene for " << number(o.seconds) << " s on " << escape(device)
      << "; relMSE is the mean over pixels and channels of (image − reference)² / (reference² + 0.01). Slope: "
         "of log relMSE against log time past a tenth of the render (−1 for an unbiased estimator). Efficiency: "
         "1 / (relMSE × time), divided by "
      << escape(baseline) << "'s. Images link to their EXR files.</p>\n";
    if (!complete)
        h << "<p><b>Partial report:</b> " << scenes.size() << " of " << o.scenes.size() << " scenes so far.</p>\n";
    for (const SceneResult& s : scenes) h << sceneHtml(s, baseline);
    h << "</body>\n</html>\n";
    fs::path page = fs::path(o.outputDir) / "index.html", temp = page;
    temp += ".tmp";
    {
        std::ofstream out(temp);
        out << h.str();
        if (!out) throw Error(temp.string() + ": cannot write");
    }
    fs::rename(temp, page);

    // The summary tables in Markdown, for a README.
    std::ostringstream md;
    md << "| scene | algorithm | seconds | iterations | samples/s | relMSE | RMSE | slope | efficiency ÷ " << baseline
       << "'s |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for (const SceneResult& s : scenes)
        for (const AlgorithmResult& a : s.algorithms)
            md << "| " << s.name << " | " << a.name << " | " << number(a.seconds) << " | " << a.iterations << " | "
               << number(a.samplesPerSecond) << " | " << number(a.error.relMse) << " | " << number(a.error.rmse)
               << " | " << number(a.slope) << " | " << number(a.efficiency) << " |\n";
    std::ofstream summary(fs::path(o.outputDir) / "summary.md");
    summary << md.str();
    if (!summary) throw Error((fs::path(o.outputDir) / "summary.md").string() + ": cannot write");

    json all = {{"device", device}, {"seconds", o.seconds}, {"baseline", baseline}, {"complete", complete},
                {"scenes", json::array()}};
    for (const SceneResult& s : scenes) all["scenes"].push_back(toJson(s));
    std::ofstream out(fs::path(o.outputDir) / "report.json");
    out << all.dump(1) << "\n";
    if (!out) throw Error((fs::path(o.outputDir) / "report.json").string() + ": cannot write");
}

void validate(const ReportOptions& o)
{
    if (o.scenes.empty()) throw Error("report: no scene given");
    if (!(o.seconds > 0) || !std::isfinite(o.seconds)) throw Error("report: --time must be a positive number of seconds");
    if (o.referenceSeconds < 0 || !std::isfinite(o.referenceSeconds))
        throw Error("report: --reference-seconds must be a positive number of seconds");
    if (!o.references.empty() && o.references.size() != o.scenes.size())
        throw Error("report: " + std::to_string(o.references.size()) + " references for " +
                    std::to_string(o.scenes.size()) + " scenes (give one per scene, in order, or none)");
    if (o.algorithms.empty()) throw Error("report: no algorithm given");
    std::set<std::string> seen;
    for (const std::string& a : o.algorithms) {
        if (a == "el") throw Error("report: el is not a light transport algorithm (pt, lt, bpt, ppm, bpm, vcm)");
        parseAlgorithm(a);
        if (!seen.insert(a).second) throw Error("report: algorithm " + a + " given twice");
    }
    if (o.outputDir.empty()) throw Error("report: no output directory (-o DIR)");
    if (!haveImageLibrary())
        throw Error("report: this wavevcm was built without OpenImageIO (-DWAVEVCM_IMAGE_IO=OFF) and writes no "
                    "report images");
    if (o.render.device.find(',') != std::string::npos || o.render.device == "all")
        throw Error("report: -d takes one device (each render's time is measured on it)");
    for (const std::string& s : o.scenes)
        if (!fs::is_regular_file(s)) throw Error(s + ": no such file");
    for (const std::string& r : o.references)
        if (!fs::is_regular_file(r)) throw Error(r + ": no such file");
    if (o.render.samplesPerIteration != 1)
        throw Error("report: --samples-per-iteration is for render; report compares every algorithm at one sample "
                    "per pixel per iteration");
    validateRenderOptions(o.render);
}

} // namespace

void writeReport(const ReportOptions& o)
{
    validate(o);
    std::error_code ec;
    fs::create_directories(o.outputDir, ec);
    if (!fs::is_directory(o.outputDir)) throw Error(o.outputDir + ": cannot create the report directory");

    std::vector<DeviceInfo> devices = enumerateDevices();
    // The device as render uses it: its pipelines, each rendering whole
    // iterations, the running image of all of them logged after each.
    const DeviceInfo selected = selectDevice(devices, o.render.device);
    DeviceContexts contexts(
        pipelineDevices(selected, o.render.pipelines > 0 ? o.render.pipelines : defaultPipelines(selected)));
    const std::vector<DeviceContext*>& pipelines = contexts.pointers;
    const std::string deviceName =
        selected.name + (pipelines.size() > 1 ? " (" + std::to_string(pipelines.size()) + " pipelines)" : "");
    const double referenceSeconds = o.referenceSeconds > 0 ? o.referenceSeconds : 6 * o.seconds;
    const std::string baseline =
        std::find(o.algorithms.begin(), o.algorithms.end(), "pt") != o.algorithms.end() ? "pt" : o.algorithms[0];
    double total = double(o.scenes.size()) * (double(o.algorithms.size()) * o.seconds +
                                               (o.references.empty() ? referenceSeconds : 0.0));
    ReportProgress progress(!o.quiet && ::isatty(STDERR_FILENO), total);
    double done = 0;

    std::vector<SceneResult> results;
    std::set<std::string> names;
    for (size_t si = 0; si < o.scenes.size(); ++si) {
        SceneResult result;
        result.path = o.scenes[si];
        result.name = fs::path(result.path).stem().string();
        for (int k = 2; !names.insert(result.name).second; ++k)
            result.name = fs::path(result.path).stem().string() + "-" + std::to_string(k);
        const fs::path dir = fs::path(o.outputDir) / result.name;
        fs::create_directories(dir, ec);
        if (!fs::is_directory(dir)) throw Error(dir.string() + ": cannot create it");

        Scene scene = prepareScene(o.render, result.path);
        RenderSettings base = renderSettings(o.render, scene);
        result.width = base.width;
        result.height = base.height;
        const std::vector<Bvh> trees = buildBvhs(scene.vertices, {selected});

        // Renders `settings` for `seconds` of render time (whole iterations),
        // calling `after` after each iteration with the image, iterations and
        // time so far (its own work untimed). A throwaway render runs one
        // iteration per pipeline first: PoCL compiles each kernel's work-group
        // function at its first launch (seconds, cold), which would otherwise
        // be charged to whichever render came first.
        auto renderFor = [&](RenderSettings settings, double seconds, const std::string& what, auto after) {
            progress.update(done, result.name + ": " + what + " (warming up)");
            MultiDeviceRender(pipelines, scene, trees, settings)
                .run(IterationSchedule{0, 1, int(pipelines.size())}, 0, [] { return false; }, nullptr);
            auto render = std::make_unique<MultiDeviceRender>(pipelines, scene, trees, settings);
            render->run(IterationSchedule{}, seconds, [] { return false; },
                        [&](Renderer& finished, int iterations, double rendered) {
                            after(render->runningImage(finished), iterations, rendered);
                            progress.update(done + std::min(rendered, seconds), result.name + ": " + what);
                        });
            done += seconds;
            if (render->nonFiniteCount() > 0)
                std::fprintf(stderr, "\nwavevcm: warning: %s, %s: %llu NaN or Inf samples were dropped\n",
                             result.path.c_str(), what.c_str(),
                             static_cast<unsigned long long>(render->nonFiniteCount()));
            return render;
        };

        Image reference;
        if (!o.references.empty()) {
            reference = readImage(o.references[si]);
            result.reference = o.references[si];
            if (reference.width != base.width || reference.height != base.height)
                throw Error(o.references[si] + " is " + std::to_string(reference.width) + "x" +
                            std::to_string(reference.height) + " but the renders are " + std::to_string(base.width) +
                            "x" + std::to_string(base.height) + " (set --width/--height)");
        } else {
            RenderSettings settings = base;
            settings.algorithm = Algorithm::VertexConnectionMerging;
            settings.seed = base.seed + 0x9E3779B9u; // other samples than the renders it measures
            auto r = renderFor(settings, referenceSeconds, "reference", [](const Image&, int, double) {});
            reference = r->image();
            result.reference = "vcm, " + std::to_string(r->iterations()) + " iterations (" + number(r->seconds()) +
                               " s), another seed";
        }
        writeImage((dir / "reference.exr").string(), reference);
        writeImage((dir / "reference.png").string(), reference);

        for (const std::string& name : o.algorithms) {
            AlgorithmResult a;
            a.name = name;
            RenderSettings settings = base;
            settings.algorithm = parseAlgorithm(name);
            settings.techniques = name == "vcm";
            auto r = renderFor(settings, o.seconds, name, [&](const Image& image, int iterations, double rendered) {
                ImageDifference d = compareImages(image, reference);
                a.log.push_back({rendered, iterations, d.rmse, d.relMse});
            });
            a.image = r->image();
            a.iterations = r->iterations();
            a.seconds = r->seconds();
            a.samplesPerSecond = double(base.width) * base.height * a.iterations / a.seconds;
            a.error = compareImages(a.image, reference);
            a.slope = fittedSlope(a.log, o.seconds);
            writeImage((dir / (name + ".exr")).string(), a.image);
            writeImage((dir / (name + ".png")).string(), a.image);
            if (settings.techniques) {
                std::array<Image, 3> families = r->techniqueImages();
                writeTechniqueImages((dir / "vcm").string(), families);
                const char* familyNames[3] = {"unidirectional", "connection", "merging"};
                for (int f = 0; f < 3; ++f) writeImage((dir / ("vcm." + std::string(familyNames[f]) + ".png")).string(), families[f]);
                result.techniques = true;
            }
            result.algorithms.push_back(std::move(a));
        }
        double baseEfficiency = 0;
        for (AlgorithmResult& a : result.algorithms) {
            a.efficiency = a.error.relMse > 0 ? 1.0 / (a.error.relMse * a.seconds) : 0.0;
            if (a.name == baseline) baseEfficiency = a.efficiency;
        }
        for (AlgorithmResult& a : result.algorithms) a.efficiency = baseEfficiency > 0 ? a.efficiency / baseEfficiency : 0.0;

        findHardestRegion(result, reference);
        writeImage((dir / "crop-reference.png").string(), crop(reference, result.cropX, result.cropY, result.cropSize));
        for (const AlgorithmResult& a : result.algorithms)
            writeImage((dir / ("crop-" + a.name + ".png")).string(), crop(a.image, result.cropX, result.cropY, result.cropSize));
        writeErrorPlot((dir / "error-vs-time.svg").string(), result);
        for (AlgorithmResult& a : result.algorithms) a.image = Image(); // the files have them
        results.push_back(std::move(result));
        progress.finish();
        writePage(o, results, deviceName, baseline, results.size() == o.scenes.size());
        if (!o.quiet) {
            std::fprintf(stderr, "wavevcm: %s:", results.back().path.c_str());
            for (const AlgorithmResult& a : results.back().algorithms)
                std::fprintf(stderr, " %s relMSE %s (%d it)", a.name.c_str(), number(a.error.relMse).c_str(), a.iterations);
            std::fprintf(stderr, "\n");
        }
    }
    if (!o.quiet) std::fprintf(stderr, "wavevcm: report -> %s\n", (fs::path(o.outputDir) / "index.html").c_str());
}

} // namespace wv
