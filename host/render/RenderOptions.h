// The options of a render as the command line gives them (`wavevcm render`,
// and `wavevcm report` for each of its renders), and what follows from them:
// the scene with the camera and light they choose, and the RenderSettings.
#pragma once

#include "Renderer.h"
#include "scene/Scene.h"

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
    int pipelines = 0; // --pipelines N per device; 0 = defaultPipelines()
    int width = 0, height = 0; // 0 = from the camera
    int maxPathLength = 10;
    unsigned seed = 0;
    int wavefront = 0;
    int roundsAhead = 0; // --rounds-ahead N
    int samplesPerIteration = 1; // --samples-per-iteration K
    std::string vertexConnections; // --vertex-connections inline|queued; empty = the device's default
    double radiusFactor = 0.003, radiusAlpha = 0.75;
    std::string aov; // "techniques" or empty
    std::string reference, errorLog; // --reference REF --error-log LOG.csv
    std::string statsFile;
    double checkpoint = 0;  // --checkpoint SECONDS: write the image so far this often; 0 = never
    int camera = -1;        // --camera N: the file's N-th camera; -1 = the first
    std::string background; // --background R,G,B (radiance); empty = the scene's
    std::string environment;         // --environment FILE: equirectangular .exr/.hdr/.pfm
    double environmentStrength = 1;  // --environment-strength S
    double environmentRotation = 0;  // --environment-rotation DEGREES, about +y
    bool quiet = false;
    bool profile = false;
};

// Throws wv::Error naming the option that is out of range.
void validateRenderOptions(const RenderOptions& options);

// The scene at `path` with its warnings printed, the camera --camera picks,
// --background or --environment in place of its background, and, when it
// has no light at all, a uniform white background (with a warning).
Scene prepareScene(const RenderOptions& options, const std::string& path);

// Resolution (--width/--height, else from the camera's aspect ratio, 512
// high), path length, seed, wavefront and merge radius.
RenderSettings renderSettings(const RenderOptions& options, const Scene& scene);

} // namespace wv
