#!/usr/bin/env python3
"""Paired A/B of one build under settings that differ by environment.

Renders one scene and algorithm with each VARIANT in turn (NAME:ENV=VALUE ...,
e.g. a kernel copy through WAVEVCM_KERNEL_DIR, build options through
WAVEVCM_CL_OPTIONS, LLVM's through WAVEVCM_LLVM_OPTIONS), PAIRS rounds of all
variants back to back, each for SECONDS of wall time with --profile. Prints
every run's iterations per second and milliseconds per iteration of each
kernel (summed over the pipelines), then, for every variant after the first,
the median and range of its per-round ratios against the first. The machine's
speed drifts by 10-25 % over a minute on the 2-core development machine, far
more than most changes gain; neighbouring runs drift together, so the paired
ratio is what to read. Where the variants must give the same image, compare
the kept images (OUT/NAME.exr from the last round) with `wavevcm compare`.

Usage: scripts/compare_variants.py [--algorithm A] [--scene F] [--pairs N]
       [--seconds S] [--kernels REGEX] [--out DIR] [--build DIR]
       [--extra "render options"] NAME:ENV=VALUE... NAME:ENV=VALUE...
A variant without settings is 'NAME:'. Example (a kernel copy against the tree):
  scripts/compare_variants.py -a bpt 'tree:' 'copy:WAVEVCM_KERNEL_DIR=/tmp/kernels'
"""
import argparse
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import tempfile


def parse_variant(text):
    name, sep, settings = text.partition(":")
    if not sep or not re.fullmatch(r"[A-Za-z0-9_.-]+", name):
        sys.exit(f"compare_variants: '{text}' is not NAME:ENV=VALUE ...")
    env = {}
    for item in shlex.split(settings):
        key, eq, value = item.partition("=")
        if not eq:
            sys.exit(f"compare_variants: '{item}' in '{text}' is not ENV=VALUE")
        env[key] = value
    return name, env


def run(args, wavevcm, name, env, out, kernels):
    """One timed render: (iterations per second, {kernel: ms per iteration})."""
    stats = os.path.join(out, name + ".json")
    command = [wavevcm, "render", args.scene, "-a", args.algorithm, "-t", str(args.seconds), "--profile",
               "-o", os.path.join(out, name + ".exr"), "--stats", stats] + shlex.split(args.extra)
    result = subprocess.run(command, env=dict(os.environ, **env), capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"compare_variants: variant {name} failed:\n{result.stderr}")
    with open(stats) as f:
        s = json.load(f)
    iterations = s["iterations"]
    seconds = {}
    for line in (result.stdout + result.stderr).splitlines():
        m = re.match(r"wavevcm: kernel (\S+)\s+([0-9.]+) s", line)
        if m and kernels.search(m.group(1)):
            seconds[m.group(1)] = seconds.get(m.group(1), 0.0) + float(m.group(2))
    return iterations / s["render_seconds"], {k: 1000 * v / iterations for k, v in seconds.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-a", "--algorithm", default="vcm")
    ap.add_argument("--scene", default="scenes/cornell-box.gltf")
    ap.add_argument("--pairs", type=int, default=4, help="rounds of all variants")
    ap.add_argument("--seconds", type=float, default=6, help="wall time of each render")
    ap.add_argument("--kernels", default=".", help="regular expression: the kernels to list")
    ap.add_argument("--out", help="keep each variant's last image and stats here")
    ap.add_argument("--build", default="build")
    ap.add_argument("--extra", default="", help="more render options, for every variant")
    ap.add_argument("variants", nargs="+", metavar="NAME:ENV=VALUE...")
    args = ap.parse_args()
    if len(args.variants) < 2:
        sys.exit("compare_variants: give two variants or more")
    variants = [parse_variant(v) for v in args.variants]
    wavevcm = os.path.join(args.build, "wavevcm")
    if not os.access(wavevcm, os.X_OK):
        sys.exit(f"compare_variants: build {wavevcm} first")
    kernels = re.compile(args.kernels)
    with tempfile.TemporaryDirectory() as scratch:
        out = args.out or scratch
        os.makedirs(out, exist_ok=True)
        # Each variant's program built (and cached) outside the timing, on the
        # pipelines a timed render uses: under 4 iterations a render takes one.
        for name, env in variants:
            warm = subprocess.run([wavevcm, "render", args.scene, "-a", args.algorithm, "-n", "4", "-q", "-o",
                                   os.path.join(out, name + ".exr")] + shlex.split(args.extra),
                                  env=dict(os.environ, **env))
            if warm.returncode != 0:
                sys.exit(f"compare_variants: variant {name} failed (its error above)")
        rounds = []
        for p in range(args.pairs):
            results = {}
            for name, env in variants:
                rate, ms = run(args, wavevcm, name, env, out, kernels)
                results[name] = (rate, ms)
                print(f"round {p + 1} {name}: {rate:.3f} it/s  " +
                      " ".join(f"{k}={v:.0f}" for k, v in sorted(ms.items())) + " ms/it", flush=True)
            rounds.append(results)
    base = variants[0][0]
    print(f"\n{args.algorithm}, {args.scene}: paired ratios against '{base}' over {args.pairs} rounds "
          "(iterations per second; kernels: time per iteration, below 1 is faster)")
    for name, _ in variants[1:]:
        metrics = ["it/s"] + sorted(rounds[0][base][1])
        for metric in metrics:
            ratios = []
            for r in rounds:
                a = r[name][0] if metric == "it/s" else r[name][1].get(metric)
                b = r[base][0] if metric == "it/s" else r[base][1].get(metric)
                if a is not None and b:
                    ratios.append(a / b)
            if ratios:
                print(f"  {name} {metric:22s} median {statistics.median(ratios):.3f}  "
                      f"range {min(ratios):.2f}-{max(ratios):.2f}")


if __name__ == "__main__":
    main()
