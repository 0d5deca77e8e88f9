#!/usr/bin/env bash
# Compares SAM with the ground truth and the other techniques on meshes that
# no scene, default or test was made with (docs/comparison.md, "Meshes
# without a bundled scene"): each is staged as a user would stage a bare
# mesh (sam_render MESH --write-scene: framing, key light, back light,
# exposure; the up axis given where the guess is wrong), compared with
# sam_compare, and some are compared again with the back light turned into
# another kind of light (relight_scene.py).
# Writes OUT/NAME.json (the staged scene), OUT/NAME/ (sam_compare's files),
# OUT/NAME_KIND/ for a relit one, and OUT/summary.md
# (scripts/summarise_compare.py). On two cores, about 12 minutes.
#   scripts/held_out.sh [OUT_DIR [NAME...]]   (default out/held_out, every case; needs a build in build/)
# Set SAM_BUILD_DIR to use another build tree.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case "${1:-}" in
  -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
esac
out=${1:-$root/out/held_out}
[ $# -gt 0 ] && shift
bin=${SAM_BUILD_DIR:-$root/build}/bin
[ -x "$bin/sam_compare" ] || { echo "held_out.sh: no $bin/sam_compare; run scripts/build.sh first" >&2; exit 1; }
scans=$root/meshes/scans
# name, mesh in meshes/scans/, material, size in mm (the bounding box's
# diagonal), the kinds of light the back light also becomes ("-": none),
# and more staging options, commas for spaces (optional)
cases=(
  "hand_skin hand.off skin 220 -"
  "hand_milk hand.off wholemilk 150 -"
  "camel_marble camel.off marble 100 area"
  "mushroom_apple mushroom.off apple 60 -"
  "lion_jade lion_head.off $root/scenes/materials/jade_radius.json 80 environment"
  "homer_ketchup homer.off ketchup 60 directional"
  "cow_skin2 cow.off skin2 80 spot"
  "bull_marble bull.off marble 150 environment"
  "dino_skin dino.off skin 90 - --up,+Z,--angle,150"
  "femur_cream femur.off cream 120 -"
  "bear_milk bear.off wholemilk 80 -"
  "diplodocus_apple diplodocus.off apple 120 spot"
  "elk_skin2 elk.off skin2 60 area"
  "cactus_potato cactus.off potato 50 -"
)
known=" "
for c in "${cases[@]}"; do known+="${c%% *} "; done
for want in "$@"; do
  [[ "$known" == *" $want "* ]] || { echo "held_out.sh: no case '$want' (cases:$known)" >&2; exit 2; }
done
"$root/meshes/fetch_scans.sh" > /dev/null
mkdir -p "$out/relit"
compare() { # NAME SCENE
  echo "held_out.sh: $1" >&2
  "$bin/sam_compare" "$2" -o "$out/$1" --force --cache "$out/cache" 2> "$out/$1.log" \
    || { tail -5 "$out/$1.log" >&2; exit 1; }
}
for c in "${cases[@]}"; do
  read -r name mesh material size kinds staging <<<"$c"
  IFS=, read -r -a staging <<<"${staging:-}"
  if [ $# -gt 0 ] && [[ " $* " != *" $name "* ]]; then continue; fi
  "$bin/sam_render" "$scans/$mesh" -o "$out/$name.png" --material "$material" --size-mm "$size" --size 400x400 \
    --write-scene "$out/$name.json" --cache "$out/cache" --force "${staging[@]}" 2> "$out/$name.stage.log" \
    || { tail -5 "$out/$name.stage.log" >&2; exit 1; }
  compare "$name" "$out/$name.json"
  if [ "$kinds" != - ]; then
    python3 "$root/scripts/relight_scene.py" --kinds "$kinds" "$out/$name.json" "$out/relit" > /dev/null
    for kind in ${kinds//,/ }; do compare "${name}_$kind" "$out/relit/${name}_$kind.json"; done
  fi
done
python3 "$root/scripts/summarise_compare.py" "$out" \
  --title "Held-out meshes (scripts/held_out.sh), $(date -u +%Y-%m-%d); the staging's back lights and exposures are in NAME.stage.log"
