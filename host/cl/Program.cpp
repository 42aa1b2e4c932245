#include "Program.h"

#include "DeviceContext.h"

#include "../Error.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string_view>
#include <regex>
#include <set>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace wv {

// Bump when the cache format or anything outside the hashed inputs changes.
static const char* kCacheVersion = "wavevcm-program-cache-2";

std::string findKernelDir()
{
    std::error_code ec;
    // Set by hand to try other kernels: a wrong path is an error, never a
    // silent fall back to the installed kernels.
    if (const char* env = std::getenv("WAVEVCM_KERNEL_DIR")) {
        if (fs::exists(fs::path(env) / "interface" / "shared_types.h", ec)) return env;
        throw Error(std::string("WAVEVCM_KERNEL_DIR=") + env +
                    ": not a kernels/ directory (no interface/shared_types.h in it)");
    }
    std::vector<fs::path> candidates;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share" / "wavevcm" / "kernels");
    candidates.emplace_back(WAVEVCM_SOURCE_KERNEL_DIR);
    for (const fs::path& dir : candidates)
        if (fs::exists(dir / "interface" / "shared_types.h", ec)) return dir.string();
    std::string tried;
    for (const fs::path& dir : candidates) tried += "\n  " + dir.string();
    throw Error("cannot find the kernel sources (kernels/interface/shared_types.h); looked in:" + tried +
                "\nset WAVEVCM_KERNEL_DIR to the kernels/ directory");
}

static std::string readFile(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path.string() + ": cannot read");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Includes resolve against the including file's directory, then kernelDir.
static void expandInto(const fs::path& kernelDir, const fs::path& file, std::set<fs::path>& included,
                       std::string& out)
{
    static const std::regex includeLine(R"(^\s*#\s*include\s*"([^"]+)\"\s*$)");
    std::istringstream in(readFile(file));
    std::string name = file.filename().string();
    out += "#line 1 \"" + name + "\"\n";
    std::string line;
    int lineNumber = 0;
    while (std::getline(in, line)) {
        ++lineNumber;
        std::smatch m;
        if (!std::regex_match(line, m, includeLine)) {
            out += line + "\n";
            continue;
        }
        std::error_code ec;
        fs::path header = file.parent_path() / m[1].str();
        if (!fs::exists(header, ec)) header = kernelDir / m[1].str();
        if (!fs::exists(header, ec))
            throw Error(file.string() + ":" + std::to_string(lineNumber) + ": included file \"" + m[1].str() +
                        "\" not found");
        if (included.insert(fs::weakly_canonical(header)).second) expandInto(kernelDir, header, included, out);
        out += "#line " + std::to_string(lineNumber + 1) + " \"" + name + "\"\n";
    }
}

std::string expandKernelSources(const std::string& kernelDir, const std::vector<std::string>& files)
{
    std::set<fs::path> included;
    std::string out;
    for (const std::string& f : files) {
        fs::path path = fs::path(f).is_absolute() ? fs::path(f) : fs::path(kernelDir) / f;
        expandInto(kernelDir, path, included, out);
    }
    return out;
}

static fs::path cacheDir()
{
    if (const char* env = std::getenv("WAVEVCM_CACHE_DIR")) {
        if (std::string(env) == "off") return {};
        return env;
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "wavevcm";
    if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "wavevcm";
    return {};
}

static std::string buildLog(const cl::Program& program, const cl::Device& device)
{
    try {
        return program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device);
    } catch (const cl::Error&) {
        return "(no build log)";
    }
}

// Where each physical line of the expanded source came from, as "file:line"
// by the #line directives before it ("" before the first).
static std::vector<std::string> originalLocations(const std::string& source)
{
    static const std::regex lineDirective(R"re(^#line (\d+) "([^"]+)"$)re");
    std::vector<std::string> where;
    std::istringstream in(source);
    std::string text, file;
    int line = 0;
    while (std::getline(in, text)) {
        std::smatch m;
        if (std::regex_match(text, m, lineDirective)) {
            file = m[2].str();
            line = std::stoi(m[1].str()) - 1; // the next line is line m[1]
            where.push_back("");
        } else {
            ++line;
            where.push_back(file.empty() ? "" : file + ":" + std::to_string(line));
        }
    }
    return where;
}

std::string attributeBuildLog(const std::string& log, const std::string& source)
{
    static const std::regex unnamed(R"(<(kernel|source|stdin|input)>:(\d{1,9}))");
    std::vector<std::string> where;
    std::string out;
    auto last = log.cbegin();
    for (std::sregex_iterator it(log.begin(), log.end(), unnamed), end; it != end; ++it) {
        if (where.empty()) where = originalLocations(source);
        size_t line = std::stoul((*it)[2].str());
        out.append(last, log.cbegin() + it->position());
        out += line >= 1 && line <= where.size() && !where[line - 1].empty() ? where[line - 1] : it->str();
        last = log.cbegin() + it->position() + it->length();
    }
    out.append(last, log.cend());
    return out;
}

static double secondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A cache file is a header (magic, binary size, fingerprint of the binary)
// followed by the driver's binary. The header is checked before the driver
// sees the bytes: some drivers (rusticl 22.3) abort the process on a corrupt
// binary instead of returning CL_INVALID_BINARY.
struct CacheHeader {
    char magic[8];
    uint64_t size;
    uint64_t fingerprint;
};
static const char kCacheMagic[8] = {'W', 'V', 'C', 'M', 'B', 'I', 'N', '1'};

// The cache's names and integrity checks: the standard library's string hash
// (the same values for every run of one build, which is all a cache needs).
static uint64_t hash64(const char* data, size_t size) { return std::hash<std::string_view>{}({data, size}); }

// Loads a cached binary; any failure (missing, truncated, corrupt, rejected by
// the driver) means "not cached" and the caller builds from source.
static bool loadCached(const fs::path& file, const cl::Context& context, const DeviceInfo& device,
                       const std::string& options, cl::Program* program)
{
    std::error_code ec;
    if (!fs::exists(file, ec)) return false;
    std::string bytes = readFile(file);
    CacheHeader header;
    if (bytes.size() < sizeof header) return false;
    std::memcpy(&header, bytes.data(), sizeof header);
    const char* binary = bytes.data() + sizeof header;
    if (std::memcmp(header.magic, kCacheMagic, sizeof kCacheMagic) != 0 || header.size == 0 ||
        header.size != bytes.size() - sizeof header ||
        header.fingerprint != hash64(binary, header.size))
        return false;
    try {
        cl::Program::Binaries binaries{std::vector<unsigned char>(binary, binary + header.size)};
        std::vector<cl_int> status;
        cl::Program p(context, {device.device}, binaries, &status);
        p.build({device.device}, options.c_str());
        *program = p;
        return true;
    } catch (const cl::Error&) {
        return false;
    }
}

// Whether the binary was stored.
static bool storeCached(const fs::path& file, const cl::Program& program)
{
    std::vector<std::vector<unsigned char>> binaries;
    try {
        binaries = program.getInfo<CL_PROGRAM_BINARIES>();
    } catch (const cl::Error&) {
        return false; // the driver cannot export binaries: no cache, nothing wrong
    }
    if (binaries.empty() || binaries[0].empty()) return false;
    const std::vector<unsigned char>& binary = binaries[0];
    CacheHeader header;
    std::memcpy(header.magic, kCacheMagic, sizeof kCacheMagic);
    header.size = binary.size();
    header.fingerprint = hash64(reinterpret_cast<const char*>(binary.data()), binary.size());
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    // Write then rename, so a concurrent or interrupted run never sees half a file.
    fs::path tmp = file;
    tmp += ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary);
        out.write(reinterpret_cast<const char*>(&header), sizeof header);
        out.write(reinterpret_cast<const char*>(binary.data()), std::streamsize(binary.size()));
        if (!out) {
            out.close();
            fs::remove(tmp, ec);
            return false;
        }
    }
    fs::rename(tmp, file, ec);
    if (ec) fs::remove(tmp, ec);
    return !ec;
}

// PoCL keeps the program's bitcode and each kernel's work-group function in
// its own disk cache (POCL_CACHE_DIR), keyed by the source and options, so a
// second run loads them from there. Exporting a binary from PoCL
// (CL_PROGRAM_BINARIES) compiles a generic work-group function for every
// kernel of the program on top of the specialised ones its launches compile:
// with wavevcm's cache as well, a cold HardCases.EveryAlgorithmStaysFinite
// took 188 s on PoCL 3.1, without it 99 s. A warm program build takes 0.09 s
// from PoCL's cache, 0.04 s from wavevcm's (vcm on a Cornell box).
static bool driverCachesPrograms(const DeviceInfo& device)
{
    if (!device.isPocl()) return false;
    const char* env = std::getenv("POCL_KERNEL_CACHE");
    return !env || std::string(env) != "0";
}

const char* cacheName(ProgramBuild::Cache cache)
{
    switch (cache) {
    case ProgramBuild::Cache::Wavevcm: return "wavevcm";
    case ProgramBuild::Cache::Driver: return "driver";
    case ProgramBuild::Cache::None: break;
    }
    return "none";
}

// Driver-specific build options for experiments, appended to wavevcm's own
// (e.g. NVIDIA's -cl-nv-verbose, which puts each kernel's registers in the
// build log, or -cl-nv-maxrregcount=N); part of the cache key like the rest.
static std::string extraOptions()
{
    const char* env = std::getenv("WAVEVCM_CL_OPTIONS");
    return env && *env ? std::string(" ") + env : std::string();
}

ProgramBuild buildProgram(const cl::Context& context, const DeviceInfo& device, const std::string& source,
                          const std::string& wavevcmOptions)
{
    auto start = std::chrono::steady_clock::now();
    const std::string options = wavevcmOptions + extraOptions();
    ProgramBuild result;
    result.options = options;
    fs::path dir = cacheDir();
    if (driverCachesPrograms(device)) {
        result.cache = ProgramBuild::Cache::Driver;
    } else if (!dir.empty()) {
        std::string key = std::string(kCacheVersion) + '\n' + device.platformName + '\n' + device.name + '\n' +
                          device.version + '\n' + device.driverVersion + '\n' + options + '\n' + source;
        char name[32];
        std::snprintf(name, sizeof name, "%016llx.bin",
                      static_cast<unsigned long long>(hash64(key.data(), key.size())));
        result.cacheFile = (dir / name).string();
        if (loadCached(result.cacheFile, context, device, options, &result.program)) {
            result.cache = ProgramBuild::Cache::Wavevcm;
            result.fromCache = true;
            result.seconds = secondsSince(start);
            return result;
        }
    }

    cl::Program program(context, source);
    try {
        program.build({device.device}, options.c_str());
    } catch (const cl::Error& e) {
        throw Error("kernel build failed on " + device.name + " (" + device.platformName + ") with options '" +
                    options + "': " + clErrorName(e.err()) + "\n--- build log ---\n" +
                    attributeBuildLog(buildLog(program, device.device), source) + "\n--- end of build log ---");
    }
    result.log = attributeBuildLog(buildLog(program, device.device), source);
    if (const char* env = std::getenv("WAVEVCM_BUILD_LOG"); env && std::string(env) == "1")
        std::fprintf(stderr, "wavevcm: build log on %s with options '%s':\n%s\n", device.name.c_str(), options.c_str(),
                     result.log.c_str());
    if (!result.cacheFile.empty() && storeCached(result.cacheFile, program)) result.cache = ProgramBuild::Cache::Wavevcm;
    result.program = program;
    result.seconds = secondsSince(start);
    return result;
}

ProgramBuild buildProgramOnce(DeviceContext& device, const std::string& source, const std::string& options)
{
    auto start = std::chrono::steady_clock::now();
    const std::string key = options + '\n' + source;
    DeviceContext::BuiltPrograms& built = *device.builtPrograms;
    {
        std::lock_guard<std::mutex> lock(built.mutex);
        auto found = built.builds.find(key);
        if (found != built.builds.end()) {
            ProgramBuild again = found->second;
            again.fromCache = true;
            again.seconds = secondsSince(start);
            return again;
        }
    }
    ProgramBuild build = buildProgram(device.context, device.info, source, options);
    std::lock_guard<std::mutex> lock(built.mutex);
    built.builds.emplace(key, build);
    return build;
}

} // namespace wv
