/* A development aid for scripts/vectorizer_report.py, loaded with LD_PRELOAD
 * into a wavevcm process that runs on PoCL; never part of the renderer.
 *
 * PoCL compiles kernels with the LLVM library it is linked with, in the
 * renderer's process, and offers no way to pass options to LLVM's passes.
 * This library wraps the OpenCL loader's clBuildProgram and, before the
 * first build,
 *   - parses POCL_LLVM_OPTIONS (space-separated, e.g. "-slp-threshold=100000
 *     -force-vector-width=8") as LLVM command-line options in that library
 *     (LLVMParseCommandLineOptions), so experiments can switch an LLVM pass
 *     or a cost model off;
 *   - appends KERNEL_BUILD_OPTIONS (e.g. "-g -DNO_PREFETCH") to every build's
 *     options; with -g the vectorizer's remarks carry the kernel's file and
 *     line.
 * Build: cc -O2 -shared -fPIC -o pocl_llvm_options.so pocl_llvm_options.c -ldl */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef int cl_int;
typedef unsigned cl_uint;
typedef void* cl_program;
typedef void* cl_device_id;
typedef void (*BuildCallback)(cl_program, void*);
typedef cl_int (*BuildProgram)(cl_program, cl_uint, const cl_device_id*, const char*, BuildCallback, void*);

static void parse_llvm_options(void)
{
    static int done = 0;
    const char* options = getenv("POCL_LLVM_OPTIONS");
    if (done || !options || !*options)
        return;
    done = 1;
    /* PoCL loaded LLVM already; find that copy rather than load another. */
    const char* libraries[] = {"libLLVM-15.so.1", "libLLVM-15.so", "libLLVM.so", NULL};
    void* llvm = NULL;
    for (int i = 0; !llvm && libraries[i]; ++i)
        llvm = dlopen(libraries[i], RTLD_NOW | RTLD_NOLOAD);
    void (*parse)(int, const char* const*, const char*) =
        llvm ? (void (*)(int, const char* const*, const char*))dlsym(llvm, "LLVMParseCommandLineOptions") : NULL;
    if (!parse) {
        fprintf(stderr, "pocl_llvm_options: no LLVM library loaded in this process; POCL_LLVM_OPTIONS ignored\n");
        return;
    }
    char* copy = strdup(options);
    const char* argv[64];
    int argc = 0;
    argv[argc++] = "pocl";
    for (char* word = strtok(copy, " "); word && argc < 63; word = strtok(NULL, " "))
        argv[argc++] = word;
    parse(argc, argv, NULL); /* the strings must outlive the options: copy is never freed */
}

cl_int clBuildProgram(cl_program program, cl_uint deviceCount, const cl_device_id* devices, const char* options,
                      BuildCallback callback, void* userData)
{
    parse_llvm_options();
    BuildProgram next = (BuildProgram)dlsym(RTLD_NEXT, "clBuildProgram");
    const char* extra = getenv("KERNEL_BUILD_OPTIONS");
    if (!extra || !*extra)
        return next(program, deviceCount, devices, options, callback, userData);
    size_t length = (options ? strlen(options) : 0) + strlen(extra) + 2;
    char* all = malloc(length);
    snprintf(all, length, "%s %s", options ? options : "", extra);
    cl_int result = next(program, deviceCount, devices, all, callback, userData);
    free(all);
    return result;
}
