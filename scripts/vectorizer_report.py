#!/usr/bin/env python3
"""Which render kernels PoCL vectorizes across work-items, and why not.

PoCL turns a work-group into a loop over its work-items and leaves SIMD to
LLVM's loop vectorizer; with POCL_VECTORIZER_REMARKS=1 it prints the
vectorizer's remarks while it compiles each kernel's work-group function (at
the kernel's first launch). This renders one small iteration with empty
caches, splits the remarks by kernel (each work-group function's remarks
follow the remark that inlines the kernel into it) and prints, per kernel,
the loops vectorized and the reasons the others were not.

  scripts/vectorizer_report.py [-a vcm] [--scene S] [--require K1,K2]

--require: exit 1 unless each named kernel has a vectorized loop (for a check
that fails when a kernel stops vectorizing). Standard library only.
"""
import argparse
import collections
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
    args = p.parse_args()

    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, POCL_VECTORIZER_REMARKS="1", POCL_CACHE_DIR=cache, WAVEVCM_CACHE_DIR="off")
        run = subprocess.run([args.wavevcm, "render", args.scene, "-a", args.algorithm, "-n", "1", "--width", "32",
                              "--height", "32", "-d", "pthread", "-q", "-o", os.path.join(out, "x.exr")],
                             env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if run.returncode != 0:
        sys.exit("render failed:\n" + run.stdout[-4000:])

    vectorized = collections.Counter()
    reasons = collections.defaultdict(collections.Counter)
    kernel = None
    marker = re.compile(r"'_pocl_kernel_(\w+)' inlined into '_pocl_kernel_\1_workgroup'")
    for remark in run.stdout.split("<unknown>:0:0: "):
        m = marker.search(remark)
        if m:
            kernel = m.group(1)
            continue
        if kernel is None:
            continue
        if remark.startswith("vectorized loop"):
            vectorized[kernel] += 1
        elif remark.startswith("loop not vectorized: "):
            reasons[kernel][remark[len("loop not vectorized: "):].strip()] += 1

    kernels = sorted(set(vectorized) | set(reasons))
    print("| kernel | loops vectorized | not vectorized, by reason |")
    print("| --- | --- | --- |")
    for k in kernels:
        why = "; ".join(f"{n}× {r}" for r, n in reasons[k].most_common())
        print(f"| {k} | {vectorized[k]} | {why} |")
    missing = [k for k in filter(None, args.require.split(",")) if vectorized[k] == 0]
    if missing:
        sys.exit("not vectorized: " + ", ".join(missing))


if __name__ == "__main__":
    main()
