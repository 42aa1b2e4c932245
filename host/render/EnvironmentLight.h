// The environment map as the kernels sample it (kernels/lights/environment.h):
// its radiance per texel and a piecewise-constant density over the map's
// (u, v) proportional to luminance · sin θ, the solid angle a texel covers,
// as a marginal CDF over rows and a conditional CDF over each row's texels.
#pragma once

#include "../scene/Scene.h"

#include <vector>

namespace wv {

struct EnvironmentLight {
    int width = 0, height = 0;
    std::vector<float> radiance;       // 4 floats per texel (RGB, 0), row 0 at +y
    std::vector<float> marginalCdf;    // height + 1 entries, 0 … 1
    std::vector<float> conditionalCdf; // height rows of width + 1 entries, 0 … 1
    float pdfScale = 0;                // density over (u, v) of a texel = f(texel) · pdfScale
    double luminanceIntegral = 0;      // ∫ luminance dω over the sphere, before strength
};

// Throws wv::Error naming the map's file if it has no texels.
EnvironmentLight buildEnvironmentLight(const EnvironmentMap& map);

} // namespace wv
