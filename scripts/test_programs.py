#!/usr/bin/env python3
"""Which kernel programs the test suite builds, and which tests alone need each.

Most of a cold test run is building programs (README, "Run the test suite"):
one per scene feature set x algorithm x device. A test that builds a program
no other test builds pays all of its cold build; a test whose programs others
build too pays little for them. This reads the log of a ctest run in which
wavevcm printed every build (WAVEVCM_BUILD_LOG=1; PoCL's builds print on
every run, rusticl's only when wavevcm's cache misses, so use empty caches):

  XDG_CACHE_HOME=$(mktemp -d) WAVEVCM_BUILD_LOG=1 ctest --test-dir build -j2
  scripts/test_programs.py build/Testing/Temporary/LastTest.log [--list]

and prints the distinct programs per device, then the tests by the programs
that they alone build (PoCL, rusticl) with their time in that run. --list
also prints those programs' options. Standard library only.
"""
import argparse
import collections
import re
import sys

BUILD = re.compile(r"wavevcm: build log on (.*?) with options '(.*?)'")
# Options every render program has, left out of the listing.
COMMON = re.compile(r"\s*-(cl-std=CL1\.2|DHOST_STRUCT_LAYOUT=\S+|DLLVM_OPTIONS_KEY=\S+)")


def device_kind(name):
    return "rusticl" if "llvmpipe" in name else "PoCL" if "pthread" in name or "basic" in name else name


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("log", help="ctest's LastTest.log of a run with WAVEVCM_BUILD_LOG=1")
    p.add_argument("--list", action="store_true", help="print the options of each test's own programs")
    args = p.parse_args()
    text = open(args.log, errors="replace").read()
    users = collections.defaultdict(set)  # (device kind, options) -> tests
    seconds = {}
    for section in re.split(r"\n\d+/\d+ Testing: ", text)[1:]:
        test = section.split("\n", 1)[0].strip()
        t = re.search(r"Test time =\s*([\d.]+) sec", section)
        seconds[test] = float(t.group(1)) if t else 0.0
        for device, options in BUILD.findall(section):
            users[(device_kind(device), options)].add(test)
    if not users:
        sys.exit(f"{args.log}: no 'wavevcm: build log on' lines; run ctest with WAVEVCM_BUILD_LOG=1")
    per_device = collections.Counter(kind for kind, _ in users)
    alone = collections.defaultdict(list)
    for key, tests in users.items():
        if len(tests) == 1:
            alone[next(iter(tests))].append(key)
    print("distinct programs: " + ", ".join(f"{n} on {k}" for k, n in sorted(per_device.items())) +
          f"; {sum(len(v) for v in alone.values())} built by one test alone")
    print(f"{'own programs':>12}  {'seconds':>7}  test")
    for test, keys in sorted(alone.items(), key=lambda kv: (-len(kv[1]), kv[0])):
        kinds = collections.Counter(kind for kind, _ in keys)
        split = ", ".join(f"{n} {k}" for k, n in sorted(kinds.items()))
        print(f"{len(keys):>12}  {seconds.get(test, 0):7.1f}  {test} ({split})")
        if args.list:
            for kind, options in sorted(keys):
                print(f"{'':>23}{kind}: {COMMON.sub('', options).strip()}")


if __name__ == "__main__":
    main()
