#!/usr/bin/env bash
# Iterations per second of one process against an MPI job on this machine,
# for the README's tables ("Several machines"): 1 process on one pipeline (PoCL's threads on every
# core) and on --pipelines P (each on its share of the cores), against K ranks
# of one PoCL thread each (POCL_MAX_PTHREAD_COUNT=1) and K ranks that each use
# every core (oversubscribed); the ranks on one pipeline each. Figures, not a test.
#   scripts/mpi_scaling.sh  (settings from the environment: SCENE, ALGORITHMS="pt vcm",
#   SECONDS_EACH=20, RANKS=$(nproc), PIPELINES=2, WIDTH=512, HEIGHT=512)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${SCENE:-scenes/cornell-box.gltf}
seconds=${SECONDS_EACH:-20}
ranks=${RANKS:-$(nproc)}
pipelines=${PIPELINES:-2}
size=(--width "${WIDTH:-512}" --height "${HEIGHT:-512}")
mpirun=(mpirun --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpirun+=(--allow-run-as-root)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rate() { /usr/bin/python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); print("%.3g" % (s["iterations"] / s["render_seconds"]))' "$1"; }
echo "| algorithm | 1 process, 1 pipeline: it/s | 1 process, $pipelines pipelines: it/s (ratio) | $ranks ranks × 1 thread: it/s (ratio) | $ranks ranks × $(nproc) threads: it/s (ratio) |"
echo "| --- | --- | --- | --- | --- |"
for alg in ${ALGORITHMS:-pt vcm}; do
  build/wavevcm render "$scene" -a "$alg" -n 2 "${size[@]}" -q -o "$work/warm.exr" # kernel cache, PoCL's first launches
  build/wavevcm render "$scene" -a "$alg" -t "$seconds" "${size[@]}" --pipelines 1 -q -o "$work/one.exr" \
    --stats "$work/one.json"
  build/wavevcm render "$scene" -a "$alg" -t "$seconds" "${size[@]}" --pipelines "$pipelines" -q \
    -o "$work/pipelines.exr" --stats "$work/pipelines.json"
  "${mpirun[@]}" -n "$ranks" -x POCL_MAX_PTHREAD_COUNT=1 build/wavevcm render "$scene" -a "$alg" -t "$seconds" \
    "${size[@]}" --pipelines 1 -q -o "$work/single.exr" --stats "$work/single.json"
  "${mpirun[@]}" -n "$ranks" build/wavevcm render "$scene" -a "$alg" -t "$seconds" "${size[@]}" --pipelines 1 -q \
    -o "$work/all.exr" --stats "$work/all.json"
  one=$(rate "$work/one.json") piped=$(rate "$work/pipelines.json")
  single=$(rate "$work/single.json") all=$(rate "$work/all.json")
  ratio() { /usr/bin/python3 -c "print('%.2f' % ($1 / $one))"; }
  echo "| \`$alg\` | $one | $piped ($(ratio "$piped")) | $single ($(ratio "$single")) | $all ($(ratio "$all")) |"
done
