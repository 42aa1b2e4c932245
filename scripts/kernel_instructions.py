#!/usr/bin/env python3
"""Instructions per item of every kernel of one render, counted by callgrind.

Renders SCENE with ALGORITHM (2 iterations, 128x128 by default) on one PoCL
thread and one pipeline under valgrind's callgrind, counting the instructions
executed inside each kernel's work-group function, and divides each kernel's
count by its items (`render --profile --stats`: the queue sizes it ran over).
Deterministic where timings on a shared 2-core machine stray by 10 % and
more; the render kernels run at 1.6-1.8 instructions per cycle on the AMD
EPYC development machine (merge, bound by its buckets' cache misses, at 0.7),
so for most of them a change that lowers the count can be judged before it
is timed. The program is built (and cached) outside valgrind first.

Usage: scripts/kernel_instructions.py [--algorithm A] [--scene F] [--size N]
       [--iterations N] [--build DIR]
Needs valgrind (Debian: apt-get install valgrind). WAVEVCM_KERNEL_DIR selects
other kernels, as for wavevcm: run it once per kernel copy to compare them.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

from ray_instructions import callgrind_env, parse


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--algorithm", default="vcm")
    ap.add_argument("--scene", default="scenes/cornell-box.gltf")
    ap.add_argument("--size", type=int, default=128, help="image width and height")
    ap.add_argument("--iterations", type=int, default=2)
    ap.add_argument("--build", default="build")
    args = ap.parse_args()
    wavevcm = os.path.join(args.build, "wavevcm")
    env = callgrind_env("kernel_instructions", wavevcm)
    with tempfile.TemporaryDirectory() as work:
        stats = os.path.join(work, "stats.json")
        run = [wavevcm, "render", args.scene, "-a", args.algorithm, "-n", str(args.iterations),
               "--width", str(args.size), "--height", str(args.size), "-d", "pthread", "--pipelines", "1",
               "--profile", "-q", "--stats", stats, "-o", os.path.join(work, "image.exr")]
        subprocess.run(run, env=env, check=True, stdout=subprocess.DEVNULL)
        out = os.path.join(work, "callgrind.out")
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        "--toggle-collect=_pocl_kernel_*_workgroup*"] + run,
                       env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        costs, _ = parse(out)
        with open(stats) as f:
            kernels = json.load(f)["devices"][0]["kernels"]
    perKernel = {}
    for obj, cost in costs.items():
        m = re.search(r"/([A-Za-z0-9_]+)\.so$", obj)
        if m and m.group(1) in kernels:
            perKernel[m.group(1)] = perKernel.get(m.group(1), 0) + cost
    if not perKernel:
        sys.exit("kernel_instructions: no kernel's instructions were recorded")
    total = sum(perKernel.values())
    print(f"{args.algorithm}, {os.path.basename(args.scene)}, {args.size}x{args.size}, "
          f"{args.iterations} iterations, one PoCL thread")
    print("| kernel | items | instructions per item | share of all |")
    print("| --- | --- | --- | --- |")
    for name, cost in sorted(perKernel.items(), key=lambda kv: -kv[1]):
        items = kernels[name]["items"]
        print(f"| {name} | {items} | {cost / max(items, 1):.0f} | {100 * cost / total:.1f} % |")


if __name__ == "__main__":
    main()
