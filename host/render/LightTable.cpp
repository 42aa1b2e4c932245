#include "LightTable.h"

#include <algorithm>
#include <cmath>

namespace wv {

static float luminance(const float c[3]) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

// Emitted power (luminance) used for selection. Infinite lights count the
// power that crosses the scene's bounding disk (pbrt-v4's Phi for them).
static double power(const Light& l, double sceneRadius, const EnvironmentLight& environment)
{
    const double pi = M_PI;
    double lum = luminance(l.emission);
    switch (l.type) {
    case LIGHT_POINT: return 4 * pi * lum;
    case LIGHT_SPOT: return 2 * pi * lum * (1 - 0.5 * (l.cosInnerCone + l.cosOuterCone));
    case LIGHT_DIRECTIONAL: return lum * pi * sceneRadius * sceneRadius;
    case LIGHT_TRIANGLE: return pi * lum * l.area * l.sides;
    case LIGHT_BACKGROUND: // emission scales the map's radiance, or is the uniform radiance
        return pi * sceneRadius * sceneRadius * lum * (environment.width > 0 ? environment.luminanceIntegral : 4 * pi);
    }
    return 0;
}

// How much an emissive texture scales a triangle's power: the mean over
// scene triangle `tri` (16 stratified points) of the luminance of emission ×
// texel, over the luminance of `emission` alone (exact for coloured factors,
// the luminance being linear in the channels); kept above zero so that no
// part of an emitter that does emit is left unselectable.
static double texturePowerScale(const Scene& scene, const Texture& texture, uint32_t tri, const float* emission)
{
    const float* uv = &(texture.texCoord == 1 ? scene.uvs1 : scene.uvs)[6 * size_t(tri)];
    double sum = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            float b1 = (i + 0.5f) / 4, b2 = (j + 0.5f) / 4;
            if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2; // folded into the triangle
            float b0 = 1 - b1 - b2;
            Vec3 c = texture.sample(b0 * uv[0] + b1 * uv[2] + b2 * uv[4], b0 * uv[1] + b1 * uv[3] + b2 * uv[5]);
            sum += 0.2126 * emission[0] * c.x + 0.7152 * emission[1] * c.y + 0.0722 * emission[2] * c.z;
        }
    return std::max(sum / 16 / luminance(emission), 1e-4);
}

LightTable buildLightTable(const Scene& scene, const Bvh& bvh)
{
    LightTable t;
    Bounds bounds = scene.bounds();
    Vec3 center = bounds.center();
    float radius = 0.5f * length(bounds.extent());
    t.info.center[0] = center.x;
    t.info.center[1] = center.y;
    t.info.center[2] = center.z;
    t.info.radius = radius;
    t.info.backgroundLight = -1;

    t.lights = scene.lights;
    std::vector<double> powerScale(t.lights.size(), 1.0); // emissive textures' means
    // Emitters in the scene's triangle order, so that which light a random
    // number selects, and so the image at a given seed, does not depend on
    // how the BVH orders the triangles; each keeps its BVH position, which is
    // how the kernels name triangles.
    std::vector<uint32_t> bvhPosition(bvh.triangleOrder.size());
    for (size_t i = 0; i < bvh.triangleOrder.size(); ++i) bvhPosition[bvh.triangleOrder[i]] = uint32_t(i);
    t.triangleLight.assign(bvh.triangleOrder.size(), -1);
    for (uint32_t tri = 0; tri < bvhPosition.size(); ++tri) {
        uint32_t i = bvhPosition[tri];
        const Material& m = scene.materials[scene.triangleMaterial[tri]];
        if (luminance(m.emission) <= 0) continue;
        const Vec3* v = &scene.vertices[3 * tri];
        float area = 0.5f * length(cross(v[1] - v[0], v[2] - v[0]));
        if (!(area > 0)) continue; // a degenerate emitter emits nothing
        Light l{};
        l.type = LIGHT_TRIANGLE;
        l.triangle = int(i);
        l.area = area;
        l.sides = m.doubleSided ? 2 : 1;
        for (int c = 0; c < 3; ++c) l.emission[c] = m.emission[c];
        t.triangleLight[i] = int(t.lights.size());
        t.lights.push_back(l);
        powerScale.push_back(m.emissiveTexture > 0 && !scene.uvs.empty()
                                 ? texturePowerScale(scene, scene.textures[size_t(m.emissiveTexture) - 1], tri,
                                                     m.emission)
                                 : 1.0);
    }
    if (scene.features().background) {
        Light l{};
        l.type = LIGHT_BACKGROUND;
        for (int c = 0; c < 3; ++c) l.emission[c] = scene.background[c];
        if (!scene.environment.empty()) {
            t.environment = buildEnvironmentLight(scene.environment);
            for (float& e : l.emission) e = scene.environment.strength;
            t.info.envWidth = t.environment.width;
            t.info.envHeight = t.environment.height;
            float turn = scene.environment.rotation / 360.0f;
            t.info.envRotation = turn - std::floor(turn);
            t.info.envPdfScale = t.environment.pdfScale;
        }
        t.info.backgroundLight = int(t.lights.size());
        t.lights.push_back(l);
        powerScale.push_back(1.0);
    }

    std::vector<double> powers;
    for (size_t i = 0; i < t.lights.size(); ++i) {
        powers.push_back(power(t.lights[i], radius, t.environment) * powerScale[i]);
        t.totalPower += powers.back();
    }
    t.cdf.assign(1, 0.0f);
    double running = 0;
    for (size_t i = 0; i < t.lights.size(); ++i) {
        t.lights[i].pmf = t.totalPower > 0 ? float(powers[i] / t.totalPower) : 0.0f;
        running += powers[i];
        t.cdf.push_back(t.totalPower > 0 ? float(running / t.totalPower) : 0.0f);
    }
    if (!t.lights.empty()) t.cdf.back() = 1.0f;
    t.info.lightCount = t.totalPower > 0 ? int(t.lights.size()) : 0;
    return t;
}

} // namespace wv
