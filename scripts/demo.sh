#!/usr/bin/env bash
# The main job on the bundled default: installs dependencies, builds, generates
# an ear-like shell, validates it with sam_info, and renders the skin
# material's diffusion profile to out/demo/profile_skin.png.
# (Until sam_build and sam_render exist this is the whole pipeline.)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/deps.sh"
"$root/scripts/build.sh" "$root/build"
out="$root/out/demo"
mkdir -p "$out"
bin="$root/build/bin"
"$bin/sam_meshgen" ear -o "$out/ear.obj" --resolution 48 --force
"$bin/sam_info" --mm-per-unit 60 "$out/ear.obj"
"$bin/sam_profile_image" skin -o "$out/profile_skin.png"
echo "demo: wrote $out/profile_skin.png"
