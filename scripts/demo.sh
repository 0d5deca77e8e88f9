#!/usr/bin/env bash
# The main job on the bundled default: installs dependencies, builds,
# generates an ear-like thin shell, precomputes its Spatial Adjacency Map in
# skin with sam_build, validates the .sam with sam_info, and renders the
# back-lit translucency it encodes to out/demo/ear_translucency.png
# (CPU preview; the GPU renderer sam_render comes with the runtime).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/deps.sh"
"$root/scripts/build.sh" "$root/build"
out="$root/out/demo"
mkdir -p "$out"
bin="$root/build/bin"
"$bin/sam_meshgen" ear -o "$out/ear.obj" --resolution 64 --force
"$bin/sam_build" "$out/ear.obj" -o "$out/ear.sam" --material skin --mm-per-unit 60 --force
"$bin/sam_info" "$out/ear.sam"
"$bin/sam_profile_image" skin -o "$out/profile_skin.png"
"$bin/sam_preview" "$out/ear.sam" -o "$out/ear_translucency.png"
echo "demo: wrote $out/ear_translucency.png (and $out/profile_skin.png)"
