#!/usr/bin/env bash
# scripts/bench.sh --quick: the whole benchmark suite runs, every JSON it
# writes parses, and every plot is a non-empty PNG. Args: BIN_DIR SOURCE_DIR TMP_DIR
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }

"$src/scripts/bench.sh" --quick --bin "$bin" --out "$tmp/results" > "$tmp/bench.log" 2>&1 \
  || { tail -30 "$tmp/bench.log"; fail "scripts/bench.sh --quick failed (log: $tmp/bench.log)"; }
for name in build frame truth suite; do
  [ -s "$tmp/results/$name.json" ] || fail "no $name.json"
  python3 -m json.tool "$tmp/results/$name.json" > /dev/null || fail "$name.json does not parse"
done
for name in build frame truth; do
  [ -s "$tmp/results/$name.txt" ] || fail "no table $name.txt"
done
for name in build frame_techniques translucency_pass update truth; do
  png="$tmp/results/$name.png"
  [ -s "$png" ] || fail "no plot $name.png"
  [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$name.png is not a PNG"
done
# Each technique x diffusion of every scene is measured or says why not.
python3 - "$tmp/results/frame.json" <<'PY' || fail "frame.json lacks the technique matrix"
import json, sys
frame = json.load(open(sys.argv[1]))
scenes = frame["frame_by_technique"]
assert len(scenes) == 3, len(scenes)
for scene in scenes:
    assert len(scene["frames"]) == 16, scene["scene"]
    for f in scene["frames"]:
        assert "skipped" in f or f["total_ms"] > 0, f
    assert all(f["technique"] != "tsm" or f["diffusion"] == "texture" or "skipped" in f for f in scene["frames"])
    assert "texture" in scene["sam_over_tsm"] or any("skipped" in f for f in scene["frames"] if f["technique"] == "tsm")
PY
ls "$tmp/results"/*.tmp* 2>/dev/null && fail "temporary files left in $tmp/results"
# bench_limit on a small marble slab lit from below: the cut map with more
# samples comes nearer the vertex-sum limit, and the limit is near the truth.
"$bin/sam_meshgen" slab -o "$tmp/slab.obj" --resolution 24 --thickness 0.05 > /dev/null 2>&1 || fail "meshgen slab"
printf '{"mesh": "slab.obj", "material": "marble", "scale": {"mm_per_unit": 50}, "resolution": [32, 32],
  "lights": [{"type": "directional", "direction": [0, -1, 0], "intensity": 2.0}]}' > "$tmp/slab.json"
"$bin/bench_limit" "$tmp/slab.json" --samples 2,16 --queries 48 --pairs 256 --truth-samples 65536 \
  --json "$tmp/limit.json" --csv "$tmp/limit.csv" > "$tmp/limit.txt" 2>&1 || fail "bench_limit: $(cat "$tmp/limit.txt")"
python3 - "$tmp/limit.json" "$tmp/limit.csv" <<'PY' || fail "bench_limit's results: $(cat "$tmp/limit.txt")"
import csv, json, sys
r = json.load(open(sys.argv[1]))
maps = {(m["map"], m["n"]): m for m in r["maps"]}
assert set(maps) == {("cut", 2), ("cut", 16), ("flat", 16)}, maps
assert maps[("cut", 16)]["vs_limit"]["rmse"] < 0.5 * maps[("cut", 2)]["vs_limit"]["rmse"], maps
assert abs(r["limit_vs_truth"]["bias"]) < 0.05 and abs(r["point_limit_vs_truth"]["bias"]) < 0.05, r
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == r["queries"] and "cut16_g" in rows[0] and "flat16_b" in rows[0] and "point_limit_r" in rows[0], rows[0]
PY
echo "bench: quick suite ok"
