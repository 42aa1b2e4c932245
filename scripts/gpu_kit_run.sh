#!/usr/bin/env bash
# Runs on a GPU machine from a copy of this tree with gpu-kit/ beside it
# (scripts/gpu_kit.sh builds it here; the device tool carries it there):
#   run(command="bash scripts/gpu_kit_run.sh", carry=["gpu-kit"], timeout_s=540)
# In order, each step cut short when the time budget (KIT_BUDGET seconds,
# default 450) runs out, so that one call answers as much as it can:
#   0. the OpenCL driver: NVIDIA's ICD library found (else it stops there),
#      `wavevcm devices`;
#   1. speed: every algorithm on the Cornell box and the caustics scene at
#      512 x 512 for KIT_SECONDS (default 5) with --profile and --stats, and
#      pt and vcm at 1024 x 1024 (a wavefront of 1M paths), bpt and vcm
#      with vertex connections traced inline (the GPU default queues them),
#      pt and vcm with packets of eight triangles (WAVEVCM_TRIANGLE_PACKET_WIDTH=8;
#      a GPU's tree has packets of four), pt with 1, 4 and 8 samples per iteration, vcm with 1 and 4, pt and vcm as 2 and 4 pipelines sharing
#      the GPU, and pt and vcm with NVIDIA's compiler held to 64 registers
#      (WAVEVCM_CL_OPTIONS=-cl-nv-maxrregcount=64);
#   1a. (not by default) --rounds-ahead 0 to 8 for pt and vcm;
#   1b. registers: NVIDIA's own ptxas report per kernel (-cl-nv-verbose);
#   2. ray casting: wavevcm_bench's extend/connect benchmarks on the Cornell
#      box and the 130K- and 1M-triangle scenes (made by scripts/make_scenes.py),
#      and its per-kernel benchmarks;
#   3. images: every algorithm, 16 iterations at 128 x 128, as .pfm, for
#      scripts/gpu_kit_compare.sh to compare with PoCL's here;
#   4. correctness on the GPU: the GoogleTest suites that need no image files.
# KIT_STEPS picks and orders them (default "speed registers rays images tests";
# a session that has the figures can run "tests images" first; "ahead" sweeps
# --rounds-ahead). KIT_TESTS replaces the tests' --gtest_filter.
# Writes under $OUT (else /tmp/gpu-kit-out): log.txt, bench-*.json,
# gtest.xml, results.tar.gz (the images and --stats files).
# KIT_DEVICE (default NVIDIA) selects the device; KIT_ICD names the OpenCL
# driver library to load instead of searching for NVIDIA's (checks here:
# KIT_ICD=/usr/lib/x86_64-linux-gnu/libpocl.so.2 KIT_DEVICE=pthread).
set -uo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
kit=$root/gpu-kit
out=${OUT:-/tmp/gpu-kit-out}
mkdir -p "$out"
# Everything below runs in main, its output through tee into log.txt.
main() {
deadline=$((SECONDS + ${KIT_BUDGET:-450}))
seconds=${KIT_SECONDS:-5}
device=${KIT_DEVICE:-NVIDIA}
steps=${KIT_STEPS:-speed registers rays images tests}
for s in $steps; do
  case $s in
    speed|ahead|registers|rays|images|tests) ;;
    *) echo "gpu_kit_run: unknown step '$s' in KIT_STEPS (speed ahead registers rays images tests)"; exit 1 ;;
  esac
done
left() { echo $((deadline - SECONDS)); }
# Runs "$@" with what is left of the budget (at least $1 seconds needed).
step() {
  local need=$1; shift
  if [ "$(left)" -lt "$need" ]; then echo "gpu_kit_run: skipped (budget): $*"; return 1; fi
  timeout --kill-after=5 "$(left)" "$@"
  local rc=$?
  [ $rc -eq 124 ] && echo "gpu_kit_run: timed out: $*"
  return $rc
}

[ -x "$kit/bin/wavevcm" ] || { echo "gpu_kit_run: no $kit/bin/wavevcm: run scripts/gpu_kit.sh and carry gpu-kit"; exit 1; }
echo "gpu_kit_run: kit of $(tr '\n' ' ' < "$kit/commit"); $(uname -m), $(nproc) cores; budget $(left) s"
export LD_LIBRARY_PATH="$kit/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
# Debian 12's C++ runtime, only where the machine's own is older than the
# binaries need (a newer one here stays: the driver may need it).
if ldd "$kit/bin/wavevcm" 2>&1 | grep -q 'version .* not found'; then
  echo "gpu_kit_run: this machine's C++ runtime is older than the kit's: using the kit's (lib-compat)"
  export LD_LIBRARY_PATH="$LD_LIBRARY_PATH:$kit/lib-compat"
fi
export WAVEVCM_CACHE_DIR=/tmp/wavevcm-cache
# The binaries look for kernels, scenes and test data under the path they were
# built in: point it at this copy.
src=$(cat "$kit/source-dir")
if [ "$src" != "$root" ] && [ ! -e "$src" ]; then mkdir -p "$(dirname "$src")" && ln -s "$root" "$src"; fi
[ -d "$src/kernels" ] || { echo "gpu_kit_run: cannot reach the sources at $src"; exit 1; }

# 0. The driver. Debian's ocl-icd (the kit's libOpenCL) knows no
# OCL_ICD_FILENAMES: it loads the libraries that the .icd files in
# OCL_ICD_VENDORS name. That folder is made here with one driver in it, so a
# CPU driver the machine registers is left out (it would slow the tests down).
export OCL_ICD_VENDORS=$(mktemp -d)
# Does the driver library $1 give a device matching $device?
try_driver() {
  echo "$1" > "$OCL_ICD_VENDORS/kit.icd"
  timeout --kill-after=5 60 "$kit/bin/wavevcm" devices > /tmp/gpu-kit-devices.txt 2>&1 &&
    grep -qi "$device" /tmp/gpu-kit-devices.txt
}
if [ -n "${KIT_ICD:-}" ]; then
  try_driver "$KIT_ICD" || { cat /tmp/gpu-kit-devices.txt; echo "gpu_kit_run: no device matches '$device' with $KIT_ICD"; exit 2; }
else
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
  # Every copy of NVIDIA's OpenCL driver library: the first that gives a
  # device wins (an unversioned link may lead nowhere or to a stub).
  found=
  for icd in $(find /usr/local/nvidia /usr/lib /usr/lib64 /usr/local/lib /lib /lib64 \
                 -name 'libnvidia-opencl.so*' 2>/dev/null | sort -u); do
    if try_driver "$icd"; then found=$icd; break; fi
    echo "gpu_kit_run: $icd gives no '$device' device: $(ls -l "$icd" | cut -c1-200)"
    head -3 /tmp/gpu-kit-devices.txt
    python3 -c "import ctypes, sys; ctypes.CDLL(sys.argv[1])" "$icd" 2>&1 | tail -1
  done
  if [ -z "$found" ]; then
    echo "gpu_kit_run: no working libnvidia-opencl.so here. What there is:"
    for f in /etc/OpenCL/vendors/*.icd; do [ -f "$f" ] && echo "$f: $(cat "$f")"; done
    ls -l /dev/nvidia* 2>/dev/null
    find / -xdev \( -name 'libnvidia-opencl*' -o -name 'libcuda.so*' \) -print 2>/dev/null | head -20
    exit 2
  fi
  echo "gpu_kit_run: OpenCL driver $found"
fi
cat /tmp/gpu-kit-devices.txt
# The tests run on the kit's device alone.
export WAVEVCM_TEST_DEVICES=$device

work=/tmp/gpu-kit-work
rm -rf "$work"
mkdir -p "$work/stats" "$work/images"
scenes="cornell-box caustics"
algorithms="pt vcm bpt ppm bpm lt" # the issues' main figures first, in case the budget runs out

# 1. Speed (the first run of each program builds it; the setup line says how long).
speed() {
echo "== 1. speed: ${seconds} s each at 512 x 512 on '$device'"
for alg in $algorithms; do
  for scene in $scenes; do
    step $((seconds + 20)) "$kit/bin/wavevcm" render "scenes/$scene.gltf" -a "$alg" -d "$device" -t "$seconds" \
      --profile --stats "$work/stats/$scene-$alg.json" -o "$work/speed.pfm"
  done
done
# Packets of eight triangles, which a GPU tests half by half, against the
# four its tree gets by default (trianglePacketWidth; docs/performance.md,
# "A tree per packet width").
for alg in pt vcm; do
  WAVEVCM_TRIANGLE_PACKET_WIDTH=8 step $((seconds + 20)) "$kit/bin/wavevcm" render scenes/cornell-box.gltf -a "$alg" \
    -d "$device" -t "$seconds" --profile --stats "$work/stats/cornell-box-packets8-$alg.json" -o "$work/speed.pfm"
done
# A larger image: does a wavefront of 1M paths (1024 x 1024) keep the GPU
# busier than 262K (512 x 512)? Samples/s in --stats says.
for alg in pt vcm; do
  step $((seconds + 20)) "$kit/bin/wavevcm" render scenes/cornell-box.gltf -a "$alg" -d "$device" -t "$seconds" \
    --width 1024 --height 1024 --stats "$work/stats/cornell-box-1024-$alg.json" -o "$work/speed.pfm"
done
# Vertex connections traced by each camera path's work-item, against the
# connection queue the runs above used (--profile on both, as above).
for alg in bpt vcm; do
  for scene in $scenes; do
    step $((seconds + 20)) "$kit/bin/wavevcm" render "scenes/$scene.gltf" -a "$alg" -d "$device" -t "$seconds" \
      --vertex-connections inline --profile --stats "$work/stats/$scene-inline-$alg.json" -o "$work/speed.pfm"
  done
done
# More samples per iteration: K times the paths per launch at 512 x 512
# (vcm: K light paths per pixel too), against one, both without --profile's
# events (samples/s in --stats).
for run in pt:1 pt:4 pt:8 vcm:1 vcm:4; do
  alg=${run%:*} k=${run#*:}
  step $((seconds + 20)) "$kit/bin/wavevcm" render scenes/cornell-box.gltf -a "$alg" -d "$device" -t "$seconds" \
    --samples-per-iteration "$k" --stats "$work/stats/cornell-box-spi$k-$alg.json" -o "$work/speed.pfm"
done
# Several pipelines on the one GPU (independent renderers, each with its own
# queue and host thread; the whole device shared): does one pipeline's host
# wait between rounds leave the GPU to the other's kernels?
for alg in pt vcm; do
  for n in 2 4; do
    step $((seconds + 30)) "$kit/bin/wavevcm" render scenes/cornell-box.gltf -a "$alg" -d "$device" -t "$seconds" \
      --pipelines "$n" --stats "$work/stats/cornell-box-pipelines$n-$alg.json" -o "$work/speed.pfm"
  done
done
# Registers cap occupancy (ptxas gives extend 128 on sm_90 through clang):
# the same with NVIDIA's compiler told to stay within 64.
for alg in pt vcm; do
  WAVEVCM_CL_OPTIONS=-cl-nv-maxrregcount=64 step $((seconds + 20)) "$kit/bin/wavevcm" render scenes/cornell-box.gltf \
    -a "$alg" -d "$device" -t "$seconds" --profile --stats "$work/stats/cornell-box-maxrreg64-$alg.json" -o "$work/speed.pfm"
done
# What came so far goes back even if the call is cut short later.
tar -C "$work" -czf "$out/results.tar.gz" stats images
}

# 1a. How many rounds to keep enqueued: --rounds-ahead 0 (wait for every
# round's counters) to 8, without --profile's events (not in the default steps).
ahead() {
echo "== 1a. rounds ahead: ${seconds} s each at 512 x 512 on '$device'"
for alg in pt vcm; do
  for n in 0 1 2 4 8; do
    step $((seconds + 20)) "$kit/bin/wavevcm" render scenes/cornell-box.gltf -a "$alg" -d "$device" -t "$seconds" \
      --rounds-ahead "$n" --stats "$work/stats/cornell-box-ahead$n-noprofile-$alg.json" -o "$work/speed.pfm"
  done
done
tar -C "$work" -czf "$out/results.tar.gz" stats images
}

# 1b. What NVIDIA's own compiler makes of each program: registers, stack and
# spills per kernel (-cl-nv-verbose puts ptxas's report in the build log).
registers() {
echo "== 1b. registers (NVIDIA's compiler, -cl-nv-verbose)"
for alg in pt lt bpt ppm bpm vcm; do
  CUDA_CACHE_DISABLE=1 WAVEVCM_CL_OPTIONS=-cl-nv-verbose WAVEVCM_BUILD_LOG=1 WAVEVCM_CACHE_DIR=off step 20 "$kit/bin/wavevcm" render \
    scenes/caustics.gltf -a "$alg" -d "$device" -n 1 --width 64 --height 64 -q -o "$work/registers.pfm" 2>&1 |
    grep -E "Compiling entry|Used [0-9]+ registers|spill" | sed "s/^/$alg: /"
done
}

# 2. Ray casting and kernels.
rays() {
echo "== 2. wavevcm_bench"
python3 scripts/make_scenes.py cornell-box-130k -d "$work/bench-scenes" >/dev/null &&
  step 60 python3 scripts/make_scenes.py displaced-1m -d "$work/bench-scenes" >/dev/null
for scene in scenes/cornell-box.gltf "$work/bench-scenes/cornell-box-130k.gltf" "$work/bench-scenes/displaced-1m.gltf"; do
  [ -f "$scene" ] || continue
  WAVEVCM_BENCH_SCENE=$scene WAVEVCM_BENCH_DEVICE=$device step 40 "$kit/bin/wavevcm_bench" \
    --benchmark_filter='BM_(Extend|Connect)(Coherent|Incoherent)/262144/' --benchmark_min_time=0.2 \
    --benchmark_out="$out/bench-rays-$(basename "$scene" .gltf).json" --benchmark_out_format=json
done
WAVEVCM_BENCH_DEVICE=$device step 60 "$kit/bin/wavevcm_bench" --benchmark_filter='BM_Kernel_.*/65536' \
  --benchmark_min_time=0.1 --benchmark_out="$out/bench-kernels.json" --benchmark_out_format=json
}

# 3. Images for the comparison with PoCL (scripts/gpu_kit_compare.sh).
images() {
echo "== 3. images: 16 iterations at 128 x 128"
for scene in $scenes; do
  for alg in $algorithms; do
    step 15 "$kit/bin/wavevcm" render "scenes/$scene.gltf" -a "$alg" -d "$device" -n 16 --width 128 --height 128 -q \
      -o "$work/images/$scene-$alg.pfm"
  done
done
tar -C "$work" -czf "$out/results.tar.gz" stats images
}

# 4. Correctness on the GPU: the suites that read or write no image files.
# Not brief: if the budget cuts the run short there is no gtest.xml, and the
# log's OK/FAILED lines say what ran (gpu_kit_compare.sh reads either).
tests() {
echo "== 4. tests"
suites='Bvh.*:HashGrid.*:Sampler.*:KernelInterface.*:KernelSources.*:ProgramBuild.*:EyeLight.*:PathTracer.*'
suites+=':Bidirectional.*:VertexMerging.*:Mis.*:BsdfMaterials.*:Bsdf.*:MultiDevice.*:DoubleSidedEmitter.*:HardCases.*'
suites+=':Lights.*:Environment.*:Rounds.*:SamplesPerIteration.*'
suites+='-PathTracer.EveryBundledSceneRendersFinite' # textured-room's environment map is an image
step 60 "$kit/bin/wavevcm_tests" --gtest_filter="${KIT_TESTS:-$suites}" --gtest_output="xml:$out/gtest.xml"
}

for s in $steps; do $s; done
echo "gpu_kit_run: done, $(left) s of the budget left"
}
main 2>&1 | tee "$out/log.txt"
exit "${PIPESTATUS[0]}"
