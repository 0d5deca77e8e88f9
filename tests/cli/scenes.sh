#!/usr/bin/env bash
# Every example scene in scenes/ is valid (sam_info loads it), except those
# naming scans that meshes/fetch_scans.sh has not fetched. Args: BIN SRC TMP
set -u
bin=$1 src=$2
fail() { echo "FAIL: $*"; exit 1; }
checked=0
for scene in "$src"/scenes/*.json; do
  mesh=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get("mesh", ""))' "$scene")
  if [ -n "$mesh" ] && [ ! -e "$(dirname "$scene")/$mesh" ] && [[ "$mesh" == *scans/* ]]; then
    echo "skip $(basename "$scene"): $mesh not fetched (meshes/fetch_scans.sh)"
    continue
  fi
  "$bin/sam_info" "$scene" > /dev/null || fail "$scene does not load"
  checked=$((checked + 1))
done
[ $checked -ge 3 ] || fail "only $checked scenes checked"
echo "scenes: $checked valid"
