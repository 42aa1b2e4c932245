// The MIS weights of all techniques that sample one path sum to one: vertex
// connection and merging's recursive quantities (kernels/transport/mis.h) must
// reproduce, for every way of splitting a path, the same set of pdf ratios.
// Fixed random paths of 2 to 6 segments over Lambertian vertices (each with a
// shading normal apart from its geometric one) from a light to the camera;
// every technique VCM has: emission hit, next-event estimation, the
// connections, light tracing to the camera, and a merge at every interior
// vertex; for merge radii from tiny to large. The light is a triangle, a
// uniform background (infinite: its first segment has no distance), a
// directional light (infinite and delta) or a point light (delta); and the
// paths are all diffuse, or have one mirror vertex, where no technique can
// split them (Georgiev's report, eqs. 53-55).
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/LightTable.h"
#include "render/Renderer.h"
#include "render/SceneBuffers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace wv {
namespace {

const Vec3 kPointLight(0.3f, 1.5f, -4.0f);
const Vec3 kDirectionalLight = normalize(Vec3(0.4f, -1.0f, -0.3f)); // the way its light travels

// A floor (for the bounding sphere, from which infinite lights emit) and the
// light under test; the triangle light is the test kernel's own (its
// densities written out there), with a point light for the table not to be
// empty.
Scene lightScene(int lightType)
{
    Scene s = test::sceneFromTriangles({{-2, 0, -2}, {2, 0, 2}, {2, 0, -2}});
    if (lightType == LIGHT_BACKGROUND) {
        s.background = {1, 1, 1};
        return s;
    }
    Light l{};
    l.type = lightType == LIGHT_DIRECTIONAL ? LIGHT_DIRECTIONAL : LIGHT_POINT;
    for (int c = 0; c < 3; ++c) {
        l.position[c] = kPointLight[c];
        l.direction[c] = kDirectionalLight[c];
        l.emission[c] = 1;
    }
    s.lights.push_back(l);
    return s;
}

// The techniques that can sample a path of k segments whose vertex
// `mirror` (-1: none) is specular: every split at two non-specular vertices,
// the emission hit where the light can be hit, every merge at a non-specular
// interior vertex.
int expectedTechniques(int k, int mirror, bool deltaLight)
{
    int n = deltaLight ? 0 : 1;                    // emission hit
    for (int s = 1; s <= k; ++s)                   // NEE (s = 1), connections, light tracing (s = k)
        n += (s == 1 || mirror != s - 1) && (s == k || mirror != s);
    for (int j = 1; j < k; ++j) n += j != mirror; // merges
    return n;
}

// The surfaces' materials: Lambertian; Lambertian under a rough dielectric
// layer (each lobe chosen by its Fresnel-weighted albedo at the direction
// the BSDF is sampled from, so forward and reverse densities differ in their
// lobe probabilities too); rough metal; Lambertian under a smooth coat (a
// delta lobe beside the diffuse one, which connections and merges use); and
// the same two under KHR_materials_clearcoat's coat, rough (a fourth lobe
// with its own Fresnel-weighted probability) and smooth (a delta lobe above
// the GGX one); a rough layer under KHR_materials_sheen's fibres (a
// lobe sampled as diffuse is, whose probability follows its albedo table);
// KHR_materials_diffuse_transmission through a thin wall and into a solid
// (η inverts inside), where every interior vertex transmits; and a rough
// layer made anisotropic (KHR_materials_anisotropy).
enum class Surface {
    Lambert, RoughLayer, RoughMetal, SmoothCoat, RoughClearcoat, SmoothClearcoat, Sheen, ThinTranslucent,
    TranslucentSolid, Brushed
};

bool transmits(Surface kind) { return kind == Surface::ThinTranslucent || kind == Surface::TranslucentSolid; }

Material surfaceMaterial(Surface kind)
{
    Material m{};
    for (int c = 0; c < 3; ++c) {
        m.baseColor[c] = 0.8f - 0.2f * float(c);
        m.specularColor[c] = 1;
    }
    m.roughness = 1;
    m.ior = 1.5f;
    m.thinWalled = 1;
    m.lobes = LOBE_DIFFUSE;
    switch (kind) {
    case Surface::Lambert: break;
    case Surface::RoughLayer:
        m.specular = 1;
        m.roughness = 0.4f;
        m.lobes = LOBE_DIFFUSE | LOBE_GGX_REFLECTION;
        break;
    case Surface::RoughMetal:
        m.metallic = 1;
        m.roughness = 0.4f;
        m.lobes = LOBE_GGX_REFLECTION;
        break;
    case Surface::SmoothCoat:
        m.specular = 1;
        m.roughness = 0;
        m.lobes = LOBE_DIFFUSE | LOBE_DELTA_REFLECTION;
        break;
    case Surface::RoughClearcoat:
        m.clearcoat = 1;
        m.clearcoatRoughness = 0.3f;
        m.lobes = LOBE_DIFFUSE | LOBE_GGX_COAT;
        break;
    case Surface::SmoothClearcoat:
        m.specular = 1;
        m.roughness = 0.4f;
        m.clearcoat = 0.8f;
        m.lobes = LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_DELTA_COAT;
        break;
    case Surface::Sheen:
        m.specular = 1;
        m.roughness = 0.4f;
        for (int c = 0; c < 3; ++c) m.sheenColor[c] = 0.3f + 0.3f * float(c);
        m.sheenRoughness = 0.4f;
        m.lobes = LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_SHEEN;
        break;
    case Surface::ThinTranslucent:
    case Surface::TranslucentSolid:
        // A specular layer of 0.5 lets some light through even beyond the
        // critical angle inside the solid, so that every technique samples
        // every path.
        m.specular = kind == Surface::TranslucentSolid ? 0.5f : 1.0f;
        m.roughness = 0.4f;
        m.diffuseTransmission = 0.6f;
        for (int c = 0; c < 3; ++c) m.diffuseTransmissionColor[c] = 0.9f - 0.2f * float(c);
        m.thinWalled = kind == Surface::ThinTranslucent ? 1 : 0;
        m.lobes = LOBE_DIFFUSE | LOBE_GGX_REFLECTION | LOBE_DIFFUSE_TRANSMISSION;
        break;
    case Surface::Brushed:
        m.specular = 1;
        m.roughness = 0.3f;
        m.anisotropy = 0.8f;
        m.anisotropyRotation[0] = std::cos(0.7f);
        m.anisotropyRotation[1] = std::sin(0.7f);
        m.lobes = LOBE_DIFFUSE | LOBE_GGX_REFLECTION;
        break;
    }
    return m;
}

void expectWeightsSumToOne(int lightType, bool withMirror, Surface kind = Surface::Lambert)
{
    const Material surface = surfaceMaterial(kind);
    DeviceInfo info = test::devicesUnderTest()[0];
    DeviceContext device(info);
    Scene scene = lightScene(lightType);
    Bvh bvh = buildBvh(scene.vertices);
    LightTable table = buildLightTable(scene, bvh);
    SceneBuffers buffers(device, scene, bvh, table);
    cl::Program program = test::buildTestProgram(
        device, {test::testKernel("mis_tests.cl")},
        "-DHAS_ANISOTROPY -DSCENE_LOBES=" + std::to_string(LOBES_ALL) + "u -DHAS_POINT_LIGHTS -DHAS_DIRECTIONAL_LIGHTS -DHAS_BACKGROUND" +
            lightSelectOption(table.info.lightCount));
    cl::Buffer material = uploadBuffer(device, &surface, sizeof surface, "material");
    const bool deltaLight = lightType == LIGHT_POINT || lightType == LIGHT_DIRECTIONAL;

    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-1, 1);
    const int pathCount = 256;
    int sampled = 0; // paths that some technique samples (not all can be)
    for (int k = 2; k <= 6; ++k) {
        // One camera for all paths: at the origin looking down -z; every
        // path's last vertex lies in front of it.
        CameraView view;
        view.position = {0, 0, 0};
        view.forward = {0, 0, -1};
        view.yfov = 1.0f;
        Camera camera = makeCamera(view, 64, 64);
        std::vector<std::array<float, 4>> positions, normals, shadingNormals;
        std::vector<int> mirrors, expected;
        int tilted = 0; // interior vertices whose shading normal differs
        for (int p = 0; p < pathCount; ++p) {
            std::vector<Vec3> z(size_t(k) + 1);
            z[size_t(k)] = {0, 0, 0};
            z[size_t(k) - 1] = Vec3(0.2f * u(rng), 0.2f * u(rng), -3 + 0.5f * u(rng));
            for (int j = k - 2; j >= 0; --j) z[size_t(j)] = z[size_t(j) + 1] + Vec3(u(rng), u(rng), u(rng));
            if (lightType == LIGHT_POINT) z[0] = kPointLight;
            if (lightType == LIGHT_DIRECTIONAL) z[0] = z[1] - kDirectionalLight * 2.0f;
            // The mirror at each interior vertex in turn.
            int mirror = withMirror ? 1 + p % (k - 1) : -1;
            mirrors.push_back(mirror);
            expected.push_back(expectedTechniques(k, mirror, deltaLight));
            for (int j = 0; j <= k; ++j) {
                Vec3 n(0, 0, 1);
                // Interior vertices reflect (the normal halves the two
                // directions) or transmit (the normal faces one, away from
                // the other).
                Vec3 back, ahead;
                if (j > 0 && j < k) {
                    back = normalize(z[size_t(j) - 1] - z[size_t(j)]);
                    ahead = normalize(z[size_t(j) + 1] - z[size_t(j)]);
                }
                const bool transmit = transmits(kind) && j > 0 && j < k && mirror != j;
                if (j == 0) n = normalize(normalize(z[1] - z[0]) + Vec3(0.3f * u(rng), 0.3f * u(rng), 0.3f * u(rng)));
                else if (j < k) n = normalize(transmit ? back - ahead : back + ahead);
                // Interior vertices: a shading normal up to ~25° from the
                // geometric one, with both path directions on its side of it.
                const float side = transmit ? -1.0f : 1.0f;
                Vec3 ns = n;
                for (int tries = 0; j > 0 && j < k && tries < 20; ++tries) {
                    Vec3 candidate = normalize(n + Vec3(0.45f * u(rng), 0.45f * u(rng), 0.45f * u(rng)));
                    if (dot(candidate, back) > 0.1f && side * dot(candidate, ahead) > 0.1f) {
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
        cl::Buffer mirrorBuffer = uploadBuffer(device, mirrors.data(), mirrors.size() * 4, "mirrors");
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
            kernel.setArg(arg++, mirrorBuffer);
            kernel.setArg(arg++, k);
            kernel.setArg(arg++, pathCount);
            kernel.setArg(arg++, lightType);
            kernel.setArg(arg++, lightArea);
            kernel.setArg(arg++, lightPaths);
            kernel.setArg(arg++, eta);
            kernel.setArg(arg++, buffers.lights);
            kernel.setArg(arg++, buffers.lightCdf);
            kernel.setArg(arg++, buffers.triVertices);
            kernel.setArg(arg++, buffers.sceneInfo);
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
                ASSERT_EQ(n[p], expected[size_t(p)]) << "path " << p << " (mirror " << mirrors[size_t(p)] << ")";
                if (n[p] == 0)
                    continue; // e.g. a point light seen only through a mirror: no technique samples it
                ++sampled;
                // Float rounding through up to 6 recursive steps: 1e-4.
                if (!(std::fabs(s[p] - 1.0f) < 1e-4f) && ++bad <= 3)
                    ADD_FAILURE() << "path " << p << " (mirror " << mirrors[size_t(p)] << "): weights sum to "
                                  << s[p];
            }
            EXPECT_EQ(bad, 0);
        }
    }
    EXPECT_GT(sampled, 5 * 3 * pathCount / 2);
}

TEST(Mis, WeightsOfAllTechniquesSumToOne) { expectWeightsSumToOne(LIGHT_TRIANGLE, false); }
TEST(Mis, WeightsSumToOneThroughAMirror) { expectWeightsSumToOne(LIGHT_TRIANGLE, true); }
TEST(Mis, WeightsSumToOneForTheBackground)
{
    expectWeightsSumToOne(LIGHT_BACKGROUND, false);
    expectWeightsSumToOne(LIGHT_BACKGROUND, true);
}
TEST(Mis, WeightsSumToOneForADirectionalLight)
{
    expectWeightsSumToOne(LIGHT_DIRECTIONAL, false);
    expectWeightsSumToOne(LIGHT_DIRECTIONAL, true);
}
TEST(Mis, WeightsSumToOneForAPointLight)
{
    expectWeightsSumToOne(LIGHT_POINT, false);
    expectWeightsSumToOne(LIGHT_POINT, true);
}
TEST(Mis, WeightsSumToOneOnGlossySurfaces)
{
    for (Surface kind : {Surface::RoughLayer, Surface::RoughMetal, Surface::SmoothCoat, Surface::RoughClearcoat,
                         Surface::SmoothClearcoat, Surface::Sheen, Surface::ThinTranslucent,
                         Surface::TranslucentSolid, Surface::Brushed}) {
        SCOPED_TRACE("surface " + std::to_string(int(kind)));
        expectWeightsSumToOne(LIGHT_TRIANGLE, false, kind);
        expectWeightsSumToOne(LIGHT_BACKGROUND, true, kind);
    }
}

} // namespace
} // namespace wv
