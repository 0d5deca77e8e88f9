#!/usr/bin/env bash
# scripts/relight_scene.py: each variant is a scene sam_info accepts, the
# back point light (the one farthest behind the camera's target) replaced by
# a light of that kind giving its irradiance at the target, the key light
# kept; an unknown kind and a scene without a point light are refused.
# Args: BIN SRC TMP
set -u
bin=$1 src=$(cd "$2" && pwd) tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
relight=$src/scripts/relight_scene.py
cat > "$tmp/s.json" <<JSON
{
  "mesh": "$src/meshes/sphere.obj",
  "material": "skin",
  "scale": {"size_mm": 30},
  "lights": [
    {"type": "point", "position": [0, 0, 3], "intensity": 2.0},
    {"type": "point", "position": [0, 0, -2], "color": [1, 0.9, 0.8], "intensity": 8.0}
  ],
  "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "fov_deg": 30},
  "resolution": [64, 64]
}
JSON
python3 "$relight" "$tmp/s.json" "$tmp" > "$tmp/out.txt" || fail "relight: $(cat "$tmp/out.txt")"
for kind in directional spot area environment; do
  [ -f "$tmp/s_$kind.json" ] || fail "no $kind variant"
  "$bin/sam_info" "$tmp/s_$kind.json" > "$tmp/info_$kind.txt" 2>&1 || fail "sam_info refused $kind: $(cat "$tmp/info_$kind.txt")"
done
python3 - "$tmp" <<'PY' || fail "variants"
import json, math, sys
d = sys.argv[1]
def load(k): return json.load(open(f"{d}/s_{k}.json"))
for k in ("directional", "spot", "area"):
    s = load(k)
    assert len(s["lights"]) == 2 and s["lights"][0]["position"] == [0, 0, 3], s["lights"]
    assert s["lights"][1]["type"] == k and s["lights"][1]["color"] == [1, 0.9, 0.8], s["lights"][1]
l = load("directional")["lights"][1]
assert l["direction"] == [0, 0, 1] and abs(l["intensity"] - 2.0) < 1e-9, l   # 8 / 2^2, travelling +z
l = load("spot")["lights"][1]
assert l["position"] == [0, 0, -2] and l["direction"] == [0, 0, 1] and l["intensity"] == 8.0, l
l = load("area")["lights"][1]
v = l["vertices"]
assert len(v) == 4 and all(abs(p[2] + 2) < 1e-9 for p in v), v
side = math.dist(v[0], v[1])
assert abs(side - 1.0) < 1e-9 and abs(l["intensity"] * side * side / 4 - 2.0) < 1e-9, l
e0 = [v[1][i] - v[0][i] for i in range(3)]; e1 = [v[2][i] - v[0][i] for i in range(3)]
assert e0[0] * e1[1] - e0[1] * e1[0] > 0, "does not face the target (+z)"
s = load("environment")
assert len(s["lights"]) == 1 and s["environment"]["map"].endswith("scenes/studio.exr"), s
PY
python3 "$relight" "$tmp/s.json" "$tmp" --kinds lamp 2> "$tmp/err.txt" && fail "unknown kind accepted"
grep -q "unknown kind 'lamp'" "$tmp/err.txt" || fail "unknown kind: $(cat "$tmp/err.txt")"
printf '{"mesh": "x.obj", "lights": [], "camera": {"position": [0,0,1], "target": [0,0,0]}}' > "$tmp/none.json"
python3 "$relight" "$tmp/none.json" "$tmp" 2> "$tmp/err.txt" && fail "scene without a point light accepted"
grep -q "needs a camera and a point light" "$tmp/err.txt" || fail "no point light: $(cat "$tmp/err.txt")"
echo "relight_scene cli: ok"
