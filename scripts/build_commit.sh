#!/usr/bin/env bash
# Builds `wavevcm` of COMMIT in a worktree beside this tree
# (../wavevcm-<commit>, kept for the next run) and prints the binary's path;
# with no COMMIT, builds this tree's build/ and prints its binary.
# Used by compare_commits.sh and compare_error.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
if [ $# -eq 0 ]; then
  echo "build: building this tree" >&2
  cmake --build build --target wavevcm -j"$(nproc)" >/dev/null
  echo "$root/build/wavevcm"
  exit 0
fi
sha=$(git rev-parse --short=10 "$1")
tree="$root/../wavevcm-$sha"
if [ ! -d "$tree" ]; then
  git worktree add --detach "$tree" "$sha" >&2
fi
echo "build: building $sha in $tree" >&2
cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release -DWAVEVCM_EMBREE=OFF >/dev/null
cmake --build "$tree/build" --target wavevcm -j"$(nproc)" >/dev/null
echo "$tree/build/wavevcm"
