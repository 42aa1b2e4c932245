#!/bin/bash
# wavevcm `pt` against Mitsuba 3's path tracer on the same scene for the same
# wall time (scripts/compare_mitsuba.py does the work; its --help lists the
# options, which this passes on). Makes what it needs: Debian's libllvm19
# (Dr.Jit's LLVM backend fails on LLVM 15) and a Python environment with
# Mitsuba 3 from PyPI in build/mitsuba-venv. Needs build/wavevcm.
# Example: scripts/compare_mitsuba.sh --seconds 30 --reference-seconds 240
set -euo pipefail
cd "$(dirname "$0")/.."
llvm=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
if [ ! -e "$llvm" ]; then
  echo "compare_mitsuba: installing libllvm19" >&2
  apt-get install -y -q libllvm19 >/dev/null
fi
venv=build/mitsuba-venv
if [ ! -x "$venv/bin/python" ]; then
  echo "compare_mitsuba: making $venv (mitsuba, numpy)" >&2
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/pip" install -q "mitsuba==3.9.1" numpy
fi
[ -x build/wavevcm ] || { echo "compare_mitsuba: build/wavevcm is missing; build first (README)" >&2; exit 1; }
DRJIT_LIBLLVM_PATH="$llvm" exec "$venv/bin/python" scripts/compare_mitsuba.py "$@"
