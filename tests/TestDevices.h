// Helpers shared by the tests that run on every OpenCL device present.
#pragma once

#include "cl/DeviceContext.h"
#include "cl/Program.h"
#include "scene/Scene.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace wv::test {

// Every device (ctest sets RUSTICL_ENABLE=llvmpipe so rusticl is among them),
// or those WAVEVCM_TEST_DEVICES selects.
std::vector<DeviceInfo> devicesUnderTest();

// Whether `device` is the first of devicesUnderTest(): tests that cover a case
// once, not per implementation, run it there alone (rusticl renders a small
// iteration ~50x slower than PoCL, and compiles each program of its own).
bool isFirstDevice(const DeviceInfo& device);

// A program of the named kernel files; test kernels live in tests/kernels.
cl::Program buildTestProgram(DeviceContext& device, const std::vector<std::string>& files,
                             const std::string& options = "");

std::string testKernel(const std::string& name);

// A scene with one diffuse material and the given triangles (3 vertices each).
Scene sceneFromTriangles(std::vector<Vec3> vertices);

// The Cornell box from scenes/.
std::string cornellBoxPath();

// The features of a scene that uses all of them: a program built for it
// compiles every code path of the kernels.
SceneFeatures everyFeature();

// Runs check(device, program) on every device under test with the program of
// test kernel file `kernelFile`, under a trace naming the device.
template <typename Check> void onEveryDevice(const std::string& kernelFile, Check check)
{
    for (const DeviceInfo& info : devicesUnderTest()) {
        SCOPED_TRACE(info.name + " (" + info.platformName + ")");
        DeviceContext device(info);
        check(device, buildTestProgram(device, {testKernel(kernelFile)}));
    }
}

// Rounds n up to a multiple of 64, the local size the tests launch with.
inline size_t launchSize(size_t n) { return (n + 63) / 64 * 64; }

} // namespace wv::test
