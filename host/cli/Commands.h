// The subcommands of `wavevcm`; each returns the process exit code.
#pragma once

#include <string>

namespace wv {

struct RenderOptions {
    std::string scene; // empty = the default scene
    std::string output = "render.exr";
    std::string algorithm = "vcm";
    int spp = 0;         // 0 = not given
    double seconds = 0;  // 0 = not given
    bool sppGiven = false, secondsGiven = false; // given on the command line (then they must be > 0)
    std::string device;
    int width = 0, height = 0; // 0 = from the camera
    int maxPathLength = 10;
    unsigned seed = 0;
    int wavefront = 0;
    double radiusFactor = 0.003, radiusAlpha = 0.75;
    std::string aov; // "techniques" or empty
    std::string reference, errorLog; // --reference REF --error-log LOG.csv
    std::string statsFile;
    int camera = -1;        // --camera N: the file's N-th perspective camera; -1 = the first
    std::string background; // --background R,G,B (radiance); empty = the scene's
    std::string environment;         // --environment FILE: equirectangular .exr/.hdr/.pfm
    double environmentStrength = 1;  // --environment-strength S
    double environmentRotation = 0;  // --environment-rotation DEGREES, about +y
    bool quiet = false;
    bool profile = false;
};

int runRender(const RenderOptions& options);
int runDevices();
int runCompare(const std::string& test, const std::string& reference, double maxRelMse);

// scenes/cornell-box.gltf next to the installed binary or in the source tree.
std::string defaultScenePath();

} // namespace wv
