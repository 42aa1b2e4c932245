#!/usr/bin/env bash
# Before/after on one machine in one run: builds commit BEFORE (default HEAD)
# in a worktree beside this tree (../wavevcm-<commit>, kept for the next run),
# then renders the same scenes with both builds (BEFORE's binary and this
# tree's build/) and prints, per scene and algorithm,
#   - iterations per second in SECONDS of wall time each, and after/before;
#   - relMSE between the two builds' images at the same seed and iteration
#     count (SPP), which says whether the change kept the image: ~1e-12 is
#     float rounding, a changed sampling shows as noise-level relMSE.
# Usage: scripts/compare_commits.sh [BEFORE] ; settings from the environment:
#   SCENES="scenes/cornell-box.gltf scenes/caustics.gltf"  ALGORITHMS="pt bpt vcm"
#   SECONDS_EACH=10  SPP=4  WIDTH=512  HEIGHT=512  DEVICE=pthread  MAX_PATH_LENGTH=10
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
before=${1:-HEAD}
sha=$(git rev-parse --short=10 "$before")
scenes=${SCENES:-scenes/cornell-box.gltf scenes/caustics.gltf}
algorithms=${ALGORITHMS:-pt lt bpt ppm bpm vcm}
seconds=${SECONDS_EACH:-10}
spp=${SPP:-4}
width=${WIDTH:-512}
height=${HEIGHT:-512}
device=${DEVICE:-pthread}
maxlen=${MAX_PATH_LENGTH:-10}

tree="$root/../wavevcm-$sha"
if [ ! -d "$tree" ]; then
  git worktree add --detach "$tree" "$sha" >&2
fi
echo "compare: building $sha in $tree" >&2
cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release -DWAVEVCM_EMBREE=OFF >/dev/null
cmake --build "$tree/build" --target wavevcm -j"$(nproc)" >/dev/null
echo "compare: building this tree" >&2
cmake --build build --target wavevcm -j"$(nproc)" >/dev/null
old="$tree/build/wavevcm"
new="$root/build/wavevcm"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Reads iterations / render_seconds from a --stats file.
rate() { python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print(s["iterations"]/s["render_seconds"])' "$1"; }

printf '| scene | algorithm | before it/s | after it/s | after/before | relMSE after vs before (%s it, same seed) |\n' "$spp"
printf '| --- | --- | --- | --- | --- | --- |\n'
for scene in $scenes; do
  for a in $algorithms; do
    common=(render "$scene" -a "$a" --width "$width" --height "$height" -d "$device" --max-path-length "$maxlen" -q)
    # Warm both program caches first, so neither timing includes a kernel build.
    "$old" "${common[@]}" -n 1 -o "$work/warm.exr"
    "$new" "${common[@]}" -n 1 -o "$work/warm.exr"
    "$old" "${common[@]}" -t "$seconds" -o "$work/old-t.exr" --stats "$work/old.json"
    "$new" "${common[@]}" -t "$seconds" -o "$work/new-t.exr" --stats "$work/new.json"
    "$old" "${common[@]}" -n "$spp" --seed 7 -o "$work/old.exr"
    "$new" "${common[@]}" -n "$spp" --seed 7 -o "$work/new.exr"
    r0=$(rate "$work/old.json")
    r1=$(rate "$work/new.json")
    relmse=$("$new" compare "$work/new.exr" "$work/old.exr" | sed -n 's/.*relmse \([^ ]*\).*/\1/p')
    printf '| %s | %s | %.3g | %.3g | %.2f | %s |\n' "$(basename "$scene" .gltf)" "$a" "$r0" "$r1" \
      "$(python3 -c "print($r1/$r0)")" "$relmse"
  done
done
