"""What the comparison scripts (compare_mitsuba.py, compare_smallvcm.py)
share: the error of an image against a reference, by `wavevcm compare`, and
the machine a run was on."""

import os
import subprocess


def relmse(wavevcm, test, reference):
    """relMSE of image `test` against `reference` (any format wavevcm reads)."""
    out = subprocess.run([wavevcm, "compare", test, reference], check=True, capture_output=True, text=True).stdout
    return float(out.split("relmse")[1].split()[0])


def machine():
    """CPU model, cores and widest x86 vector extension: ratios between
    renderers move with the machine (README), so runs say where."""
    model, flags = "unknown CPU", set()
    with open("/proc/cpuinfo") as f:
        for line in f:
            key, _, value = line.partition(":")
            if key.strip() == "model name":
                model = value.strip()
            elif key.strip() == "flags":
                flags = set(value.split())
    simd = next((f for f in ("avx512f", "avx2", "avx", "sse4_2") if f in flags), "sse2")
    return "%s, %d cores, %s" % (model, os.cpu_count(), simd)
