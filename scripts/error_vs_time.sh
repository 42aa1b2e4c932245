#!/usr/bin/env bash
# Regenerates the README's error-against-time results: for every bundled
# scene, a 120 s vcm reference and 20 s of each algorithm at 128 pixels high
# (scripts/convergence.py: CSV logs and the log-log figure in
# docs/results/SCENE/), then the Markdown table docs/results/table.md.
# About 4 minutes per scene on 2 cores. Extra arguments go to convergence.py
# (e.g. --device rusticl). Delete docs/results/SCENE/reference.exr to make a
# new reference.
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=(cornell-box cornell-box-point cornell-box-directional cornell-box-background caustics)
for s in "${scenes[@]}"; do
  /usr/bin/python3 scripts/convergence.py "scenes/$s.gltf" --seconds 20 --reference-seconds 120 --height 128 \
    --out "docs/results/$s" "$@"
done
/usr/bin/python3 scripts/convergence_table.py "${scenes[@]/#/docs/results/}" > docs/results/table.md
cat docs/results/table.md
