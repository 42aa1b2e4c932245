// `wavevcm report`: the comparison of light transport algorithms that the
// VCM paper's results show, as one command. Per scene, every algorithm
// renders for the same time; each image is measured against a reference
// (given, or rendered longer with vcm); the report is DIR/index.html with
// the images side by side, an enlarged crop of the hardest region, the error
// against time on log-log axes with fitted slopes, vcm's technique shares and
// a table; DIR/report.json holds the same numbers. docs/report.md describes
// every file.
#pragma once

#include "render/RenderOptions.h"

#include <string>
#include <vector>

namespace wv {

struct ReportOptions {
    std::vector<std::string> scenes;
    std::vector<std::string> algorithms{"pt", "lt", "bpt", "ppm", "bpm", "vcm"};
    double seconds = 0;                  // render time of each algorithm on each scene
    std::vector<std::string> references; // one reference image per scene, in order; empty: render them
    double referenceSeconds = 0;         // vcm's time for a rendered reference; 0: 6 × seconds
    std::string outputDir;
    RenderOptions render; // device, resolution, path length, seed, merge radius, camera, background
    bool quiet = false;   // no progress bar, no summary
};

// Throws wv::Error for bad options (before rendering anything), unreadable
// scenes or references, and unwritable output. The report is rewritten after
// each scene, so an interrupted run leaves the scenes it finished.
void writeReport(const ReportOptions& options);

} // namespace wv
