// wavevcm: the command line. Parses arguments with CLI11 and dispatches to
// the subcommands; every wv::Error ends here as one message on stderr.
#include "../Error.h"
#include "../cl/OpenCL.h"
#include "../cluster/Cluster.h"
#include "Commands.h"

#include <CLI/CLI.hpp>

#include <iostream>
#include <limits>
#include <sstream>

// The options `render` and `report` share: device, pipelines, resolution,
// path length, seed, merge radius, camera and background.
static void addSceneOptions(CLI::App* command, wv::RenderOptions& o, bool severalDevices)
{
    command->add_option("-d,--device", o.device,
                        std::string("device index from `wavevcm devices`, or a substring of its name") +
                            (severalDevices ? "; several, comma-separated, or all: they render together" : ""));
    command->add_option("--pipelines", o.pipelines,
                        "independent render pipelines per device, each rendering whole iterations (default: 2 on a "
                        "CPU device of 2 or more compute units that can be partitioned, each on half of them; 1 "
                        "elsewhere, and for render -n under 4 per process)")
        ->check(CLI::Range(1, 256));
    // 0 stands for "not given" in RenderOptions: given, it must be a size.
    command->add_option("--width", o.width, "image width (default: from the camera's aspect ratio)")
        ->check(CLI::Range(1, 32768));
    command->add_option("--height", o.height, "image height (default 512)")->check(CLI::Range(1, 32768));
    command->add_option("--max-path-length", o.maxPathLength, "segments of a full path, camera segment included")
        ->capture_default_str();
    command->add_option("--seed", o.seed, "random seed")->capture_default_str();
    command->add_option("--wavefront", o.wavefront, "path slots per wavefront (default: by device type)")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()));
    command->add_option("--rounds-ahead", o.roundsAhead,
                        "rounds enqueued before waiting for a round's counters; 0: wait after each and size "
                        "launches by them (the default)")
        ->check(CLI::Range(0, 16));
    command->add_option("--samples-per-iteration", o.samplesPerIteration,
                        "camera samples (and light paths) per pixel in one iteration (default 1): more paths per "
                        "launch for a GPU; --spp counts samples, so it must be a multiple")
        ->check(CLI::Range(1, 64));
    command->add_option("--vertex-connections", o.vertexConnections,
                        "bpt and vcm: inline (each camera path traces its connections' shadow rays) or queued (a "
                        "kernel traces them, one per work-item); default: queued on GPUs, inline elsewhere")
        ->check(CLI::IsMember({"inline", "queued"}));
    command->add_option("--radius-factor", o.radiusFactor,
                        "merge radius of the first iteration, times the scene's bounding-sphere radius")
        ->capture_default_str();
    command->add_option("--radius-alpha", o.radiusAlpha, "radius reduction: r_i = r_1 i^((alpha-1)/2)")
        ->capture_default_str();
    command->add_option("--camera", o.camera, "render from the file's N-th camera (0 = the first)")
        ->check(CLI::NonNegativeNumber);
    command->add_option("--background", o.background,
                        "uniform background radiance R,G,B (replaces the scene's; 0,0,0 for none)");
    command->add_option("--environment", o.environment,
                        "equirectangular environment map (.exr, .hdr or .pfm, linear radiance) as the background, "
                        "importance-sampled; replaces the scene's background");
    command->add_option("--environment-strength", o.environmentStrength, "radiance scale of --environment")
        ->capture_default_str();
    command->add_option("--environment-rotation", o.environmentRotation,
                        "turn of --environment about the up axis (+y), degrees")
        ->capture_default_str();
}

static int run(int argc, char** argv, bool* failed);

// An MPI job (mpirun, host/cluster): an error on one rank is printed with the
// rank's name and ends every rank at once, so that none waits for it.
int main(int argc, char** argv)
{
    int exitCode = 0;
    try {
        wv::cluster::init(&argc, &argv);
    } catch (const wv::Error& e) {
        std::cerr << "wavevcm: error: " << e.what() << "\n";
        return e.exitCode();
    }
    bool failed = false; // an error, not an interrupted render (which every rank finishes in step)
    exitCode = run(argc, argv, &failed);
    if (failed) wv::cluster::abortJob(exitCode);
    wv::cluster::finalize();
    return exitCode;
}

// The error message's prefix: which rank of an MPI job it comes from.
static std::string who()
{
    if (wv::cluster::size() == 1) return "wavevcm: ";
    return "wavevcm: rank " + std::to_string(wv::cluster::rank()) + " of " + std::to_string(wv::cluster::size()) +
           " (" + wv::cluster::hostName() + "): ";
}

static int run(int argc, char** argv, bool* failed)
{
    CLI::App app{"wavevcm: vertex connection and merging, and the techniques it unifies, on any OpenCL device"};
    app.require_subcommand(1);

    wv::RenderOptions r;
    CLI::App* render = app.add_subcommand("render", "render a glTF scene to an image");
    render->add_option("scene", r.scene, "scene file (.gltf or .glb); default: scenes/cornell-box.gltf");
    render->add_option("-o,--output", r.output, "output image: .exr, .hdr, .pfm (float) or .png/.jpg (8-bit sRGB)")
        ->capture_default_str();
    render->add_option("-a,--algorithm", r.algorithm, "el | pt | lt | bpt | ppm | bpm | vcm")->capture_default_str();
    render->add_option("-n,--spp", r.spp,
                       "samples per pixel: iterations of one jittered camera sample per pixel each, or of "
                       "--samples-per-iteration; default 16 (rounded up to a multiple of it)");
    render->add_option("-t,--time", r.seconds, "wall-clock budget in seconds: whole iterations until it is spent");
    addSceneOptions(render, r, true);
    render->add_option("--stats", r.statsFile, "write a JSON summary of the render to this file");
    render->add_option("--checkpoint", r.checkpoint,
                       "write the image rendered so far every SECONDS (with mpirun: the whole job's, by rank 0)")
        ->check(CLI::PositiveNumber);
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
    addSceneOptions(report, rep.render, false);
    report->add_flag("-q,--quiet", rep.quiet, "print nothing but errors and warnings");

    app.add_subcommand("devices", "list every OpenCL platform and device");

    std::string test, reference;
    double maxRelMse = -1;
    CLI::App* compare = app.add_subcommand("compare", "error metrics of TEST against REF (RMSE, relMSE, mean ratio)");
    compare->add_option("test", test, "image to test")->required();
    compare->add_option("reference", reference, "reference image")->required();
    compare->add_option("--max-relmse", maxRelMse, "exit with status 1 if relMSE exceeds this");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        *failed = code != 0;
        return code;
    }
    r.sppGiven = render->count("--spp") > 0;
    r.secondsGiven = render->count("--time") > 0;

    try {
        if (render->parsed()) return wv::runRender(r);
        if (report->parsed()) {
            if (wv::cluster::size() > 1)
                throw wv::Error("report runs in one process: start it without mpirun (render takes several ranks)");
            if (!algorithms.empty()) {
                rep.algorithms.clear();
                std::stringstream list(algorithms);
                for (std::string a; std::getline(list, a, ',');) rep.algorithms.push_back(a);
            }
            wv::writeReport(rep);
            return 0;
        }
        if (compare->parsed()) return wv::runCompare(test, reference, maxRelMse); // exit 1 above the bound: no error
        return wv::runDevices();
    } catch (const wv::Error& e) {
        std::cerr << who() << "error: " << e.what() << std::endl;
        *failed = true;
        return e.exitCode();
    } catch (const cl::Error& e) {
        std::cerr << who() << "OpenCL error in " << e.what() << ": " << wv::clErrorName(e.err()) << std::endl;
        *failed = true;
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << who() << "error: out of host memory" << std::endl;
        *failed = true;
        return 1;
    }
}
