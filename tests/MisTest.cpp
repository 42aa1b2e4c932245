// The MIS weights of all techniques that sample one path sum to one: vertex
// connection and merging's recursive quantities (kernels/transport/mis.h) must
// reproduce, for every way of splitting a path, the same set of pdf ratios.
// Fixed random paths of 2 to 6 segments over Lambertian vertices (each with a
// shading normal apart from its geometric one) from a triangle light to the
// camera; every technique VCM has: emission hit,
// next-event estimation, the connections, light tracing to the camera, and a
// merge at every interior vertex; for merge radii from tiny to large.
#include "TestDevices.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace wv {
namespace {

TEST(Mis, WeightsOfAllTechniquesSumToOne)
{
    DeviceInfo info = test::devicesUnderTest()[0];
    DeviceContext device(info);
    cl::Program program = test::buildTestProgram(device, {test::testKernel("mis_tests.cl")}, "-DSCENE_LOBES=31u");
    Material lambert{};
    for (int c = 0; c < 3; ++c) {
        lambert.baseColor[c] = 0.8f;
        lambert.specularColor[c] = 1;
    }
    lambert.roughness = 1;
    lambert.ior = 1.5f;
    lambert.thinWalled = 1;
    lambert.lobes = LOBE_DIFFUSE;
    cl::Buffer material = uploadBuffer(device, &lambert, sizeof lambert, "material");

    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-1, 1);
    const int pathCount = 256;
    for (int k = 2; k <= 6; ++k) {
        // One camera for all paths: at the origin looking down -z; every
        // path's last vertex lies in front of it.
        CameraView view;
        view.position = {0, 0, 0};
        view.forward = {0, 0, -1};
        view.yfov = 1.0f;
        Camera camera = makeCamera(view, 64, 64);
        std::vector<std::array<float, 4>> positions, normals, shadingNormals;
        int tilted = 0; // interior vertices whose shading normal differs
        for (int p = 0; p < pathCount; ++p) {
            std::vector<Vec3> z(size_t(k) + 1);
            z[size_t(k)] = {0, 0, 0};
            z[size_t(k) - 1] = Vec3(0.2f * u(rng), 0.2f * u(rng), -3 + 0.5f * u(rng));
            for (int j = k - 2; j >= 0; --j) z[size_t(j)] = z[size_t(j) + 1] + Vec3(u(rng), u(rng), u(rng));
            for (int j = 0; j <= k; ++j) {
                Vec3 n(0, 0, 1);
                if (j == 0) n = normalize(normalize(z[1] - z[0]) + Vec3(0.3f * u(rng), 0.3f * u(rng), 0.3f * u(rng)));
                else if (j < k) n = normalize(normalize(z[size_t(j) - 1] - z[size_t(j)]) + normalize(z[size_t(j) + 1] - z[size_t(j)]));
                // Interior vertices: a shading normal up to ~25° from the
                // geometric one, with both path directions above it.
                Vec3 ns = n;
                for (int tries = 0; j > 0 && j < k && tries < 20; ++tries) {
                    Vec3 candidate = normalize(n + Vec3(0.45f * u(rng), 0.45f * u(rng), 0.45f * u(rng)));
                    if (dot(candidate, normalize(z[size_t(j) - 1] - z[size_t(j)])) > 0.1f &&
                        dot(candidate, normalize(z[size_t(j) + 1] - z[size_t(j)])) > 0.1f) {
                        ns = candidate;
                        break;
                    }
                }
                tilted += dot(ns, n) < 0.999f;
                positions.push_back({z[size_t(j)].x, z[size_t(j)].y, z[size_t(j)].z, 0});
                normals.push_back({n.x, n.y, n.z, 0});
                shadingNormals.push_back({ns.x, ns.y, ns.z, 0});
            }
        }
        cl::Buffer cameraBuffer = uploadBuffer(device, &camera, sizeof camera, "camera");
        cl::Buffer positionBuffer = uploadBuffer(device, positions.data(), positions.size() * 16, "positions");
        cl::Buffer normalBuffer = uploadBuffer(device, normals.data(), normals.size() * 16, "normals");
        cl::Buffer shadingBuffer = uploadBuffer(device, shadingNormals.data(), shadingNormals.size() * 16, "shading");
        EXPECT_GT(tilted, pathCount * (k - 1) * 9 / 10) << "most interior vertices have a shading normal of their own";
        cl::Buffer sums = deviceBuffer(device, pathCount * 4, "sums"), counts = deviceBuffer(device, pathCount * 4, "n");
        for (float radius : {1e-4f, 1e-2f, 0.3f}) {
            SCOPED_TRACE("k = " + std::to_string(k) + ", radius " + std::to_string(radius));
            const float lightPaths = 4096, lightArea = 0.25f;
            float eta = float(M_PI) * radius * radius * lightPaths;
            cl::Kernel kernel(program, "technique_weights");
            int arg = 0;
            kernel.setArg(arg++, cameraBuffer);
            kernel.setArg(arg++, material);
            kernel.setArg(arg++, positionBuffer);
            kernel.setArg(arg++, normalBuffer);
            kernel.setArg(arg++, shadingBuffer);
            kernel.setArg(arg++, k);
            kernel.setArg(arg++, pathCount);
            kernel.setArg(arg++, lightArea);
            kernel.setArg(arg++, lightPaths);
            kernel.setArg(arg++, eta);
            kernel.setArg(arg++, sums);
            kernel.setArg(arg++, counts);
            device.queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(test::launchSize(pathCount)),
                                              cl::NDRange(64));
            std::vector<float> s(pathCount);
            std::vector<int> n(pathCount);
            device.queue.enqueueReadBuffer(sums, CL_TRUE, 0, pathCount * 4, s.data());
            device.queue.enqueueReadBuffer(counts, CL_TRUE, 0, pathCount * 4, n.data());
            int bad = 0;
            for (int p = 0; p < pathCount; ++p) {
                // k + 1 connection-family techniques and k − 1 merges.
                ASSERT_EQ(n[p], 2 * k);
                // Float rounding through up to 6 recursive steps: 1e-4.
                if (!(std::fabs(s[p] - 1.0f) < 1e-4f) && ++bad <= 3)
                    ADD_FAILURE() << "path " << p << ": weights sum to " << s[p];
            }
            EXPECT_EQ(bad, 0);
        }
    }
}

} // namespace
} // namespace wv
