// Every render program compiles for an NVIDIA GPU, without one: OpenCL C
// through clang with libclc to PTX (-target nvptx64--nvidiacl), assembled by
// the CUDA toolkit's ptxas for sm_90. PoCL and rusticl inline every helper,
// so a helper that clang declines to inline and that has no out-of-line
// definition (`inline` without `static`, C99 rules) is only found here, as
// ptxas's "unresolved extern function". Each program is built with every
// scene feature on, so every code path is compiled. Runs where clang-15,
// libclc-15 and ptxas are installed; skipped, saying why, elsewhere. Writes
// registers, stack and spills per kernel to gpu-resources.md in the working
// directory (the README's table).
#include "TestDevices.h"
#include "cl/Program.h"
#include "render/Renderer.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace wv {
namespace {

std::string findTool(const std::vector<std::string>& candidates)
{
    for (const std::string& c : candidates) {
        if (c.find('/') != std::string::npos) {
            if (fs::exists(c)) return c;
            continue;
        }
        const char* path = std::getenv("PATH");
        std::istringstream dirs(path ? path : "");
        std::string dir;
        while (std::getline(dirs, dir, ':'))
            if (!dir.empty() && fs::exists(fs::path(dir) / c)) return (fs::path(dir) / c).string();
    }
    return "";
}

// Runs `command`, returns its exit status and what it printed (stdout and stderr).
int run(const std::string& command, std::string& output)
{
    output.clear();
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return -1;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
    int status = pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct KernelResources {
    int registers = 0, stack = 0, spillStores = 0, spillLoads = 0;
};

// ptxas -v: "Compiling entry function 'k' for 'sm_90'", then "N bytes stack
// frame, N bytes spill stores, N bytes spill loads" and "Used N registers".
std::map<std::string, KernelResources> parsePtxasInfo(const std::string& log)
{
    std::map<std::string, KernelResources> out;
    static const std::regex entry(R"(Compiling entry function '([^']+)')");
    static const std::regex frame(R"((\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads)");
    static const std::regex regs(R"(Used (\d+) registers)");
    std::istringstream in(log);
    std::string line, current;
    while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_search(line, m, entry)) current = m[1];
        else if (!current.empty() && std::regex_search(line, m, frame)) {
            out[current].stack = std::stoi(m[1]);
            out[current].spillStores = std::stoi(m[2]);
            out[current].spillLoads = std::stoi(m[3]);
        } else if (!current.empty() && std::regex_search(line, m, regs)) {
            out[current].registers = std::stoi(m[1]);
            current.clear();
        }
    }
    return out;
}

TEST(GpuCompile, EveryProgramAssemblesForSm90)
{
    std::string clang = findTool({"clang-15", "/usr/lib/llvm-15/bin/clang"});
    std::string ptxas = findTool({"ptxas", "/usr/local/cuda/bin/ptxas"});
    const std::string libclc = "/usr/lib/clc/nvptx64--nvidiacl.bc";
    if (clang.empty() || ptxas.empty() || !fs::exists(libclc))
        GTEST_SKIP() << "needs clang-15, libclc-15 (" << libclc << ") and the CUDA toolkit's ptxas; found clang '"
                     << clang << "', ptxas '" << ptxas << "'";

    SceneFeatures all = test::everyFeature();

    fs::path dir = fs::temp_directory_path() / ("wavevcm-ptx-" + std::to_string(getpid()));
    fs::create_directories(dir);
    std::ostringstream table;
    table << "| program | kernel | registers | stack bytes | spill stores | spill loads |\n"
          << "| --- | --- | --- | --- | --- | --- |\n";
    // bpt and vcm with vertex connections queued, as on GPUs; vcm also inline
    // (--vertex-connections inline), the program as "vcm-inline".
    struct Program {
        Algorithm algorithm;
        bool queue;
    };
    for (Program program : {Program{Algorithm::EyeLight, false}, Program{Algorithm::PathTracing, false},
                            Program{Algorithm::LightTracing, false}, Program{Algorithm::Bidirectional, true},
                            Program{Algorithm::ProgressivePhotonMapping, false},
                            Program{Algorithm::BidirectionalPhotonMapping, false},
                            Program{Algorithm::VertexConnectionMerging, true},
                            Program{Algorithm::VertexConnectionMerging, false}}) {
        Algorithm a = program.algorithm;
        bool queue = program.queue;
        std::string name = algorithmName(a);
        if (a == Algorithm::VertexConnectionMerging && !queue) name += "-inline";
        fs::path cl = dir / (name + ".cl"), ptx = dir / (name + ".ptx"), cubin = dir / (name + ".cubin");
        std::ofstream(cl) << expandKernelSources(findKernelDir(), Renderer::kernelFiles(a));
        // The device compilers define __OPENCL_VERSION__; clang alone does not for nvptx.
        // The longest light selection (31 steps), as for a table of 2^30 lights;
        // packets of four triangles, the width a GPU's tree gets (trianglePacketWidth).
        std::string options = Renderer::programOptions(a, all, 1 << 30, queue) +
                              " -DTRIANGLE_PACKET_WIDTH=4 -D__OPENCL_VERSION__=120";
        std::string output;
        int status = run(clang + " -x cl -target nvptx64--nvidiacl -O3 " + options +
                             " -Xclang -mlink-bitcode-file -Xclang " + libclc + " -include clc/clc.h -S " +
                             cl.string() + " -o " + ptx.string(),
                         output);
        ASSERT_EQ(status, 0) << name << ": clang to PTX failed:\n" << output;
        status = run(ptxas + " -arch=sm_90 -v " + ptx.string() + " -o " + cubin.string(), output);
        ASSERT_EQ(status, 0) << name << ": ptxas failed:\n" << output;
        std::map<std::string, KernelResources> kernels = parsePtxasInfo(output);
        EXPECT_FALSE(kernels.empty()) << name << ": no kernel in ptxas's report:\n" << output;
        for (const auto& [kernel, r] : kernels)
            table << "| " << name << " | " << kernel << " | " << r.registers << " | " << r.stack << " | "
                  << r.spillStores << " | " << r.spillLoads << " |\n";
    }
    fs::remove_all(dir);
    std::ofstream("gpu-resources.md") << table.str();
    std::printf("%s", table.str().c_str());
}

} // namespace
} // namespace wv
