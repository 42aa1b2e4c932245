#!/usr/bin/env python3
"""Which render kernels PoCL vectorizes across work-items, and why not.

PoCL turns a work-group into a loop over its work-items and leaves SIMD to
LLVM's loop vectorizer; with POCL_VECTORIZER_REMARKS=1 it prints the
vectorizer's remarks while it compiles each kernel's work-group function (at
the kernel's first launch). This renders one small iteration with empty
caches, splits the remarks by kernel (each work-group function's remarks
follow the remark that inlines the kernel into it) and prints, per kernel,
the loops vectorized and the reasons the others were not. wavevcm sets the
LLVM options that let the shading kernels vectorize (host/cl/PoclVectorizer.h,
kernels/core/simd.h). It renders as renders run by default: on two
pipelines where the machine has two cores or more, each on a sub-device of
one compute unit, where the kernels that run one work-item at a time push to
their queues by an atomic per item and the SIMD ones through the group
(kernels/core/queues.h, pushes_per_item); --pipelines 1 for the whole device.

  scripts/vectorizer_report.py [-a vcm] [--scene S] [--require K1,K2] [--pipelines N]
      [--simd-shading] [--locations] [--build-options "-DNO_PREFETCH"]
      [--llvm-options "-slp-threshold=1000000 -force-vector-width=8"]

--require: exit 1 unless each named kernel has a vectorized loop (the ctests
scripts.vectorized_kernels_*); exit 77 (skipped) where wavevcm sets no LLVM
options (no AVX2 or AVX-512, or not PoCL's LLVM as a shared library).
--simd-shading: the shade kernels built for SIMD whatever the host chose for
this device and scene (-DSIMD_CAMERA_SHADING=1 -DSIMD_LIGHT_SHADING=1; the
host runs them so only with AVX-512, and there not shade_light, nor ppm's
shade_bidirectional, in a scene with a GGX lobe: Renderer::deviceOptions),
so that --require checks that their code still vectorizes on any machine
where the options are set.
--locations: builds the kernels with -g, so each reason names the kernel
source line it is about.
--build-options, --llvm-options: experiments. Extra kernel build options
(POCL_EXTRA_BUILD_FLAGS), and options for the LLVM inside PoCL in place of
wavevcm's own (WAVEVCM_LLVM_OPTIONS; "" for none).
Standard library only.
"""
import argparse
import collections
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("-a", "--algorithm", default="vcm")
    p.add_argument("--scene", default=os.path.join(ROOT, "scenes", "cornell-box.gltf"))
    p.add_argument("--wavevcm", default=os.path.join(ROOT, "build", "wavevcm"))
    p.add_argument("--require", default="", help="comma-separated kernels that must have a vectorized loop")
    p.add_argument("--pipelines", type=int, default=2 if (os.cpu_count() or 1) >= 2 else 1,
                   help="render pipelines (default: 2 on two cores or more, as renders run)")
    p.add_argument("--simd-shading", action="store_true",
                   help="shade kernels built for SIMD whatever the host chose for this device and scene")
    p.add_argument("--locations", action="store_true", help="kernel source line of each reason (builds with -g)")
    p.add_argument("--build-options", default="", help="extra kernel build options, e.g. -DNO_PREFETCH")
    p.add_argument("--llvm-options", default=None,
                   help="options for PoCL's LLVM instead of wavevcm's, e.g. -force-vector-width=8 ('' for none)")
    args = p.parse_args()
    build_options = (args.build_options + (" -g" if args.locations else "") +
                     (" -DSIMD_CAMERA_SHADING=1 -DSIMD_LIGHT_SHADING=1" if args.simd_shading else "")).strip()

    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, POCL_VECTORIZER_REMARKS="1", POCL_CACHE_DIR=cache, WAVEVCM_CACHE_DIR="off")
        if build_options:
            env["POCL_EXTRA_BUILD_FLAGS"] = build_options
        if args.llvm_options is not None:
            env["WAVEVCM_LLVM_OPTIONS"] = args.llvm_options
        stats = os.path.join(out, "stats.json")
        run = subprocess.run([args.wavevcm, "render", args.scene, "-a", args.algorithm, "-n", "1", "--width", "32",
                              "--height", "32", "-d", "pthread", "--pipelines", str(args.pipelines), "-q",
                              "-o", os.path.join(out, "x.exr"), "--stats", stats],
                             env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if run.returncode != 0:
            sys.exit("render failed:\n" + run.stdout[-4000:])
        with open(stats) as f:
            options = json.load(f)["kernel_build_options"]
    options_set = "-DLLVM_OPTIONS_KEY" in options
    print(f"kernel build options: {options.strip()}")
    if not options_set:
        print("no LLVM options set here: no work-item loop is forced into SIMD")
    else:
        print("shade kernels in SIMD:", "all (--simd-shading)" if args.simd_shading else
              ", ".join(k for k, m in (("camera paths'", "-DSIMD_CAMERA_SHADING"), ("shade_light", "-DSIMD_LIGHT_SHADING"))
                        if m in options) or "none")

    vectorized = collections.Counter()
    reasons = collections.defaultdict(collections.Counter)
    kernel = None
    marker = re.compile(r"'_pocl_kernel_(\w+)' inlined into '_pocl_kernel_\1_workgroup'")
    # PoCL prints the remarks one after another with no separator: split at
    # each remark's location, "<unknown>:0:0: " or, built with -g, a kernel
    # source file's "name.cl:line:column: ".
    sources = sorted({f for _, _, files in os.walk(os.path.join(ROOT, "kernels")) for f in files}, key=len,
                     reverse=True)
    location = re.compile("(<unknown>|" + "|".join(map(re.escape, sources)) + r"):(\d+):\d+: ")
    pieces = location.split(run.stdout)
    for file, line, remark in zip(pieces[1::3], pieces[2::3], pieces[3::3]):
        where = f" ({file}:{line})" if args.locations and file != "<unknown>" else ""
        m = marker.search(remark)
        if m:
            kernel = m.group(1)
            continue
        if kernel is None:
            continue
        if remark.startswith("vectorized loop"):
            vectorized[kernel] += 1
        elif remark.startswith("loop not vectorized: "):
            reasons[kernel][remark[len("loop not vectorized: "):].strip() + where] += 1
        elif remark.startswith("the cost-model indicates that vectorization is not beneficial"):
            reasons[kernel]["legal, but the cost model says not beneficial" + where] += 1

    kernels = sorted(set(vectorized) | set(reasons))
    print("| kernel | loops vectorized | not vectorized, by reason |")
    print("| --- | --- | --- |")
    for k in kernels:
        why = "; ".join(f"{n}× {r}" for r, n in reasons[k].most_common())
        print(f"| {k} | {vectorized[k]} | {why} |")
    required = list(filter(None, args.require.split(",")))
    if required and not options_set:
        sys.exit(77)
    missing = [k for k in required if vectorized[k] == 0]
    if missing:
        sys.exit("not vectorized: " + ", ".join(missing))


if __name__ == "__main__":
    main()
