#include "TestDevices.h"

#include <cstdlib>

namespace wv::test {

std::vector<DeviceInfo> devicesUnderTest()
{
    // WAVEVCM_TEST_DEVICES (render's -d syntax) narrows the run, e.g. to the
    // GPU alone where a slow CPU driver is also installed (scripts/gpu_kit_run.sh).
    const char* selectors = std::getenv("WAVEVCM_TEST_DEVICES");
    if (selectors && *selectors) return selectDevices(enumerateDevices(), selectors);
    return enumerateDevices();
}

bool isFirstDevice(const DeviceInfo& device) { return device.index == devicesUnderTest().front().index; }

std::string testKernel(const std::string& name) { return std::string(WAVEVCM_TEST_KERNEL_DIR) + "/" + name; }

cl::Program buildTestProgram(DeviceContext& device, const std::vector<std::string>& files, const std::string& options)
{
    std::string source = expandKernelSources(findKernelDir(), files);
    return buildProgram(device.context, device.info, source, "-cl-std=CL1.2 " + options).program;
}

Scene sceneFromTriangles(std::vector<Vec3> vertices)
{
    Scene s;
    s.path = "(generated)";
    s.vertices = std::move(vertices);
    Material m{};
    m.baseColor[0] = m.baseColor[1] = m.baseColor[2] = 0.5f;
    m.roughness = 1;
    m.ior = 1.5f;
    m.lobes = LOBE_DIFFUSE;
    s.materials.push_back(m);
    s.triangleMaterial.assign(s.vertices.size() / 3, 0);
    return s;
}

std::string cornellBoxPath() { return std::string(WAVEVCM_SOURCE_DIR) + "/scenes/cornell-box.gltf"; }

SceneFeatures everyFeature()
{
    SceneFeatures all;
    all.vertexNormals = true;
    all.lobes = LOBES_ALL;
    all.pointLights = all.spotLights = all.directionalLights = all.emissiveTriangles = all.background = true;
    all.environmentMap = all.textures = all.normalMaps = all.alphaTest = all.emissiveTextures = all.texCoord1 = true;
    all.volumeAbsorption = all.vertexColors = all.tangents = all.anisotropy = true;
    return all;
}

} // namespace wv::test
