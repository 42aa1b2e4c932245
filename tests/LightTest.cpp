// Lights: emission sampling must carry each light's power (what light
// sub-paths rely on), and next-event estimation its irradiance, both against
// closed forms.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace wv {
namespace {

constexpr double kPi = M_PI;

Light punctual(int type, Vec3 position, Vec3 direction, Vec3 emission, float inner = 0, float outer = 0)
{
    Light l{};
    l.type = type;
    for (int c = 0; c < 3; ++c) {
        l.position[c] = position[c];
        l.direction[c] = direction[c];
        l.emission[c] = emission[c];
    }
    l.cosInnerCone = std::cos(inner);
    l.cosOuterCone = std::cos(outer);
    return l;
}

// A floor (for the bounding sphere) plus, optionally, an emissive triangle of
// area 0.5 facing +y at height 1.
Scene lightScene(bool emissiveTriangle)
{
    Scene s = test::sceneFromTriangles({{-2, 0, -2}, {2, 0, 2}, {2, 0, -2}});
    if (emissiveTriangle) {
        Material m = s.materials[0];
        m.emission[0] = 2;
        m.emission[1] = 1;
        m.emission[2] = 0.5f;
        s.materials.push_back(m);
        for (Vec3 v : {Vec3(0, 1, 0), Vec3(0, 1, 1), Vec3(1, 1, 0)}) s.vertices.push_back(v);
        s.triangleMaterial.push_back(1);
    }
    return s;
}

struct Estimate {
    std::array<double, 3> mean{}, standardError{};
};

Estimate run(const Scene& scene, const char* kernelName, int n, std::array<float, 4> p = {}, std::array<float, 4> nrm = {})
{
    DeviceInfo info = test::devicesUnderTest()[0];
    DeviceContext device(info);
    Bvh bvh = buildBvh(scene.vertices);
    LightTable table = buildLightTable(scene, bvh);
    SceneBuffers buffers(device, scene, bvh, table);
    // Light selection with the renderer's step count for this table: a count
    // too small would never select the last lights, whose power would be missing.
    cl::Program program = test::buildTestProgram(
        device, {test::testKernel("light_tests.cl")},
        "-DHAS_EMISSIVE_TRIANGLES -DHAS_POINT_LIGHTS -DHAS_DIRECTIONAL_LIGHTS -DHAS_BACKGROUND" +
            lightSelectOption(table.info.lightCount));
    cl::Buffer out = deviceBuffer(device, size_t(n) * 16, "estimates");
    cl::Kernel k(program, kernelName);
    int arg = 0;
    k.setArg(arg++, buffers.lights);
    k.setArg(arg++, buffers.lightCdf);
    k.setArg(arg++, buffers.triVertices);
    k.setArg(arg++, buffers.sceneInfo);
    if (std::string(kernelName) == "nee_irradiance") {
        k.setArg(arg++, sizeof(cl_float4), p.data());
        k.setArg(arg++, sizeof(cl_float4), nrm.data());
    }
    k.setArg(arg++, n);
    k.setArg(arg++, out);
    device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(n)), cl::NDRange(64));
    std::vector<float> values(size_t(n) * 4);
    device.queue.enqueueReadBuffer(out, CL_TRUE, 0, values.size() * 4, values.data());
    Estimate e;
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sq = 0;
        for (int i = 0; i < n; ++i) {
            double x = values[4 * size_t(i) + c];
            sum += x;
            sq += x * x;
        }
        e.mean[c] = sum / n;
        e.standardError[c] = std::sqrt(std::max(0.0, sq / n - e.mean[c] * e.mean[c]) / n);
    }
    return e;
}

// The estimate agrees with the closed form within 4 standard errors (a false
// alarm ~1e-4 per channel) or 1e-5 relative where the estimator has no
// variance (a single delta light).
void expectNear(const Estimate& e, std::array<double, 3> expected, const char* what)
{
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(e.mean[c], expected[c], 4 * e.standardError[c] + 1e-5 * std::fabs(expected[c]))
            << what << " channel " << c << " (standard error " << e.standardError[c] << ")";
}

TEST(Lights, EmissionSamplingCarriesEachLightsPower)
{
    const int n = 1 << 20;
    {
        Scene s = lightScene(true); // area 0.5, radiance (2, 1, 0.5): power π·L·A
        expectNear(run(s, "emission_power", n), {kPi * 1.0, kPi * 0.5, kPi * 0.25}, "triangle");
    }
    {
        Scene s = lightScene(false);
        s.lights.push_back(punctual(LIGHT_POINT, {0, 1, 0}, {0, 0, -1}, {1, 2, 3}));
        expectNear(run(s, "emission_power", n), {4 * kPi, 8 * kPi, 12 * kPi}, "point");
    }
    {
        // glTF spot: falloff t² with t linear in cos θ from outer to inner;
        // power = I · 2π (∫ t² dcos over the ramp + (1 − cos inner)).
        float inner = 0.3f, outer = 0.6f;
        double ci = std::cos(inner), co = std::cos(outer);
        double power = 2 * kPi * ((ci - co) / 3 + (1 - ci));
        Scene s = lightScene(false);
        s.lights.push_back(punctual(LIGHT_SPOT, {0, 1, 0}, {0, -1, 0}, {1, 1, 1}, inner, outer));
        expectNear(run(s, "emission_power", n), {power, power, power}, "spot");
    }
    {
        // Irradiance E over the bounding sphere's disk: E · π R².
        Scene s = lightScene(false);
        s.lights.push_back(punctual(LIGHT_DIRECTIONAL, {}, normalize(Vec3(1, -1, 0)), {3, 2, 1}));
        double r = 0.5 * length(s.bounds().extent()), area = kPi * r * r;
        expectNear(run(s, "emission_power", n), {3 * area, 2 * area, area}, "directional");
    }
    {
        // Uniform radiance L from every direction through the disk: L · 4π · π R².
        Scene s = lightScene(false);
        s.background = {0.5f, 0.25f, 1};
        double r = 0.5 * length(s.bounds().extent()), flux = 4 * kPi * kPi * r * r;
        expectNear(run(s, "emission_power", n), {0.5 * flux, 0.25 * flux, flux}, "background");
    }
    {
        // All together: the selection probabilities cancel in the sum.
        Scene s = lightScene(true);
        s.lights.push_back(punctual(LIGHT_POINT, {0, 1, 0}, {0, 0, -1}, {1, 2, 3}));
        s.background = {0.5f, 0.25f, 1};
        double r = 0.5 * length(s.bounds().extent()), flux = 4 * kPi * kPi * r * r;
        expectNear(run(s, "emission_power", n),
                   {kPi * 1.0 + 4 * kPi + 0.5 * flux, kPi * 0.5 + 8 * kPi + 0.25 * flux, kPi * 0.25 + 12 * kPi + flux},
                   "all lights");
    }
}

TEST(Lights, NextEventEstimationGivesIrradiance)
{
    const int n = 1 << 20;
    std::array<float, 4> up = {0, 1, 0, 0};
    {
        // A point light at height 2 above p: E = I / d².
        Scene s = lightScene(false);
        s.lights.push_back(punctual(LIGHT_POINT, {0, 2, 0}, {0, 0, -1}, {4, 8, 12}));
        expectNear(run(s, "nee_irradiance", n, {0, 0, 0, 0}, up), {1, 2, 3}, "point");
    }
    {
        // Uniform background over the upper hemisphere: E = π L.
        Scene s = lightScene(false);
        s.background = {1, 0.5f, 0.25f};
        expectNear(run(s, "nee_irradiance", n, {0, 0.5f, 0, 0}, up), {kPi, kPi / 2, kPi / 4}, "background");
    }
    {
        // A directional light at 60° from the normal: E cos 60°.
        Scene s = lightScene(false);
        Vec3 d = normalize(Vec3(std::sin(float(kPi) / 3), -std::cos(float(kPi) / 3), 0));
        s.lights.push_back(punctual(LIGHT_DIRECTIONAL, {}, d, {2, 2, 2}));
        expectNear(run(s, "nee_irradiance", n, {0, 0.5f, 0, 0}, up), {1, 1, 1}, "directional");
    }
    {
        // A small emissive triangle far above p, facing down: E ≈ L · A · cos·cos / d².
        Scene s = test::sceneFromTriangles({{-2, 0, -2}, {2, 0, 2}, {2, 0, -2}});
        Material m = s.materials[0];
        m.emission[0] = m.emission[1] = m.emission[2] = 100;
        s.materials.push_back(m);
        float h = 0.01f; // a right triangle of legs h at height 1, wound to face -y
        for (Vec3 v : {Vec3(0, 1, 0), Vec3(h, 1, 0), Vec3(0, 1, h)}) s.vertices.push_back(v);
        s.triangleMaterial.push_back(1);
        double expected = 100 * 0.5 * h * h; // cosines ≈ 1 and d ≈ 1 to within 1e-4
        Estimate e = run(s, "nee_irradiance", n, {0, 0, 0, 0}, up);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.mean[c], expected, 1e-3 * expected) << "triangle";
    }
}

} // namespace
} // namespace wv
