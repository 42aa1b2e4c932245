#!/usr/bin/env bash
# Error at equal iterations, before and after a change of sampling: builds
# commit BEFORE (default HEAD) beside this tree (build_commit.sh), renders
# each scene and algorithm with both builds at the same SEEDS seeds and SPP
# iterations, measures each image against a reference and prints, per scene
# and algorithm, the two builds' mean relMSE and tone-mapped MSE (wavevcm
# compare) and the after/before change of each, averaged over the seeds with
# its standard error. At the same seed both builds draw the same numbers
# wherever the change did not touch the sampling, so the paired change is far
# less noisy than either mean. The reference is this tree's REF_ALGORITHM at
# REF_SPP iterations (another seed), rendered once and kept in
# ../wavevcm-references/ under a hash of the scene file and the settings. Where a change keeps the
# image to float rounding, compare_commits.sh says so in one render.
# Usage: scripts/compare_error.sh [BEFORE] ; settings from the environment:
#   SCENES="scenes/cornell-box.gltf scenes/caustics.gltf"  ALGORITHMS="pt lt bpt ppm bpm vcm"
#   SEEDS=16  SPP=32  HEIGHT=256  REF_ALGORITHM=vcm  REF_SPP=1024  DEVICE=pthread  EXTRA="" (more render options)
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=${SCENES:-scenes/cornell-box.gltf scenes/caustics.gltf}
algorithms=${ALGORITHMS:-pt lt bpt ppm bpm vcm}
seeds=${SEEDS:-16}
spp=${SPP:-32}
height=${HEIGHT:-256}
ref_algorithm=${REF_ALGORITHM:-vcm}
ref_spp=${REF_SPP:-1024}
device=${DEVICE:-pthread}
read -r -a extra <<< "${EXTRA:-}"

old=$(scripts/build_commit.sh "${1:-HEAD}")
new=$(scripts/build_commit.sh)
references="$(pwd)/../wavevcm-references"
mkdir -p "$references"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# "relmse tonemapped_mse" of image $2 against $1, by binary $3.
errors() { "$3" compare "$2" "$1" | awk '/^relmse/{r=$2} /^tonemapped_mse/{t=$2} END{print r, t}'; }

printf '| scene | algorithm | relMSE before | after | change | tone-mapped MSE before | after | change |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- |\n'
for scene in $scenes; do
  # Named by the scene file's contents and every setting that shapes the reference.
  hash=$( (cat "$scene"; echo "$height $ref_algorithm $ref_spp $device ${EXTRA:-}") | sha256sum | cut -c1-16)
  reference="$references/$(basename "$scene" .gltf)-$hash.exr"
  if [ ! -f "$reference" ]; then
    echo "compare_error: rendering the reference $reference" >&2
    "$new" render "$scene" -a "$ref_algorithm" --height "$height" -d "$device" -n "$ref_spp" --seed 1000003 -q \
      "${extra[@]}" -o "$work/reference.exr"
    mv "$work/reference.exr" "$reference"
  fi
  for a in $algorithms; do
    rows="$work/rows"
    : > "$rows"
    for ((s = 1; s <= seeds; ++s)); do
      common=(render "$scene" -a "$a" --height "$height" -d "$device" -n "$spp" --seed "$s" -q "${extra[@]}")
      "$old" "${common[@]}" -o "$work/old.exr"
      "$new" "${common[@]}" -o "$work/new.exr"
      echo "$(errors "$reference" "$work/old.exr" "$new") $(errors "$reference" "$work/new.exr" "$new")" >> "$rows"
    done
    python3 - "$(basename "$scene" .gltf)" "$a" "$rows" <<'PY'
import math, sys
scene, algorithm, path = sys.argv[1:4]
rows = [[float(x) for x in line.split()] for line in open(path) if line.strip()]
def summary(before, after):
    mb, ma = sum(before) / len(before), sum(after) / len(after)
    # The change per seed, relative to the mean before, with its standard error.
    d = [(a - b) / mb for a, b in zip(after, before)]
    md = sum(d) / len(d)
    se = math.sqrt(sum((x - md) ** 2 for x in d) / (len(d) - 1) / len(d)) if len(d) > 1 else float("nan")
    return f"{mb:.4g} | {ma:.4g} | {100 * md:+.1f} % ± {100 * se:.1f} %"
rel = summary([r[0] for r in rows], [r[2] for r in rows])
tm = summary([r[1] for r in rows], [r[3] for r in rows])
print(f"| {scene} | {algorithm} | {rel} | {tm} |")
PY
  done
done
