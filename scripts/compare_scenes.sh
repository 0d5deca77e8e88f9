#!/usr/bin/env bash
# Runs sam_compare on every comparison scene (scenes/compare_*.json) and
# writes OUT/summary.md (scripts/summarise_compare.py): one table of PSNRs
# over the scenes, as the README's "How close to the truth" shows, and a second
# one of the map against the flat maps: every scene but the statue gets the
# samples sweep 3,16,32,64, which scores the cut map, the flat map and the
# flat-scaled baseline at each N against the same truth (the statue's 280k
# vertices make that sweep take hours on two cores).
#   scripts/compare_scenes.sh [OUT_DIR]      (default out/compare; needs a build in build/)
# Set SAM_BUILD_DIR to use another build tree.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/out/compare}
bin=${SAM_BUILD_DIR:-$root/build}/bin
[ -x "$bin/sam_compare" ] || { echo "compare_scenes.sh: no $bin/sam_compare; run scripts/build.sh first" >&2; exit 1; }
"$root/meshes/fetch_scans.sh" > /dev/null
mkdir -p "$out"
for scene in "$root"/scenes/compare_*.json; do
  name=$(basename "$scene" .json)
  name=${name#compare_}
  extra=()
  if [ "$name" != statue ]; then extra=(--samples-sweep ${SWEEP:-3,16,32,64}); fi
  echo "compare_scenes.sh: $name" >&2
  start=$(date +%s)
  "$bin/sam_compare" "$scene" -o "$out/$name" --force "${extra[@]}" 2> "$out/$name.log" \
    || { tail -5 "$out/$name.log" >&2; exit 1; }
  echo "compare_scenes.sh: $name done in $(( $(date +%s) - start )) s" >&2
done
python3 "$root/scripts/summarise_compare.py" "$out"
