// `wavevcm report` (host/report): a tiny report of the Cornell box, 64 × 64,
// every algorithm for 1 s against a 2 s vcm reference. Every file the page
// refers to exists and is a valid image (SVG: well-formed enough to hold its
// lines); every number of the summary table, recomputed here from the EXR
// files and the error log, is what the page shows; the enlarged crop is of
// the block with the highest summed relMSE. Where Debian's chromium is
// installed, it renders the page with no resource missing (skipped, and said
// so, elsewhere).
#include "TestDevices.h"
#include "image/Image.h"
#include "report/Report.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <unistd.h>

namespace wv {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

std::string readText(const fs::path& p)
{
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string formatted(double v) // as the page writes numbers
{
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

class Report : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        dir_ = fs::temp_directory_path() / ("wavevcm_report_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        ReportOptions o;
        o.scenes = {test::cornellBoxPath()};
        o.seconds = 1;
        o.referenceSeconds = 2;
        o.outputDir = dir_.string();
        o.render.width = 64;
        o.render.height = 64;
        o.render.device = "0"; // the first device, as the other tests
        o.quiet = true;
        writeReport(o);
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    static fs::path dir_;
};
fs::path Report::dir_;

TEST_F(Report, EveryReferencedFileExistsAndIsAnImage)
{
    std::string page = readText(dir_ / "index.html");
    ASSERT_FALSE(page.empty());
    std::regex reference("(?:src|href)=\"([^\"]+)\"");
    std::set<std::string> files;
    for (auto it = std::sregex_iterator(page.begin(), page.end(), reference); it != std::sregex_iterator(); ++it)
        files.insert((*it)[1].str());
    EXPECT_GE(files.size(), 6u * 3 + 2 + 4) << "every algorithm's PNG, EXR and crop, the plot, vcm's techniques";
    for (const std::string& f : files) {
        SCOPED_TRACE(f);
        EXPECT_EQ(f.find("://"), std::string::npos) << "a self-contained page has relative paths only";
        fs::path p = dir_ / f;
        ASSERT_TRUE(fs::is_regular_file(p));
        if (p.extension() == ".svg") {
            std::string svg = readText(p);
            EXPECT_NE(svg.find("<svg"), std::string::npos);
            EXPECT_NE(svg.find("</svg>"), std::string::npos);
            EXPECT_GE(std::count(svg.begin(), svg.end(), '\n'), 10);
            EXPECT_NE(svg.find("<polyline"), std::string::npos);
        } else {
            Image im = readImage(p.string());
            EXPECT_GT(im.width, 0);
            EXPECT_GT(im.height, 0);
        }
    }
}

TEST_F(Report, TableNumbersAreThoseOfTheImages)
{
    json r = json::parse(readText(dir_ / "report.json"));
    ASSERT_TRUE(r["complete"].get<bool>());
    ASSERT_EQ(r["scenes"].size(), 1u);
    const json& s = r["scenes"][0];
    fs::path sceneDir = dir_ / s["directory"].get<std::string>();
    Image reference = readImage((sceneDir / "reference.exr").string());
    std::string page = readText(dir_ / "index.html");
    ASSERT_EQ(s["algorithms"].size(), 6u);
    double ptEfficiency = 0;
    for (const json& a : s["algorithms"])
        if (a["algorithm"] == "pt") ptEfficiency = 1 / (a["relmse"].get<double>() * a["seconds"].get<double>());
    for (const json& a : s["algorithms"]) {
        std::string name = a["algorithm"];
        SCOPED_TRACE(name);
        ImageDifference d = compareImages(readImage((sceneDir / (name + ".exr")).string()), reference);
        EXPECT_NEAR(a["relmse"].get<double>(), d.relMse, 1e-9 * d.relMse);
        EXPECT_NEAR(a["rmse"].get<double>(), d.rmse, 1e-9 * d.rmse);
        const json& log = a["log"];
        ASSERT_FALSE(log.empty());
        EXPECT_EQ(a["iterations"].get<int>(), log.back()[1].get<int>());
        EXPECT_GE(a["seconds"].get<double>(), 1.0);
        EXPECT_NEAR(log.back()[3].get<double>(), d.relMse, 1e-9 * d.relMse) << "the log ends at the image";
        double efficiency = 1 / (d.relMse * a["seconds"].get<double>()) / ptEfficiency;
        EXPECT_NEAR(a["efficiency"].get<double>(), efficiency, 1e-6 * efficiency);
        // Least squares of log relMSE on log time past a tenth of the render.
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        int n = 0;
        for (const json& p : log) {
            double t = p[0], e = p[3];
            if (t < 0.1 * 1.0 || !(e > 0)) continue;
            sx += std::log(t), sy += std::log(e), sxx += std::log(t) * std::log(t), sxy += std::log(t) * std::log(e);
            ++n;
        }
        ASSERT_GE(n, 2);
        double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
        EXPECT_NEAR(a["slope"].get<double>(), slope, 1e-6);
        // The page shows each of them (the row's cells in order).
        std::string row = "<tr><td>" + name + "</td><td>" + std::to_string(a["iterations"].get<int>()) + "</td><td>" +
                          formatted(a["seconds"]) + "</td><td>" + formatted(a["samples_per_second"]) + "</td><td>" +
                          formatted(d.relMse) + "</td><td>" + formatted(d.rmse) + "</td><td>" + formatted(slope) +
                          "</td><td>" + formatted(efficiency) + "</td></tr>";
        EXPECT_NE(page.find(row), std::string::npos) << "missing row " << row;
    }
}

TEST_F(Report, CropIsTheHardestBlock)
{
    json s = json::parse(readText(dir_ / "report.json"))["scenes"][0];
    fs::path sceneDir = dir_ / s["directory"].get<std::string>();
    Image reference = readImage((sceneDir / "reference.exr").string());
    std::vector<Image> images;
    for (const json& a : s["algorithms"])
        images.push_back(readImage((sceneDir / (a["algorithm"].get<std::string>() + ".exr")).string()));
    int b = s["crop"][2];
    ASSERT_EQ(b, 8) << "an eighth of 64";
    double best = -1;
    int bx = -1, by = -1;
    for (int y0 = 0; y0 + b <= 64; y0 += b)
        for (int x0 = 0; x0 + b <= 64; x0 += b) {
            double sum = 0;
            for (const Image& im : images)
                for (int y = y0; y < y0 + b; ++y)
                    for (int x = x0; x < x0 + b; ++x)
                        for (int c = 0; c < 3; ++c) {
                            size_t i = 3 * (size_t(y) * 64 + size_t(x)) + size_t(c);
                            double d = im.rgb[i] - reference.rgb[i];
                            sum += d * d / (reference.rgb[i] * reference.rgb[i] + 0.01);
                        }
            if (sum > best) best = sum, bx = x0, by = y0;
        }
    EXPECT_EQ(s["crop"][0].get<int>(), bx);
    EXPECT_EQ(s["crop"][1].get<int>(), by);
    Image crop = readImage((sceneDir / "crop-vcm.png").string());
    EXPECT_EQ(crop.width, 160) << "8 pixels enlarged 20 times";
}

TEST_F(Report, RendersInChromiumWithNoResourceMissing)
{
    const char* candidates[] = {"/usr/bin/chromium", "/usr/bin/chromium-browser"};
    std::string chromium;
    for (const char* c : candidates)
        if (fs::exists(c)) chromium = c;
    if (chromium.empty()) GTEST_SKIP() << "Debian's chromium is not installed: the page was not rendered";
    fs::path shot = dir_ / "screenshot.png", log = dir_ / "chromium.log";
    std::string command = chromium + " --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1400,2400" +
                          " --enable-logging=stderr --v=0 --screenshot=" + shot.string() + " file://" +
                          (dir_ / "index.html").string() + " > " + log.string() + " 2>&1";
    int status = std::system(command.c_str());
    std::string output = readText(log);
    ASSERT_EQ(status, 0) << output;
    Image im = readImage(shot.string());
    EXPECT_EQ(im.width, 1400);
    EXPECT_EQ(output.find("ERR_FILE_NOT_FOUND"), std::string::npos) << output;
    EXPECT_EQ(output.find("Failed to load resource"), std::string::npos) << output;
}

} // namespace
} // namespace wv
