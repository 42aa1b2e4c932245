#!/usr/bin/env bash
# Builds the GPU kit: wavevcm, wavevcm_bench and wavevcm_tests without
# OpenImageIO, Embree and MPI (-DWAVEVCM_IMAGE_IO=OFF: .pfm output only), in
# build-gpu-kit/, and gathers them with the shared libraries they need beyond
# the C and C++ runtimes into gpu-kit/ (git-ignored, a few MB), so that a
# machine with a GPU but none of Debian's packages (the device tool's H200)
# can run them from a copy of this tree: scripts/gpu_kit_run.sh there.
#   scripts/gpu_kit.sh        then, with the device tool:
#   run(command="bash scripts/gpu_kit_run.sh", carry=["gpu-kit"], timeout_s=540)
#   scripts/gpu_kit_compare.sh FILES_AT   (here: the GPU's images against PoCL's)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=build-gpu-kit
kit=gpu-kit
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DWAVEVCM_IMAGE_IO=OFF -DWAVEVCM_EMBREE=OFF -DWAVEVCM_MPI=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target wavevcm wavevcm_bench wavevcm_tests >/dev/null
rm -rf "$kit"
mkdir -p "$kit/bin" "$kit/lib"
cp "$build/wavevcm" "$build/wavevcm_bench" "$build/tests/wavevcm_tests" "$kit/bin/"
# The libraries beyond glibc and the C++ runtime (newer ones on the target
# run these binaries): the ICD loader, tinygltf, stb, Draco, Google Benchmark.
for b in "$kit"/bin/*; do
  ldd "$b" | awk '$2 == "=>" && $3 ~ /^\// {print $3}'
done | sort -u | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so.*|libm.so.*|libstdc++.so.*|libgcc_s.so.*|libpthread.so.*|libdl.so.*|librt.so.*|ld-linux*) ;;
    *) cp -L "$lib" "$kit/lib/" ;;
  esac
done
# Debian 12's C++ runtime, for a machine whose own is older (gpu_kit_run.sh
# uses it only then: a newer one there may be what the driver needs).
mkdir -p "$kit/lib-compat"
for lib in libstdc++.so.6 libgcc_s.so.1; do
  cp -L "$(ldd "$kit/bin/wavevcm" | awk -v l="$lib" '$1 == l {print $3}')" "$kit/lib-compat/"
done
# The binaries find kernels, scenes and test data under the source path
# compiled into them; gpu_kit_run.sh links it to the tree's copy there.
echo "$root" > "$kit/source-dir"
git rev-parse --short=10 HEAD > "$kit/commit"
git status --porcelain --untracked-files=no | grep -q . && echo "(with uncommitted changes)" >> "$kit/commit"
missing=$(LD_LIBRARY_PATH="$kit/lib" ldd "$kit"/bin/* | grep 'not found' || true)
[ -z "$missing" ] || { echo "gpu_kit: unresolved libraries: $missing" >&2; exit 1; }
echo "gpu_kit: $kit/ ($(du -sh "$kit" | cut -f1)): $(ls "$kit/bin" | tr '\n' ' ')+ $(ls "$kit/lib" | wc -l) libraries, $(cat "$kit/commit" | tr '\n' ' ')"
