#!/usr/bin/env python3
"""Instructions per ray of wavevcm's traversal and of Embree's, on the same rays.

Runs wavevcm_bench's ray benchmarks (65,536 rays) under valgrind's callgrind on
one PoCL thread and counts the instructions executed inside the `extend` (or
`connect`) kernel's work-group function and inside rtcIntersect1 (or
rtcOccluded1), each divided by the rays it traced. Deterministic where timings
on a shared 2-core machine stray by 10 % and more: on the AMD EPYC development
machine traversal is bound by instruction count (docs/performance.md,
"Ray casting"), so a change that lowers it can be judged before it is timed.

Usage: scripts/ray_instructions.py [--scene F] [--bench B ...] [--build DIR]
  B: ExtendIncoherent (default), ExtendCoherent, ConnectIncoherent, ConnectCoherent.
Needs valgrind (Debian: apt-get install valgrind) and a build with Embree for
the Embree column. WAVEVCM_KERNEL_DIR selects other kernels, as for wavevcm.
"""
import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile

RAYS = 65536


def group_size():
    """RENDER_GROUP_SIZE, the work-items per call of a work-group function."""
    header = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "kernels", "interface", "queue_ids.h")
    with open(header) as f:
        m = re.search(r"#define RENDER_GROUP_SIZE (\d+)", f.read())
    if not m:
        sys.exit(f"ray_instructions: no RENDER_GROUP_SIZE in {header}")
    return int(m.group(1))


def parse(path):
    """Instructions per object file (exclusive costs), and calls per called
    function, from a callgrind output file."""
    objects, functions = {}, {}
    costs = collections.Counter()
    calls = collections.Counter()
    obj = callee = None
    pending_call = False
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            m = re.match(r"(c?ob|c?fn)=\((\d+)\)(?: (.*))?$", line)
            if m:
                table = objects if m.group(1).endswith("ob") else functions
                if m.group(3):
                    table[m.group(2)] = m.group(3)
                if m.group(1) == "ob":
                    obj = objects[m.group(2)]
                elif m.group(1) == "cfn":
                    callee = functions[m.group(2)]
                continue
            if line.startswith("calls="):
                calls[callee] += int(line.split()[0][len("calls="):])
                pending_call = True
                continue
            if not line or not (line[0].isdigit() or line[0] in "+-*"):
                continue
            if pending_call:  # the inclusive cost of that call, counted where it was spent
                pending_call = False
                continue
            parts = line.split()
            if len(parts) >= 2 and obj is not None:
                costs[obj] += int(parts[-1])
    return costs, calls


def callgrind_env(tool, binary):
    """Exits with a message unless valgrind and the built `binary` are there;
    else the environment that runs PoCL on one thread (callgrind serializes
    threads, and one thread's work-group functions are what is counted)."""
    if not shutil.which("valgrind"):
        sys.exit(f"{tool}: needs valgrind (apt-get install valgrind)")
    if not os.access(binary, os.X_OK):
        sys.exit(f"{tool}: build {binary} first")
    return dict(os.environ, POCL_MAX_PTHREAD_COUNT="1")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", help="glTF scene (default: the benchmark's, the Cornell box)")
    ap.add_argument("--bench", nargs="+", default=["ExtendIncoherent"])
    ap.add_argument("--build", default="build")
    args = ap.parse_args()
    bench = os.path.join(args.build, "wavevcm_bench")
    env = callgrind_env("ray_instructions", bench)
    if args.scene:
        env["WAVEVCM_BENCH_SCENE"] = args.scene
    print("| benchmark | wavevcm instructions/ray | Embree instructions/ray | ratio |")
    print("| --- | --- | --- | --- |")
    for b in args.bench:
        kernel = "connect" if b.startswith("Connect") else "extend"
        embree = "rtcOccluded1" if kernel == "connect" else "rtcIntersect1"
        run = [bench, f"--benchmark_filter=BM_{b}/{RAYS}/", "--benchmark_min_time=0.001"]
        # Once outside valgrind, so that the program is in PoCL's cache.
        subprocess.run(run, env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with tempfile.TemporaryDirectory() as work:
            out = os.path.join(work, "callgrind.out")
            subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                            f"--toggle-collect=_pocl_kernel_{kernel}_workgroup*", f"--toggle-collect={embree}"] + run,
                           env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            costs, calls = parse(out)
        ours = sum(c for o, c in costs.items() if o.endswith(f"/{kernel}.so"))
        embreeIr = sum(c for o, c in costs.items() if "libembree" in o)
        groups = sum(c for f, c in calls.items() if f.startswith(f"_pocl_kernel_{kernel}_workgroup"))
        if not ours or not groups:
            sys.exit(f"ray_instructions: no call of the {kernel} kernel was recorded")
        perRay = ours / (groups * group_size())
        if calls[embree]:
            e = embreeIr / calls[embree]
            print(f"| {b} | {perRay:.0f} | {e:.0f} | {perRay / e:.2f} |")
        else:
            print(f"| {b} | {perRay:.0f} | (no Embree) | |")


if __name__ == "__main__":
    main()
