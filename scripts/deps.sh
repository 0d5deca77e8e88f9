#!/usr/bin/env bash
# Installs the Debian 12 packages the project builds, tests and runs with.
# Idempotent: packages already present are left alone.
set -euo pipefail
packages=(
  build-essential cmake pkg-config git python3
  clang libclang-rt-14-dev libomp-14-dev       # fuzzers (libFuzzer), sanitizer runtimes
  libopenmesh-dev libembree-dev libopenexr-dev libcjson-dev libcmocka-dev
  libepoxy-dev libglfw3-dev libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri
  libpng-dev zlib1g-dev
  libstb-dev                                   # JPEG and TGA albedo maps (stb_image), sam_view's text
  libtinygltf-dev                              # glTF 2.0 meshes
  libmeshoptimizer-dev                         # glTF geometry gltfpack compressed (EXT_meshopt_compression)
  libdraco-dev draco                           # Draco-compressed glTF geometry; tests: draco_transcoder writes it
  gltfpack                                     # tests: a glTF written by a real exporter
  xvfb xauth                                   # window tests
  gnuplot-nox                                  # sam_compare's RMSE-against-N plot
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
