#!/usr/bin/env bash
# Installs whatever of wavevcm's Debian packages is missing, then configures
# and builds wavevcm in build/ (Release). Safe to run again: it installs
# nothing when everything is present and rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake g++ make
  ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers   # OpenCL ICD loader, C and C++ headers
  pocl-opencl-icd                                          # PoCL: OpenCL on the CPU (the default device here)
  mesa-opencl-icd                                          # rusticl: the second implementation the tests compare with
  libopenimageio-dev openimageio-tools                    # the tools: Debian's OpenImageIO CMake config requires them
  libtinygltf-dev nlohmann-json3-dev libcli11-dev
  libdraco-dev                                             # Draco-compressed glTF meshes
  libopenmpi-dev openmpi-bin                               # optional: render with mpirun across machines
  libgtest-dev libbenchmark-dev
  clang libclang-rt-dev                                    # the glTF loader's fuzz target (libFuzzer)
  libembree-dev                                            # optional: the ray benchmarks compare with Embree
  clang-15 libclc-15                                       # kernels to PTX for the GPU compile test (with CUDA's ptxas)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
