#!/bin/bash
# wavevcm against SmallVCM (the VCM paper's scalar CPU reference) on its own
# Cornell boxes, for the same wall time on the same cores
# (scripts/compare_smallvcm.py does the work; its --help lists the options,
# which this passes on). SmallVCM's source comes from SMALLVCM_SRC (a
# checkout) or is cloned from GitHub into build/smallvcm-src. It is built
# twice, as released (base seed 1234) and with another base seed for the
# references; nothing else in it is changed. Needs build/wavevcm and g++.
# Example: scripts/compare_smallvcm.sh --scenes area --seconds 30
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/wavevcm ] || { echo "compare_smallvcm: build/wavevcm is missing; build first (README)" >&2; exit 1; }
src="${SMALLVCM_SRC:-build/smallvcm-src}"
if [ ! -f "$src/src/smallvcm.cxx" ]; then
  if [ -n "${SMALLVCM_SRC:-}" ]; then
    echo "compare_smallvcm: SMALLVCM_SRC=$src has no src/smallvcm.cxx" >&2; exit 1
  fi
  echo "compare_smallvcm: cloning SmallVCM into $src" >&2
  git clone -q https://github.com/SmallVCM/SmallVCM "$src" ||
    { echo "compare_smallvcm: cannot clone SmallVCM; set SMALLVCM_SRC to a checkout" >&2; exit 1; }
fi
config="$src/src/config.hxx"
grep -q 'mBaseSeed *= *1234;' "$config" ||
  { echo "compare_smallvcm: $config does not set mBaseSeed = 1234 where expected; cannot reseed" >&2; exit 1; }
out=build/smallvcm-bin
mkdir -p "$out"
# Binaries built from another source tree are built again.
if [ "$(cat "$out/source" 2>/dev/null)" != "$(realpath "$src")" ]; then
  rm -f "$out"/smallvcm-*
  realpath "$src" > "$out/source"
fi
for seed in 1234 1000000; do
  if [ ! -x "$out/smallvcm-$seed" ]; then
    echo "compare_smallvcm: building SmallVCM (base seed $seed)" >&2
    rm -rf "$out/src-$seed" && cp -r "$src/src" "$out/src-$seed"
    sed -i "s/mBaseSeed *= *1234;/mBaseSeed = $seed;/" "$out/src-$seed/config.hxx"
    g++ -O3 -march=native -fopenmp -std=c++11 "$out/src-$seed/smallvcm.cxx" -o "$out/smallvcm-$seed"
  fi
done
exec /usr/bin/python3 scripts/compare_smallvcm.py --smallvcm "$out/smallvcm-1234" \
  --smallvcm-reseeded "$out/smallvcm-1000000" "$@"
