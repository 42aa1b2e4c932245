// wavevcm: the command line. Parses arguments with CLI11 and dispatches to
// the subcommands; every wv::Error ends here as one message on stderr.
#include "../Error.h"
#include "../cl/OpenCL.h"
#include "Commands.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <sstream>

int main(int argc, char** argv)
{
    CLI::App app{"wavevcm: vertex connection and merging, and the techniques it unifies, on any OpenCL device"};
    app.require_subcommand(1);

    wv::RenderOptions r;
    CLI::App* render = app.add_subcommand("render", "render a glTF scene to an image");
    render->add_option("scene", r.scene, "scene file (.gltf or .glb); default: scenes/cornell-box.gltf");
    render->add_option("-o,--output", r.output, "output image: .exr, .hdr, .pfm (float) or .png/.jpg (8-bit sRGB)")
        ->capture_default_str();
    render->add_option("-a,--algorithm", r.algorithm, "el | pt | lt | bpt | ppm | bpm | vcm")->capture_default_str();
    render->add_option("-n,--spp", r.spp, "iterations (one jittered camera sample per pixel each); default 16");
    render->add_option("-t,--time", r.seconds, "wall-clock budget in seconds: whole iterations until it is spent");
    render->add_option("-d,--device", r.device, "device index from `wavevcm devices`, or a substring of its name");
    render->add_option("--width", r.width, "image width (default: from the camera's aspect ratio)");
    render->add_option("--height", r.height, "image height (default 512)");
    render->add_option("--max-path-length", r.maxPathLength, "segments of a full path, camera segment included")
        ->capture_default_str();
    render->add_option("--seed", r.seed, "random seed")->capture_default_str();
    render->add_option("--wavefront", r.wavefront, "path slots per wavefront (default: by device type)");
    render->add_option("--radius-factor", r.radiusFactor,
                       "merge radius of the first iteration, times the scene's bounding-sphere radius")
        ->capture_default_str();
    render->add_option("--radius-alpha", r.radiusAlpha, "radius reduction: r_i = r_1 i^((alpha-1)/2)")
        ->capture_default_str();
    render->add_option("--stats", r.statsFile, "write a JSON summary of the render to this file");
    render->add_option("--camera", r.camera, "render from the file's N-th perspective camera (0 = the first)")
        ->check(CLI::NonNegativeNumber);
    render->add_option("--background", r.background,
                       "uniform background radiance R,G,B (replaces the scene's; 0,0,0 for none)");
    render->add_option("--environment", r.environment,
                       "equirectangular environment map (.exr, .hdr or .pfm, linear radiance) as the background, "
                       "importance-sampled; replaces the scene's background");
    render->add_option("--environment-strength", r.environmentStrength, "radiance scale of --environment")
        ->capture_default_str();
    render->add_option("--environment-rotation", r.environmentRotation,
                       "turn of --environment about the up axis (+y), degrees")
        ->capture_default_str();
    render->add_flag("-q,--quiet", r.quiet, "print nothing but errors and warnings");
    render->add_flag("--profile", r.profile, "print the device time spent in each kernel");
    render->add_option("--reference", r.reference, "reference image for --error-log (same resolution)");
    render->add_option("--error-log", r.errorLog,
                       "after every iteration write seconds, iterations, RMSE and relMSE against --reference "
                       "to this CSV file (the error computation is excluded from the timing)");
    render->add_option("--aov", r.aov,
                       "techniques: also write OUTPUT_STEM.techniques.exr (layers unidirectional, connection, "
                       "merging) and OUTPUT_STEM.techniques.png (red/green/blue = their shares)")
        ->check(CLI::IsMember({"techniques"}));

    wv::ReportOptions rep;
    std::string algorithms;
    CLI::App* report = app.add_subcommand(
        "report", "render scenes with every algorithm for the same time and write an HTML comparison");
    report->add_option("scenes", rep.scenes, "scene files (.gltf or .glb)")->required();
    report->add_option("-t,--time", rep.seconds, "render time of each algorithm on each scene, seconds")->required();
    report->add_option("-o,--output", rep.outputDir, "report directory (index.html, report.json, one folder per scene)")
        ->required();
    report->add_option("--algorithms", algorithms, "comma-separated subset of pt,lt,bpt,ppm,bpm,vcm (default all)");
    report->add_option("--reference", rep.references,
                       "reference image of each scene, in the scenes' order (default: render one with vcm)");
    report->add_option("--reference-seconds", rep.referenceSeconds,
                       "vcm's render time for each reference (default 6 times --time)");
    report->add_option("-d,--device", rep.render.device, "device index from `wavevcm devices`, or a substring of its name");
    report->add_option("--width", rep.render.width, "image width (default: from the camera's aspect ratio)");
    report->add_option("--height", rep.render.height, "image height (default 512)");
    report->add_option("--max-path-length", rep.render.maxPathLength, "segments of a full path, camera segment included")
        ->capture_default_str();
    report->add_option("--seed", rep.render.seed, "random seed")->capture_default_str();
    report->add_option("--wavefront", rep.render.wavefront, "path slots per wavefront (default: by device type)");
    report->add_option("--radius-factor", rep.render.radiusFactor,
                       "merge radius of the first iteration, times the scene's bounding-sphere radius")
        ->capture_default_str();
    report->add_option("--radius-alpha", rep.render.radiusAlpha, "radius reduction: r_i = r_1 i^((alpha-1)/2)")
        ->capture_default_str();
    report->add_option("--camera", rep.render.camera, "render from the file's N-th perspective camera (0 = the first)")
        ->check(CLI::NonNegativeNumber);
    report->add_option("--background", rep.render.background, "uniform background radiance R,G,B");
    report->add_option("--environment", rep.render.environment, "equirectangular environment map as the background");
    report->add_option("--environment-strength", rep.render.environmentStrength, "radiance scale of --environment")
        ->capture_default_str();
    report->add_option("--environment-rotation", rep.render.environmentRotation,
                       "turn of --environment about the up axis (+y), degrees")
        ->capture_default_str();
    report->add_flag("-q,--quiet", rep.quiet, "print nothing but errors and warnings");

    app.add_subcommand("devices", "list every OpenCL platform and device");

    std::string test, reference;
    double maxRelMse = -1;
    CLI::App* compare = app.add_subcommand("compare", "error metrics of TEST against REF (RMSE, relMSE, mean ratio)");
    compare->add_option("test", test, "image to test")->required();
    compare->add_option("reference", reference, "reference image")->required();
    compare->add_option("--max-relmse", maxRelMse, "exit with status 1 if relMSE exceeds this");

    CLI11_PARSE(app, argc, argv);
    r.sppGiven = render->count("--spp") > 0;
    r.secondsGiven = render->count("--time") > 0;

    try {
        if (render->parsed()) return wv::runRender(r);
        if (report->parsed()) {
            if (!algorithms.empty()) {
                rep.algorithms.clear();
                std::stringstream list(algorithms);
                for (std::string a; std::getline(list, a, ',');) rep.algorithms.push_back(a);
            }
            wv::writeReport(rep);
            return 0;
        }
        if (compare->parsed()) return wv::runCompare(test, reference, maxRelMse);
        return wv::runDevices();
    } catch (const wv::Error& e) {
        std::cerr << "wavevcm: error: " << e.what() << "\n";
        return e.exitCode();
    } catch (const cl::Error& e) {
        std::cerr << "wavevcm: OpenCL error in " << e.what() << ": " << wv::clErrorName(e.err()) << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "wavevcm: error: out of host memory\n";
        return 1;
    }
}
