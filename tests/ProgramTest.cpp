// Kernel sources and programs: #include inlining with #line, the build log
// on failure naming file and line, the on-disk binary cache, and one build
// per source and options in a context.
#include "TestDevices.h"
#include "bvh/Bvh.h"
#include "render/Renderer.h"
#include "render/SceneBuffers.h"
#include "scene/GltfLoader.h"
#include "Error.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace wv {
namespace {

struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name)
        : path(fs::temp_directory_path() / ("wavevcm-" + name + "-" + std::to_string(::getpid())))
    {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    void write(const std::string& file, const std::string& text) const { std::ofstream(path / file) << text; }
};

TEST(KernelSources, IncludesAreInlinedOnceWithLineDirectives)
{
    TempDir dir("expand");
    dir.write("a.h", "#ifndef A\n#define A\nint a;\n#endif\n");
    dir.write("b.h", "#include \"a.h\"\nint b;\n");
    dir.write("main.cl", "#include \"a.h\"\n#include \"b.h\"\nint main_;\n");
    std::string out = expandKernelSources(dir.path.string(), {"main.cl"});
    EXPECT_NE(out.find("#line 1 \"main.cl\""), std::string::npos);
    EXPECT_NE(out.find("#line 3 \"main.cl\""), std::string::npos) << out; // after the second include
    EXPECT_EQ(out.find("int a;"), out.rfind("int a;")) << "a.h inlined twice:\n" << out;
    EXPECT_NE(out.find("int b;"), std::string::npos);
}

TEST(KernelSources, MissingIncludeNamesFileAndLine)
{
    TempDir dir("missing");
    dir.write("main.cl", "int x;\n#include \"nowhere.h\"\n");
    try {
        expandKernelSources(dir.path.string(), {"main.cl"});
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("main.cl:2"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("nowhere.h"), std::string::npos) << e.what();
    }
}

TEST(KernelSources, EveryRenderKernelBuilds)
{
    // The production kernels compile with every feature on and with every
    // feature off (the scene-specific builds lie in between). On the first
    // device only: the renders build each algorithm on every device, and
    // rusticl's front end is clang as PoCL's is (its eight builds here took
    // ~20 s of a CI run).
    DeviceInfo info = test::devicesUnderTest()[0];
    DeviceContext device(info);
    for (Algorithm a : {Algorithm::EyeLight, Algorithm::PathTracing, Algorithm::LightTracing, Algorithm::Bidirectional}) {
        std::string source = expandKernelSources(findKernelDir(), Renderer::kernelFiles(a));
        SCOPED_TRACE(info.name + " " + algorithmName(a));
        std::string mode = a == Algorithm::LightTracing    ? " -DBIDIRECTIONAL -DLIGHT_TRACING"
                           : a == Algorithm::Bidirectional ? " -DBIDIRECTIONAL"
                           : a == Algorithm::EyeLight      ? " -DEYE_LIGHT"
                                                           : "";
        // The fewest features (with an orthographic camera, which only takes code
        // away) and the most.
        for (std::string options :
             {std::string(" -DSCENE_LOBES=0u -DORTHOGRAPHIC_CAMERA"), test::everyFeature().buildOptions()})
            EXPECT_NO_THROW(buildProgram(device.context, info, source, "-cl-std=CL1.2" + options + mode));
    }
}

// A cold build prints nothing: PoCL's compiler writes "N warnings generated."
// to the terminal of every first run that has warnings (on AVX2 CPUs, double8
// conversions in the triangle test printed nine). The define that no other
// build uses makes the build cold, past wavevcm's and PoCL's caches; every
// feature on, so that each kernel's code is compiled.
TEST(ProgramBuild, KernelsBuildWithoutWarnings)
{
    std::string uncached = " -DWAVEVCM_TEST_COLD_BUILD=" + std::to_string(::getpid()) + "u" +
                           std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + "u";
    for (Algorithm a : {Algorithm::PathTracing, Algorithm::Bidirectional}) {
        std::string source = expandKernelSources(findKernelDir(), Renderer::kernelFiles(a));
        for (const DeviceInfo& info : test::devicesUnderTest()) {
            SCOPED_TRACE(info.name + " " + algorithmName(a));
            DeviceContext device(info);
            std::string options = "-cl-std=CL1.2" + test::everyFeature().buildOptions() +
                                  " -DTRIANGLE_PACKET_WIDTH=" + std::to_string(trianglePacketWidth(info)) +
                                  (a == Algorithm::Bidirectional ? " -DBIDIRECTIONAL -DVERTEX_CONNECTION" : "");
            ProgramBuild build = buildProgram(device.context, info, source, options + uncached);
            ASSERT_FALSE(build.fromCache);
            EXPECT_EQ(build.log.find("warning"), std::string::npos) << build.log;
        }
    }
}

// Kernel sources are read from the tree at run time: where they declare the
// shared structs otherwise than the binary was built with (edited or
// updated without rebuilding), the program must fail to build, saying so,
// not run with its arguments read wrongly (a crash, before the check).
TEST(KernelSources, ASharedStructLayoutOtherThanTheHostsFailsTheBuild)
{
    DeviceInfo info = test::devicesUnderTest()[0];
    DeviceContext device(info);
    std::string source = expandKernelSources(findKernelDir(), Renderer::kernelFiles(Algorithm::PathTracing));
    std::string options = "-cl-std=CL1.2 -DSCENE_LOBES=0u -DHOST_STRUCT_LAYOUT=";
    EXPECT_NO_THROW(buildProgram(device.context, info, source, options + std::to_string(STRUCT_LAYOUT) + "u"));
    try {
        buildProgram(device.context, info, source, options + std::to_string(STRUCT_LAYOUT + 4) + "u");
        FAIL() << "kernels of another layout built";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("otherwise_than_the_wavevcm_binary_rebuild_it"), std::string::npos)
            << e.what();
    }
}

TEST(ProgramBuild, FailureReportsTheBuildLogWithFileAndLine)
{
    TempDir dir("broken");
    dir.write("broken.cl", "__kernel void k(__global int* x)\n{\n    x[0] = undeclared_name;\n}\n");
    std::string source = expandKernelSources(dir.path.string(), {"broken.cl"});
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        SCOPED_TRACE(info.name);
        DeviceContext device(info);
        try {
            buildProgram(device.context, info, source, "");
            FAIL() << "the broken kernel built";
        } catch (const Error& e) {
            std::string msg = e.what();
            EXPECT_NE(msg.find("build log"), std::string::npos) << msg;
            EXPECT_NE(msg.find("broken.cl:3"), std::string::npos) << msg;
            EXPECT_NE(msg.find("undeclared_name"), std::string::npos) << msg;
        }
    }
}

// NVIDIA's compiler ignores #line and counts lines of the whole source: the
// log names them by kernel file and line instead. On PoCL, whose logs name
// files already, this is the only check of the mapping.
TEST(ProgramBuild, UnnamedLogLinesAreMappedToKernelFiles)
{
    TempDir dir("unnamed");
    dir.write("inc.h", "#define X 1\n");
    dir.write("main.cl", "#include \"inc.h\"\n\n__kernel void k(__global int* x)\n{\n    x[0] = y;\n}\n");
    std::string source = expandKernelSources(dir.path.string(), {"main.cl"});
    // Physical lines: #line 1 "main.cl", #line 1 "inc.h", #define, #line 2 "main.cl", "", __kernel, {, x[0] = y;
    std::string log = "<kernel>:8:12: error: use of undeclared identifier 'y'\n<kernel>:3:9: note: here\n"
                      "<kernel>:99:1: beyond the source\nmain.cl:5:12: already named\n";
    EXPECT_EQ(attributeBuildLog(log, source), "main.cl:5:12: error: use of undeclared identifier 'y'\n"
                                              "inc.h:1:9: note: here\n<kernel>:99:1: beyond the source\n"
                                              "main.cl:5:12: already named\n");
}

// wavevcm's cache, on every device: on PoCL wavevcm uses it only when
// POCL_KERNEL_CACHE=0, which buildProgram reads at each build (PoCL itself
// may have read it earlier, at start-up; its own caching does not matter here).
TEST(ProgramBuild, SecondBuildComesFromTheCache)
{
    TempDir dir("cache");
    ::setenv("WAVEVCM_CACHE_DIR", dir.path.c_str(), 1);
    ::setenv("POCL_KERNEL_CACHE", "0", 1);
    // A source unique to this run, so nothing older can be in any cache.
    std::string source = "__kernel void k(__global int* x) { x[get_global_id(0)] = " +
                         std::to_string(::getpid()) + "; }\n";
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        SCOPED_TRACE(info.name);
        DeviceContext device(info);
        ProgramBuild first = buildProgram(device.context, info, source, "");
        ProgramBuild second = buildProgram(device.context, info, source, "");
        EXPECT_FALSE(first.fromCache);
        if (!fs::exists(first.cacheFile)) {
            // Allowed: a driver that cannot export binaries; then there is no cache.
            EXPECT_FALSE(second.fromCache);
            continue;
        }
        EXPECT_TRUE(second.fromCache);
        // Different options are a different program.
        EXPECT_FALSE(buildProgram(device.context, info, source, "-DOTHER").fromCache);
        // The cached program runs.
        cl::Buffer out(device.context, CL_MEM_WRITE_ONLY, 64 * sizeof(int));
        cl::Kernel k(second.program, "k");
        k.setArg(0, out);
        device.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(64), cl::NDRange(64));
        std::vector<int> result(64);
        device.queue.enqueueReadBuffer(out, CL_TRUE, 0, 64 * sizeof(int), result.data());
        EXPECT_EQ(result[63], ::getpid());
        // A corrupt cache file is ignored, not fatal.
        std::ofstream(first.cacheFile, std::ios::trunc) << "garbage";
        ProgramBuild third = buildProgram(device.context, info, source, "");
        EXPECT_FALSE(third.fromCache);
    }
    ::unsetenv("POCL_KERNEL_CACHE");
    ::unsetenv("WAVEVCM_CACHE_DIR");
}

// One context builds a source with given options once (buildProgramOnce):
// the renderers the tests make one after another, one per seed, share the
// build instead of each paying PoCL's preprocessing of the whole source.
TEST(ProgramBuild, OneContextBuildsASourceOnce)
{
    std::string source = "__kernel void k(__global int* x) { x[get_global_id(0)] = 7; }\n";
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        SCOPED_TRACE(info.name);
        DeviceContext device(info), other(info);
        ProgramBuild first = buildProgramOnce(device, source, "");
        ProgramBuild second = buildProgramOnce(device, source, "");
        EXPECT_EQ(first.program(), second.program());
        EXPECT_TRUE(second.fromCache);
        EXPECT_NE(buildProgramOnce(device, source, "-DOTHER").program(), first.program());
        EXPECT_NE(buildProgramOnce(other, source, "").program(), first.program());
    }
    // Renderers in one context.
    DeviceContext device(test::devicesUnderTest()[0]);
    Scene scene = loadGltf(std::string(WAVEVCM_SOURCE_DIR) + "/scenes/cornell-box.gltf");
    Bvh bvh = buildBvh(scene.vertices, trianglePacketWidth(device.info));
    RenderSettings s;
    s.algorithm = Algorithm::VertexConnectionMerging;
    s.width = s.height = 16;
    Renderer a(device, scene, bvh, s);
    s.seed = 2;
    Renderer b(device, scene, bvh, s);
    EXPECT_EQ(a.programBuild().program(), b.programBuild().program());
}

// PoCL with its own cache on is left to it: wavevcm writes no binary there
// (exporting one compiles every kernel again), and says so.
TEST(ProgramBuild, PoclIsLeftToItsOwnCache)
{
    TempDir dir("driver-cache");
    ::setenv("WAVEVCM_CACHE_DIR", dir.path.c_str(), 1);
    ::unsetenv("POCL_KERNEL_CACHE");
    std::string source = "__kernel void k(__global int* x) { x[get_global_id(0)] = " +
                         std::to_string(::getpid()) + " + 1; }\n";
    int pocl = 0;
    for (const DeviceInfo& info : test::devicesUnderTest()) {
        if (!info.isPocl()) continue;
        ++pocl;
        DeviceContext device(info);
        ProgramBuild build = buildProgram(device.context, info, source, "");
        EXPECT_EQ(build.cache, ProgramBuild::Cache::Driver);
        EXPECT_TRUE(build.cacheFile.empty());
        EXPECT_FALSE(build.fromCache);
    }
    EXPECT_TRUE(fs::is_empty(dir.path));
    ::unsetenv("WAVEVCM_CACHE_DIR");
    if (pocl == 0) GTEST_SKIP() << "no PoCL device";
}

} // namespace
} // namespace wv
