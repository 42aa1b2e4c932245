#!/usr/bin/env bash
# Before/after on one machine in one run: builds commit BEFORE (default HEAD)
# in a worktree beside this tree (../wavevcm-<commit>, kept for the next run),
# then renders the same scenes with both builds (BEFORE's binary and this
# tree's build/) and prints, per scene and algorithm,
#   - iterations per second in SECONDS of wall time each, and after/before;
#     with REPEATS=n > 1 the two builds run alternately n times each and the
#     table gives each build's median and the range of the n paired ratios
#     (the machine's speed drifts by ±10 % between single runs);
#   - relMSE between the two builds' images at the same seed and iteration
#     count (SPP), which says whether the change kept the image: ~1e-12 is
#     float rounding, a changed sampling shows as noise-level relMSE (at 4
#     iterations up to thousands where fireflies fall on different pixels);
#   - the ratio of the two images' means, ~1 when either holds.
# Where a change alters the sampling, compare_error.sh measures what matters:
# the error at equal iterations over many seeds.
# Usage: scripts/compare_commits.sh [BEFORE] ; settings from the environment:
#   SCENES="scenes/cornell-box.gltf scenes/caustics.gltf"  ALGORITHMS="pt lt bpt ppm bpm vcm"
#   SECONDS_EACH=10  SPP=4  WIDTH=512  HEIGHT=512  DEVICE=pthread  MAX_PATH_LENGTH=10  REPEATS=1
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=${SCENES:-scenes/cornell-box.gltf scenes/caustics.gltf}
algorithms=${ALGORITHMS:-pt lt bpt ppm bpm vcm}
seconds=${SECONDS_EACH:-10}
spp=${SPP:-4}
width=${WIDTH:-512}
height=${HEIGHT:-512}
device=${DEVICE:-pthread}
maxlen=${MAX_PATH_LENGTH:-10}
repeats=${REPEATS:-1}

old=$(scripts/build_commit.sh "${1:-HEAD}")
new=$(scripts/build_commit.sh)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Reads iterations / render_seconds from a --stats file.
rate() { python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print(s["iterations"]/s["render_seconds"])' "$1"; }

if [ "$repeats" -gt 1 ]; then
  printf '| scene | algorithm | before it/s (median of %s) | after it/s (median) | after/before (medians) | paired ratios, min-max | relMSE after vs before (%s it, same seed) | mean after/before |\n' "$repeats" "$spp"
  printf '| --- | --- | --- | --- | --- | --- | --- | --- |\n'
else
  printf '| scene | algorithm | before it/s | after it/s | after/before | relMSE after vs before (%s it, same seed) | mean after/before |\n' "$spp"
  printf '| --- | --- | --- | --- | --- | --- | --- |\n'
fi
for scene in $scenes; do
  for a in $algorithms; do
    common=(render "$scene" -a "$a" --width "$width" --height "$height" -d "$device" --max-path-length "$maxlen" -q)
    # Warm both program caches first, so neither timing includes a kernel build:
    # 4 iterations, so that they run on the pipelines a timed run uses (fewer run on one).
    "$old" "${common[@]}" -n 4 -o "$work/warm.exr"
    "$new" "${common[@]}" -n 4 -o "$work/warm.exr"
    before=() after=()
    for ((i = 0; i < repeats; ++i)); do
      "$old" "${common[@]}" -t "$seconds" -o "$work/old-t.exr" --stats "$work/old.json"
      "$new" "${common[@]}" -t "$seconds" -o "$work/new-t.exr" --stats "$work/new.json"
      before+=("$(rate "$work/old.json")")
      after+=("$(rate "$work/new.json")")
    done
    "$old" "${common[@]}" -n "$spp" --seed 7 -o "$work/old.exr"
    "$new" "${common[@]}" -n "$spp" --seed 7 -o "$work/new.exr"
    difference=$("$new" compare "$work/new.exr" "$work/old.exr")
    relmse=$(sed -n 's/^relmse \([^ ]*\).*/\1/p' <<< "$difference")
    mean_ratio=$(sed -n 's/^mean_ratio \([^ ]*\).*/\1/p' <<< "$difference")
    python3 - "$(basename "$scene" .gltf)" "$a" "$relmse" "$mean_ratio" "${before[*]}" "${after[*]}" <<'PY'
import statistics, sys
scene, algorithm, relmse, mean_ratio = sys.argv[1:5]
before = [float(x) for x in sys.argv[5].split()]
after = [float(x) for x in sys.argv[6].split()]
b, a = statistics.median(before), statistics.median(after)
mean_ratio = f"{float(mean_ratio):.4f}"
if len(before) == 1:
    print(f"| {scene} | {algorithm} | {b:.3g} | {a:.3g} | {a / b:.2f} | {relmse} | {mean_ratio} |")
else:
    ratios = [y / x for x, y in zip(before, after)]
    print(f"| {scene} | {algorithm} | {b:.3g} | {a:.3g} | {a / b:.2f} | {min(ratios):.2f}-{max(ratios):.2f} | {relmse} | {mean_ratio} |")
PY
  done
done
