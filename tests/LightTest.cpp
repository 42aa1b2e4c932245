// Lights: emission sampling must carry each light's power (what light
// sub-paths rely on), and next-event estimation its irradiance, both against
// closed forms.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <algorithm>
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
            std::string(scene.environment.empty() ? "" : " -DHAS_ENVIRONMENT_MAP") +
            lightSelectOption(table.info.lightCount));
    cl::Buffer out = deviceBuffer(device, size_t(n) * 16, "estimates");
    cl::Kernel k(program, kernelName);
    int arg = 0;
    k.setArg(arg++, buffers.lights);
    k.setArg(arg++, buffers.lightCdf);
    k.setArg(arg++, buffers.triVertices);
    k.setArg(arg++, buffers.sceneInfo);
    k.setArg(arg++, buffers.envRadiance);
    k.setArg(arg++, buffers.envMarginalCdf);
    k.setArg(arg++, buffers.envConditionalCdf);
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
// An 8 × 4 environment map whose texels all differ, one of them 40 times
// brighter than the rest, turned by 30°, at strength 1.5.
EnvironmentMap testEnvironment()
{
    EnvironmentMap m;
    m.path = "test environment";
    m.image = Image(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) {
            float* c = &m.image.rgb[3 * size_t(y * 8 + x)];
            c[0] = 0.2f + 0.1f * float(x);
            c[1] = 0.3f + 0.2f * float(y);
            c[2] = (x == 5 && y == 1) ? 20.0f : 0.5f;
        }
    m.strength = 1.5f;
    m.rotation = 30;
    return m;
}

// Σ over texels of radiance × weight(row): the closed forms below integrate
// a piecewise-constant map exactly.
template <typename RowWeight>
std::array<double, 3> sumOverTexels(const EnvironmentMap& m, RowWeight weight)
{
    std::array<double, 3> sum{};
    for (int y = 0; y < m.image.height; ++y) {
        double theta0 = kPi * y / m.image.height, theta1 = kPi * (y + 1) / m.image.height;
        for (int x = 0; x < m.image.width; ++x)
            for (int c = 0; c < 3; ++c)
                sum[size_t(c)] += m.strength * m.image.rgb[3 * size_t(y * m.image.width + x) + size_t(c)] *
                                  weight(theta0, theta1) * 2 * kPi / m.image.width;
    }
    return sum;
}

void expectNear(const Estimate& e, std::array<double, 3> expected, const char* what)
{
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(e.mean[c], expected[c], 4 * e.standardError[c] + 1e-5 * std::fabs(expected[c]))
            << what << " channel " << c << " (standard error " << e.standardError[c] << ")";
}

// The render programs carry the light selection's step count for their
// table (enough bits for the largest index, in multiples of 4): without it
// the kernels fall back to the 31 steps that cover any table. Enough steps is
// what the sampling tests below check; this checks the renderer asks for them.
// The light table lists emitters in the scene's triangle order, whatever
// order the BVH stores the triangles in, so that which emitter a selection
// number picks, and so an image at a given seed, does not change with the
// tree's build. Two trees that differ only in that order (the second the
// first reversed) must give the same lights, each naming its own BVH
// position of the same scene triangle.
TEST(Lights, TableFollowsTheSceneNotTheTree)
{
    Scene scene = lightScene(false);
    for (int k = 0; k < 5; ++k) {
        Material m = scene.materials[0];
        m.emission[0] = float(k + 1);
        scene.materials.push_back(m);
        for (Vec3 v : {Vec3(float(k), 1, 0), Vec3(float(k), 1, 1), Vec3(float(k) + 1, 1, 0)}) scene.vertices.push_back(v);
        scene.triangleMaterial.push_back(int(scene.materials.size()) - 1);
    }
    Bvh tree = buildBvh(scene.vertices), reversed = tree;
    std::reverse(reversed.triangleOrder.begin(), reversed.triangleOrder.end());
    LightTable a = buildLightTable(scene, tree), b = buildLightTable(scene, reversed);
    ASSERT_EQ(a.lights.size(), 5u);
    ASSERT_EQ(b.lights.size(), a.lights.size());
    EXPECT_EQ(a.cdf, b.cdf);
    for (size_t k = 0; k < a.lights.size(); ++k) {
        SCOPED_TRACE(k);
        EXPECT_EQ(a.lights[k].emission[0], float(k + 1)); // the scene's order
        EXPECT_EQ(b.lights[k].emission[0], a.lights[k].emission[0]);
        EXPECT_EQ(tree.triangleOrder[size_t(a.lights[k].triangle)], reversed.triangleOrder[size_t(b.lights[k].triangle)]);
        EXPECT_EQ(a.triangleLight[size_t(a.lights[k].triangle)], int(k));
        EXPECT_EQ(b.triangleLight[size_t(b.lights[k].triangle)], int(k));
    }
}

TEST(Lights, RenderProgramsSearchTheirOwnTable)
{
    SceneFeatures features;
    auto steps = [&](int lights) {
        std::string o = Renderer::programOptions(Algorithm::VertexConnectionMerging, features, lights);
        size_t at = o.find("-DLIGHT_SELECT_STEPS=");
        return at == std::string::npos ? -1 : std::atoi(o.c_str() + at + 21);
    };
    EXPECT_EQ(steps(1), 0);
    EXPECT_EQ(steps(2), 4);
    EXPECT_EQ(steps(16), 4);
    EXPECT_EQ(steps(17), 8);
    EXPECT_EQ(steps(1 << 20), 20);
    EXPECT_EQ(steps((1 << 20) + 1), 24);
    EXPECT_EQ(steps(1 << 30), 31);
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
        // An environment map: its radiance through the disk, π R² ∫ L dω,
        // with ∫ over a texel of dω = Δφ (cos θ0 − cos θ1).
        Scene s = lightScene(false);
        s.environment = testEnvironment();
        double r = 0.5 * length(s.bounds().extent());
        std::array<double, 3> expected =
            sumOverTexels(s.environment, [](double t0, double t1) { return std::cos(t0) - std::cos(t1); });
        for (double& v : expected) v *= kPi * r * r;
        expectNear(run(s, "emission_power", n), expected, "environment map");
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
        // An environment map over the upper hemisphere (its rows end at the
        // horizon): E = ∫ L cos θ dω, over a texel Δφ (sin² θ1 − sin² θ0) / 2.
        Scene s = lightScene(false);
        s.environment = testEnvironment();
        std::array<double, 3> expected = sumOverTexels(s.environment, [](double t0, double t1) {
            return t1 <= 0.5 * kPi + 1e-9 ? 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0)) : 0.0;
        });
        expectNear(run(s, "nee_irradiance", n, {0, 0.5f, 0, 0}, up), expected, "environment map");
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

// The environment map's sampler against its documented frame
// (kernels/lights/environment.h): θ from +y, φ = atan2(x, −z) with the map's
// centre along −z, turned by `rotation`. Every sampled direction must fall in
// a texel whose radiance is the one the sampler returned, the kernels' own
// lookup must agree with the sampler (else MIS would weigh the two
// strategies with different densities), and the texels must be picked in
// proportion to luminance · solid angle.
TEST(Lights, EnvironmentMapSamplesFollowItsFrame)
{
    Scene scene = lightScene(false);
    scene.environment = testEnvironment();
    DeviceInfo info = test::devicesUnderTest()[0];
    DeviceContext device(info);
    Bvh bvh = buildBvh(scene.vertices);
    LightTable table = buildLightTable(scene, bvh);
    SceneBuffers buffers(device, scene, bvh, table);
    cl::Program program = test::buildTestProgram(device, {test::testKernel("light_tests.cl")},
                                                 "-DHAS_BACKGROUND -DHAS_ENVIRONMENT_MAP" +
                                                     lightSelectOption(table.info.lightCount));
    const int n = 1 << 18;
    cl::Buffer out = deviceBuffer(device, size_t(n) * 64, "samples");
    cl::Kernel k(program, "environment_samples");
    int arg = 0;
    k.setArg(arg++, buffers.lights);
    k.setArg(arg++, buffers.sceneInfo);
    k.setArg(arg++, buffers.envRadiance);
    k.setArg(arg++, buffers.envMarginalCdf);
    k.setArg(arg++, buffers.envConditionalCdf);
    k.setArg(arg++, n);
    k.setArg(arg++, out);
    device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(test::launchSize(n)), cl::NDRange(64));
    std::vector<float> v(size_t(n) * 16);
    device.queue.enqueueReadBuffer(out, CL_TRUE, 0, v.size() * 4, v.data());

    const EnvironmentMap& m = scene.environment;
    const int w = m.image.width, h = m.image.height;
    std::vector<double> count(size_t(w * h), 0.0);
    int wrongTexel = 0, lookupDisagrees = 0, failed = 0;
    std::string disagreements; // the first few, for the failure message
    for (int i = 0; i < n; ++i) {
        const float* s = &v[16 * size_t(i)];
        if (s[3] < 0) {
            ++failed;
            continue;
        }
        double theta = std::acos(std::clamp(double(s[1]), -1.0, 1.0));
        double u = std::atan2(double(s[0]), -double(s[2])) / (2 * kPi) + 0.5 - m.rotation / 360.0;
        u -= std::floor(u);
        int x = std::min(int(u * w), w - 1), y = std::min(int(theta / kPi * h), h - 1);
        const float* texel = &m.image.rgb[3 * size_t(y * w + x)];
        bool same = true;
        for (int c = 0; c < 3; ++c) same = same && std::fabs(s[4 + c] - m.strength * texel[c]) <= 1e-5f * s[4 + c];
        wrongTexel += !same;
        if (s[7] != 1.0f && ++lookupDisagrees <= 4) {
            char line[480];
            std::snprintf(line, sizeof line,
                          "\n  d (%.7g %.7g %.7g): sampled texel %d radiance (%.7g %.7g %.7g) pdf %.7g; looked up "
                          "texel %g radiance (%.7g %.7g %.7g, %s) pdf %.7g u %.7g (host %.7g), rotation %.7g (host %.7g)",
                          s[0], s[1], s[2], y * w + x, s[4], s[5], s[6], s[3], s[9], s[12], s[13], s[14],
                          s[15] == 1.0f ? "the same" : "different", s[8], s[10],
                          std::atan2(double(s[0]), -double(s[2])) / (2 * kPi) + 0.5 - m.rotation / 360.0, s[11],
                          m.rotation / 360.0);
            disagreements += line;
        }
        count[size_t(y * w + x)] += 1;
    }
    // Directions within float rounding of a texel border may land in the neighbour.
    EXPECT_EQ(failed, 0);
    EXPECT_LT(wrongTexel, n / 10000) << "sampled radiance not that of the texel the direction lies in";
    EXPECT_LT(lookupDisagrees, n / 10000) << "the kernels' lookup disagrees with their sampler:" << disagreements;
    std::printf("[ environment ] %d of %d samples in another texel, %d looked up differently\n", wrongTexel, n,
                lookupDisagrees);
    double total = 0;
    std::vector<double> expected(size_t(w * h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float* c = &m.image.rgb[3 * size_t(y * w + x)];
            double lum = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            expected[size_t(y * w + x)] = lum * std::sin(kPi * (y + 0.5) / h);
            total += expected[size_t(y * w + x)];
        }
    for (size_t t = 0; t < expected.size(); ++t) {
        double p = expected[t] / total, sd = std::sqrt(n * p * (1 - p));
        EXPECT_NEAR(count[t], n * p, 5 * sd + 1) << "texel " << t;
    }
}

} // namespace
} // namespace wv
