#!/usr/bin/env bash
# The main job on the bundled default: installs dependencies, builds,
# precomputes the Spatial Adjacency Map of the bundled ear-like shell
# (meshes/ear.obj) in skin, validates it, previews it on the CPU, renders
# scenes/ear_backlit.json headless on the GPU runtime (Mesa's llvmpipe when
# there is no GPU) to out/demo/ear_render.png, and ends with a real scan
# rendered from the bare mesh in one command: the Stanford bunny (from
# Debian's libcgal-demo, fetched by meshes/fetch_scans.sh) in skin, its ears
# glowing against a back light, beside the same view without translucency
# in out/demo/bunny.png.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/deps.sh"
"$root/scripts/build.sh" "$root/build"
out="$root/out/demo"
mkdir -p "$out"
bin="$root/build/bin"
"$bin/sam_build" "$root/meshes/ear.obj" -o "$out/ear.sam" --material skin --mm-per-unit 60 --force
"$bin/sam_info" "$out/ear.sam"
"$bin/sam_profile_image" skin -o "$out/profile_skin.png" --force
"$bin/sam_preview" "$out/ear.sam" -o "$out/ear_translucency.png" --force
"$bin/sam_render" "$root/scenes/ear_backlit.json" -o "$out/ear_render.exr" --png "$out/ear_render.png" --passes 4 --force
"$root/meshes/fetch_scans.sh" > /dev/null
"$bin/sam_render" "$root/meshes/scans/bunny.off" --material skin --size-mm 80 -o "$out/bunny.png" --beside none \
  --size 960x720 --write-scene "$out/bunny.json" --cache "$out/cache" --force
echo "demo: wrote $out/bunny.png: the bunny in skin, with SAM's translucency (left) and without (right)"
echo "demo: also $out/ear_render.png (and ear_render.exr, ear_translucency.png, profile_skin.png, bunny.json)"
