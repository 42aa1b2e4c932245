#!/usr/bin/env bash
# Here, after scripts/gpu_kit_run.sh ran on a GPU: its figures as Markdown
# tables, its images against this machine's PoCL renders of the same
# iterations (same seed, 16 iterations at 128 x 128, build/wavevcm), and the
# tests' outcome:
#   scripts/gpu_kit_compare.sh DIR   (DIR: the run's files: results.tar.gz, bench-*.json, gtest.xml, log.txt)
# Per scene and algorithm: relMSE of the GPU's image against PoCL's, and of
# PoCL's image with another seed against it (the noise of 16 iterations).
# The GPU draws the same samples as PoCL with other float rounding, so its
# relMSE must be far below the noise: the table flags a ratio over 0.05 (the
# threshold of MultiDevice.PoclAndRusticlTogetherGiveTheImageOfOne).
set -uo pipefail
shopt -s nullglob # a cut-short run may have left some of them out
cd "$(dirname "$0")/.."
dir=${1:?usage: scripts/gpu_kit_compare.sh DIR}
device=${DEVICE:-pthread}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ -f "$dir/results.tar.gz" ]; then
  tar -C "$work" -xzf "$dir/results.tar.gz"
else
  echo "(no results.tar.gz in $dir: no speed figures or images)"
fi
py=/usr/bin/python3

echo "### Speed on the GPU (512 x 512, render -t, from --stats)"
echo
echo "| scene | algorithm | iterations/s | samples/s | rays/s | kernel build s |"
echo "| --- | --- | --- | --- | --- | --- |"
for f in "$work"/stats/*.json; do
  name=$(basename "$f" .json)
  $py - "$f" "$name" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1])); scene, alg = sys.argv[2].rsplit("-", 1)
print("| %s | `%s` | %.3g | %.3g | %.3g | %.2f |" % (scene, alg, s["iterations"] / s["render_seconds"],
      s["samples_per_second"], s["rays_per_second"], s["kernel_build_seconds"]))
EOF
done

echo
echo "### Ray casting on the GPU (wavevcm_bench, 262,144 rays)"
echo
echo "| scene | benchmark | M rays/s |"
echo "| --- | --- | --- |"
for f in "$dir"/bench-rays-*.json; do
  [ -f "$f" ] || continue
  $py - "$f" <<'EOF'
import json, os, sys
b = json.load(open(sys.argv[1]))
scene = os.path.basename(sys.argv[1])[len("bench-rays-"):-len(".json")]
for r in b["benchmarks"]:
    print("| %s | %s | %.1f |" % (scene, r["name"], r.get("items_per_second", 0) / 1e6))
EOF
done

echo
echo "### GPU images against PoCL ($device), 16 iterations at 128 x 128"
echo
echo "| scene | algorithm | relMSE GPU vs PoCL | relMSE other seed vs PoCL | ratio |"
echo "| --- | --- | --- | --- | --- |"
relmse() { build/wavevcm compare "$1" "$2" | awk '$1 == "relmse" {print $2}'; }
for f in "$work"/images/*.pfm; do
  name=$(basename "$f" .pfm)
  scene=${name%-*} alg=${name##*-}
  args=(render "scenes/$scene.gltf" -a "$alg" -d "$device" -n 16 --width 128 --height 128 -q)
  build/wavevcm "${args[@]}" -o "$work/pocl.exr"
  build/wavevcm "${args[@]}" --seed 1 -o "$work/other.exr"
  gpu=$(relmse "$f" "$work/pocl.exr") noise=$(relmse "$work/other.exr" "$work/pocl.exr")
  if [ -z "$gpu" ] || [ -z "$noise" ]; then echo "| $scene | \`$alg\` | (not compared) | | |"; continue; fi
  $py -c "
g, n = $gpu, $noise
r = g / n if n > 0 else float('inf')
print('| $scene | \`$alg\` | %.3g | %.3g | %.3g%s |' % (g, n, r, '' if r < 0.05 else ' (over 0.05)'))"
done

echo
echo "### Tests on the GPU (gtest.xml)"
echo
if [ -f "$dir/gtest.xml" ]; then
  $py - "$dir/gtest.xml" <<'PYEOF'
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
cases = root.findall(".//testcase")
failed = [c for c in cases if c.find("failure") is not None]
skipped = [c for c in cases if c.get("result") == "skipped" or c.find("skipped") is not None]
print("%d tests: %d passed, %d failed, %d skipped" % (len(cases), len(cases) - len(failed) - len(skipped),
      len(failed), len(skipped)))
for c in failed:
    message = " ".join(c.find("failure").get("message", "").split())
    print("- FAILED %s.%s: %s" % (c.get("classname"), c.get("name"), message[:300]))
PYEOF
elif [ -f "$dir/log.txt" ] && grep -q '^\[ RUN      \]' "$dir/log.txt"; then
  # Cut short before gtest wrote its XML: the log says what ran.
  ok=$(grep -c '^\[       OK \]' "$dir/log.txt")
  skipped=$(grep -c '^\[  SKIPPED \]' "$dir/log.txt")
  echo "(no gtest.xml: the run was cut short) from log.txt: $ok passed, $skipped skipped, these failed:"
  grep '^\[  FAILED  \] [A-Za-z0-9_]*\.[A-Za-z0-9_/]* (' "$dir/log.txt" | sed 's/^/- /'
  # The test the budget cut short: a RUN line with no OK or FAILED after it.
  last=$(grep -E '^\[ (RUN      |      OK |  FAILED  )\]' "$dir/log.txt" | tail -1)
  case $last in "[ RUN      ]"*) echo "unfinished: ${last:13}" ;; esac
else
  echo "(no gtest.xml or test log: the tests did not run)"
fi
