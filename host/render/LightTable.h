// The scene's lights as the kernels sample them: punctual lights from the
// file, one entry per emissive triangle, the background; each selected with
// probability proportional to its emitted power.
#pragma once

#include "../bvh/Bvh.h"
#include "../scene/Scene.h"
#include "EnvironmentLight.h"

#include <vector>

namespace wv {

struct LightTable {
    std::vector<Light> lights;
    std::vector<float> cdf;            // lights.size() + 1 entries, cdf[0] = 0, cdf.back() = 1
    std::vector<int> triangleLight;    // per BVH-ordered triangle: its light index, or -1
    SceneInfo info{};
    double totalPower = 0;
    EnvironmentLight environment; // the background's map, if it has one (width 0 otherwise)
};

LightTable buildLightTable(const Scene& scene, const Bvh& bvh);

} // namespace wv
