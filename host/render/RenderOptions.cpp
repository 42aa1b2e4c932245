#include "RenderOptions.h"

#include "Error.h"
#include "image/Image.h"
#include "scene/GltfLoader.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace fs = std::filesystem;

namespace wv {

void validateRenderOptions(const RenderOptions& o)
{
    if (o.sppGiven && o.spp <= 0) throw Error("--spp must be positive");
    if (o.secondsGiven && !(o.seconds > 0 && std::isfinite(o.seconds)))
        throw Error("--time must be a positive number of seconds");
    if (o.checkpoint < 0 || !std::isfinite(o.checkpoint))
        throw Error("--checkpoint must be a positive number of seconds");
    if (o.width < 0 || o.height < 0 || o.width > 32768 || o.height > 32768)
        throw Error("--width and --height must be between 1 and 32768");
    if (o.maxPathLength < 1) throw Error("--max-path-length must be at least 1");
    if (o.wavefront < 0) throw Error("--wavefront must be positive");
    if (!(o.radiusFactor > 0) || !std::isfinite(o.radiusFactor)) throw Error("--radius-factor must be positive");
    if (!(o.radiusAlpha > 0 && o.radiusAlpha <= 1)) throw Error("--radius-alpha must be in (0, 1]");
    if (!(o.environmentStrength >= 0) || !std::isfinite(o.environmentStrength))
        throw Error("--environment-strength must be a finite number >= 0");
    if (!std::isfinite(o.environmentRotation)) throw Error("--environment-rotation must be a finite number");
    if (!o.environment.empty()) {
        if (!o.background.empty()) throw Error("--environment and --background both replace the background: give one");
        std::string ext = fs::path(o.environment).extension().string();
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (ext != ".exr" && ext != ".hdr" && ext != ".pfm")
            throw Error(o.environment + ": an environment map must be linear radiance in .exr, .hdr or .pfm");
        if (!fs::is_regular_file(o.environment)) throw Error(o.environment + ": no such file");
    }
}

// The image size: both given, one given (the other from the camera's aspect
// ratio), or neither (512 high).
static void resolution(const RenderOptions& o, const Scene& scene, int* width, int* height)
{
    float aspect = scene.camera.aspectRatio > 0 ? scene.camera.aspectRatio : 1.0f;
    *height = o.height > 0 ? o.height : (o.width > 0 ? std::max(1, int(std::lround(o.width / aspect))) : 512);
    *width = o.width > 0 ? o.width : std::max(1, int(std::lround(*height * aspect)));
}

static Vec3 parseColor(const std::string& option, const std::string& text)
{
    Vec3 c;
    char comma1 = 0, comma2 = 0, extra = 0;
    if (std::sscanf(text.c_str(), " %f %c %f %c %f %c", &c.x, &comma1, &c.y, &comma2, &c.z, &extra) != 5 ||
        comma1 != ',' || comma2 != ',' || !(c.x >= 0 && c.y >= 0 && c.z >= 0) || !std::isfinite(c.x + c.y + c.z))
        throw Error(option + " " + text + ": expected R,G,B, three finite numbers >= 0");
    return c;
}

// --camera and --background, and a default light: a scene with none (most
// exported models carry no light) would render black without a word, so it
// gets a uniform white background of radiance 1, what glTF viewers show.
static void chooseCameraAndLight(const RenderOptions& o, const std::string& scenePath, Scene& scene)
{
    if (o.camera >= 0) {
        if (size_t(o.camera) >= scene.cameras.size())
            throw Error("--camera " + std::to_string(o.camera) + ": " + scenePath + " has " +
                        std::to_string(scene.cameras.size()) + " camera" +
                        (scene.cameras.size() == 1 ? "" : "s") + " (numbered from 0)");
        scene.camera = scene.cameras[size_t(o.camera)];
    }
    if (!o.background.empty()) {
        scene.background = parseColor("--background", o.background);
        scene.environment = EnvironmentMap{}; // replaces the scene's map too
    }
    if (!o.environment.empty()) {
        scene.environment.path = o.environment;
        scene.environment.image = readImage(o.environment);
        scene.environment.strength = float(o.environmentStrength);
        scene.environment.rotation = float(o.environmentRotation);
        if (!scene.hasLight()) {
            std::fprintf(stderr,
                         "wavevcm: warning: %s emits nothing (black, or --environment-strength 0) and %s has no "
                         "other light: the image is black\n",
                         o.environment.c_str(), scenePath.c_str());
            return;
        }
    }
    if (scene.hasLight()) return;
    if (!o.background.empty()) {
        std::fprintf(stderr, "wavevcm: warning: %s has no light and --background is 0: the image is black\n",
                     scenePath.c_str());
        return;
    }
    std::fprintf(stderr,
                 "wavevcm: warning: %s has no light (no KHR_lights_punctual light, no emissive material, no "
                 "background); rendering it under a uniform white background of radiance 1, as glTF viewers "
                 "do. Add lights to the file or set --background R,G,B.\n",
                 scenePath.c_str());
    scene.background = Vec3(1, 1, 1);
}

Scene prepareScene(const RenderOptions& o, const std::string& path)
{
    Scene scene = loadGltf(path);
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "wavevcm: warning: %s\n", w.c_str());
    chooseCameraAndLight(o, path, scene);
    return scene;
}

RenderSettings renderSettings(const RenderOptions& o, const Scene& scene)
{
    RenderSettings settings;
    settings.algorithm = parseAlgorithm(o.algorithm);
    resolution(o, scene, &settings.width, &settings.height);
    settings.maxPathLength = o.maxPathLength;
    settings.seed = o.seed;
    settings.wavefront = o.wavefront;
    settings.roundsAhead = o.roundsAhead;
    settings.samplesPerIteration = o.samplesPerIteration;
    settings.vertexConnections = o.vertexConnections == "inline"   ? VertexConnections::Inline
                                 : o.vertexConnections == "queued" ? VertexConnections::Queued
                                                                   : VertexConnections::Default;
    settings.radiusFactor = float(o.radiusFactor);
    settings.radiusAlpha = float(o.radiusAlpha);
    settings.techniques = o.aov == "techniques";
    return settings;
}

} // namespace wv
