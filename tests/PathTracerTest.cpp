// The path tracer (-a pt) against analytic answers and across devices:
// white furnaces, agreement between OpenCL implementations, and the error's
// O(N^-1/2) convergence.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "scene/GltfLoader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

namespace wv {
namespace {

// A UV sphere; `inward` winds the triangles so the front face (and the
// geometric normal) looks at the centre.
void addSphere(Scene& s, Vec3 centre, float radius, bool inward, int material, int rings = 24, int segments = 48)
{
    auto point = [&](int ring, int seg) {
        float theta = float(M_PI) * float(ring) / float(rings), phi = 2.0f * float(M_PI) * float(seg) / float(segments);
        return centre + Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)) * radius;
    };
    auto triangle = [&](Vec3 a, Vec3 b, Vec3 c) {
        if (inward) std::swap(b, c);
        for (Vec3 v : {a, b, c}) s.vertices.push_back(v);
        s.triangleMaterial.push_back(material);
    };
    for (int r = 0; r < rings; ++r)
        for (int g = 0; g < segments; ++g) {
            Vec3 p00 = point(r, g), p01 = point(r, g + 1), p10 = point(r + 1, g), p11 = point(r + 1, g + 1);
            // Outward winding: counter-clockwise seen from outside.
            if (r > 0) triangle(p00, p01, p10);
            if (r < rings - 1) triangle(p01, p11, p10);
        }
}

Material lambert(float albedo, float emission = 0)
{
    Material m{};
    for (int c = 0; c < 3; ++c) {
        m.baseColor[c] = albedo;
        m.emission[c] = emission;
        m.specularColor[c] = 1;
    }
    m.roughness = 1;
    m.ior = 1.5f;
    m.thinWalled = 1;
    m.lobes = LOBE_DIFFUSE;
    return m;
}

struct Render {
    Image image;
    uint64_t nonFinite = 0;
};

Render renderPt(const DeviceInfo& info, const Scene& scene, int width, int height, int iterations, uint32_t seed,
                int maxPathLength = 1 << 20)
{
    DeviceContext device(info);
    Bvh bvh = buildBvh(scene.vertices);
    RenderSettings s;
    s.algorithm = Algorithm::PathTracing;
    s.width = width;
    s.height = height;
    s.seed = seed;
    s.maxPathLength = maxPathLength;
    s.wavefront = 1024; // several rounds of slot regeneration per iteration
    Renderer renderer(device, scene, bvh, s);
    for (int i = 0; i < iterations; ++i) renderer.iterate();
    return {renderer.image(), renderer.nonFiniteCount()};
}

// Mean over pixels and channels, and its standard error from the spread of
// the pixel values (pixels are independent samples of a uniform image).
void meanAndStandardError(const Image& img, double* mean, double* se)
{
    size_t n = img.rgb.size();
    double sum = std::accumulate(img.rgb.begin(), img.rgb.end(), 0.0), sq = 0;
    *mean = sum / double(n);
    for (float v : img.rgb) sq += (v - *mean) * (v - *mean);
    *se = std::sqrt(sq / double(n - 1) / double(n / 3)); // channels of a pixel are correlated: count pixels
}

// Inside a closed enclosure whose surface has albedo a and emits Le, radiance
// is Le / (1 − a) everywhere (Le + a·Le + a²·Le + …), whatever the shape and
// whatever else inside conserves energy. The camera looks at the enclosure
// and at an object inside it.
void expectFurnace(float albedo, const Material* object, const char* what, bool cameraInsideObject = false)
{
    const float Le = 0.5f;
    Scene scene;
    scene.path = what;
    scene.materials.push_back(lambert(albedo, Le));
    addSphere(scene, {0, 0, 0}, 2.0f, true, 0);
    if (object) {
        scene.materials.push_back(*object);
        if (cameraInsideObject)
            addSphere(scene, {0, 0, 0}, 1.0f, false, 1);
        else
            addSphere(scene, {0, 0, -0.8f}, 0.6f, false, 1);
    }
    scene.camera.position = cameraInsideObject ? Vec3(0, 0, 0) : Vec3(0, 0, 1.2f);
    scene.camera.forward = {0, 0, -1};
    scene.camera.yfov = 1.2f;
    // Inside a dielectric of index η in equilibrium, radiance is η² times
    // that outside (the radiance theorem, Veach 1997 §5.2).
    double eta2 = cameraInsideObject ? double(object->ior) * object->ior : 1.0;
    double expected = eta2 * Le / (1.0 - albedo);
    // On the first device only: furnace paths are long, and every round costs
    // each kernel's launch (~0.2 ms on rusticl); SameImageOnEveryDevice
    // covers agreement across implementations.
    {
        DeviceInfo info = test::devicesUnderTest()[0];
        SCOPED_TRACE(std::string(what) + " on " + info.name);
        Render r = renderPt(info, scene, 48, 48, 12, 7); // few iterations: rounds cost launches
        double mean, se;
        meanAndStandardError(r.image, &mean, &se);
        // 5 standard errors: a false alarm has probability ~6e-7; a 2 % bias
        // is several times larger than the standard error here.
        EXPECT_NEAR(mean, expected, 5 * se) << "standard error " << se;
        EXPECT_LT(se, 0.01 * expected) << "too noisy to detect a 2 % bias";
        EXPECT_EQ(r.nonFinite, 0u);
    }
}

TEST(PathTracer, DiffuseFurnace)
{
    expectFurnace(0.5f, nullptr, "albedo 0.5");
    expectFurnace(0.8f, nullptr, "albedo 0.8");
}

TEST(PathTracer, FurnaceWithSmoothGlassInside)
{
    // Exact Fresnel reflection plus refraction (with the 1/η² radiance
    // scaling on the way in and η² on the way out) conserves energy.
    Material glass{};
    for (int c = 0; c < 3; ++c) { glass.baseColor[c] = 1; glass.specularColor[c] = 1; }
    glass.specular = 1;
    glass.transmission = 1;
    glass.ior = 1.5f;
    glass.lobes = LOBE_DELTA_REFLECTION | LOBE_DELTA_TRANSMISSION;
    expectFurnace(0.6f, &glass, "smooth glass");
    expectFurnace(0.6f, &glass, "inside smooth glass", true);
}

TEST(PathTracer, FurnaceWithWhiteMirrorInside)
{
    // A metal with base colour 1 reflects everything (Schlick F = 1).
    Material mirror{};
    for (int c = 0; c < 3; ++c) { mirror.baseColor[c] = 1; mirror.specularColor[c] = 1; }
    mirror.metallic = 1;
    mirror.specular = 1;
    mirror.ior = 1.5f;
    mirror.thinWalled = 1;
    mirror.lobes = LOBE_DELTA_REFLECTION;
    expectFurnace(0.6f, &mirror, "white mirror");
}

// Every bundled scene renders: a non-black image, every sample finite.
TEST(PathTracer, EveryBundledSceneRendersFinite)
{
    for (const char* name : {"cornell-box", "cornell-box-point", "cornell-box-background", "cornell-box-directional",
                             "caustics"}) {
        SCOPED_TRACE(name);
        Scene scene = loadGltf(std::string(WAVEVCM_SOURCE_DIR) + "/scenes/" + name + ".gltf");
        Render r = renderPt(test::devicesUnderTest()[0], scene, 32, 24, 4, 3, 8);
        EXPECT_EQ(r.nonFinite, 0u);
        double sum = 0;
        for (float v : r.image.rgb) {
            ASSERT_TRUE(std::isfinite(v));
            sum += v;
        }
        EXPECT_GT(sum / double(r.image.rgb.size()), 0.01) << "black image";
    }
}

double imageMean(const Image& img)
{
    return std::accumulate(img.rgb.begin(), img.rgb.end(), 0.0) / double(img.rgb.size());
}

// PoCL and rusticl render the Cornell box alike. Each device renders the same
// three seeds. The seed-to-seed spread of 8×8-pixel tile means gives their
// standard error; the devices' tile means (over the seeds) must agree within
// 5 of them. With the same seeds both devices draw the same samples, so
// their images must also be much closer to each other than two seeds are.
TEST(PathTracer, SameImageOnEveryDevice)
{
    std::vector<DeviceInfo> devices = test::devicesUnderTest();
    if (devices.size() < 2) GTEST_SKIP() << "only one OpenCL device; install mesa-opencl-icd for rusticl";
    Scene scene = loadGltf(test::cornellBoxPath());
    const int w = 48, h = 48, iterations = 16, tile = 8;
    const uint32_t seeds[] = {1, 2, 3};
    std::vector<std::vector<Image>> images(devices.size());
    for (size_t d = 0; d < devices.size(); ++d)
        for (uint32_t seed : seeds) images[d].push_back(renderPt(devices[d], scene, w, h, iterations, seed, 10).image);

    auto tileMean = [&](const Image& img, int tx, int ty) {
        double sum = 0;
        for (int y = ty * tile; y < (ty + 1) * tile; ++y)
            for (int x = tx * tile; x < (tx + 1) * tile; ++x)
                for (int c = 0; c < 3; ++c) sum += img.rgb[3 * (size_t(y) * w + x) + c];
        return sum / (tile * tile * 3);
    };
    const size_t S = std::size(seeds);
    for (size_t d = 1; d < devices.size(); ++d) {
        SCOPED_TRACE(devices[0].name + " vs " + devices[d].name);
        int bad = 0;
        for (int ty = 0; ty < h / tile; ++ty)
            for (int tx = 0; tx < w / tile; ++tx) {
                double m0 = 0, m1 = 0, var = 0;
                std::vector<double> a, b;
                for (size_t s = 0; s < S; ++s) {
                    a.push_back(tileMean(images[0][s], tx, ty));
                    b.push_back(tileMean(images[d][s], tx, ty));
                    m0 += a.back() / S;
                    m1 += b.back() / S;
                }
                for (size_t s = 0; s < S; ++s) var += ((a[s] - m0) * (a[s] - m0) + (b[s] - m1) * (b[s] - m1)) / (2 * (S - 1));
                double se = std::sqrt(2 * var / S) + 1e-6;
                if (std::fabs(m0 - m1) > 5 * se) {
                    ++bad;
                    ADD_FAILURE() << "tile " << tx << "," << ty << ": " << m0 << " vs " << m1 << " (se " << se << ")";
                }
            }
        EXPECT_EQ(bad, 0);
        double sameSeed = compareImages(images[d][0], images[0][0]).relMse;
        double otherSeed = compareImages(images[0][1], images[0][0]).relMse;
        EXPECT_LT(sameSeed, 0.25 * otherSeed) << "same-seed images differ about as much as independent ones";
        EXPECT_NEAR(imageMean(images[d][0]) / imageMean(images[0][0]), 1.0, 0.01);
    }
}

// The error against a long render falls as N^-1/2 with the number of
// iterations N: fit log RMSE against log N over N = 4 … 256 (mean squared
// error over two seeds each). The reference's own error (8× more samples
// than the largest N) is subtracted from the measured MSE, which is its
// expected contribution. Tolerance ±0.1 on the slope: far outside it are
// biased estimators (slope → 0) and broken sample sequences (slope ≠ −0.5).
TEST(PathTracer, ErrorFallsAsInverseSquareRootOfSamples)
{
    Scene scene = loadGltf(test::cornellBoxPath());
    DeviceInfo info = test::devicesUnderTest()[0];
    const int w = 40, h = 40, referenceIterations = 2048;
    Image reference = renderPt(info, scene, w, h, referenceIterations, 1000, 6).image;
    std::vector<double> logN, logRmse;
    double referenceMse = 0;
    std::vector<std::pair<int, double>> mses;
    for (int n : {4, 16, 64, 256}) {
        double mse = 0;
        for (uint32_t seed : {1u, 2u}) {
            double rmse = compareImages(renderPt(info, scene, w, h, n, seed, 6).image, reference).rmse;
            mse += rmse * rmse / 2;
        }
        mses.push_back({n, mse});
    }
    // MSE(N) = σ²/N + σ²/N_ref: estimate σ² from the smallest N, where the
    // reference's share is negligible, then remove the reference's share.
    double sigma2 = mses.front().second * mses.front().first;
    referenceMse = sigma2 / referenceIterations;
    for (auto [n, mse] : mses) {
        logN.push_back(std::log(double(n)));
        logRmse.push_back(0.5 * std::log(std::max(mse - referenceMse, 1e-30)));
        std::printf("[ N = %3d ] RMSE %.5f\n", n, std::sqrt(mse));
    }
    double mx = std::accumulate(logN.begin(), logN.end(), 0.0) / logN.size();
    double my = std::accumulate(logRmse.begin(), logRmse.end(), 0.0) / logRmse.size();
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < logN.size(); ++i) {
        sxy += (logN[i] - mx) * (logRmse[i] - my);
        sxx += (logN[i] - mx) * (logN[i] - mx);
    }
    double slope = sxy / sxx;
    std::printf("[ slope ] %.3f\n", slope);
    EXPECT_NEAR(slope, -0.5, 0.1);
}

} // namespace
} // namespace wv
