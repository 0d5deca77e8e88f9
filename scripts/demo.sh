#!/usr/bin/env bash
# The main job on the bundled default: installs dependencies, builds,
# precomputes the Spatial Adjacency Map of the bundled ear-like shell
# (meshes/ear.obj) in skin, validates it, previews it on the CPU, and
# renders scenes/ear_backlit.json headless on the GPU runtime (Mesa's
# llvmpipe when there is no GPU) to out/demo/ear_render.png.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/deps.sh"
"$root/scripts/build.sh" "$root/build"
out="$root/out/demo"
mkdir -p "$out"
bin="$root/build/bin"
"$bin/sam_build" "$root/meshes/ear.obj" -o "$out/ear.sam" --material skin --mm-per-unit 60 --force
"$bin/sam_info" "$out/ear.sam"
"$bin/sam_profile_image" skin -o "$out/profile_skin.png"
"$bin/sam_preview" "$out/ear.sam" -o "$out/ear_translucency.png"
"$bin/sam_render" "$root/scenes/ear_backlit.json" -o "$out/ear_render.exr" --png "$out/ear_render.png" --frames 4
echo "demo: wrote $out/ear_render.png (and ear_render.exr, ear_translucency.png, profile_skin.png)"
