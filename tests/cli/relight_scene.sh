#!/usr/bin/env bash
# scripts/relight_scene.py: the back point light (the one farthest behind the
# camera's target, not the brightest or the last) becomes a directional, spot
# or area light giving its irradiance at the target (the area light's checked
# by integrating over the square), or the studio environment; the other
# lights stay; relative paths are made absolute and "sam" is dropped; each
# variant is a scene sam_info accepts; bad input gives one line and exit 1,
# a usage error exit 2, and nothing half-written is left. Args: BIN SRC TMP
set -u
bin=$1 src=$(cd "$2" && pwd) tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp/scenes" "$tmp/m" "$tmp/out"
fail() { echo "FAIL: $*"; exit 1; }
relight=$src/scripts/relight_scene.py
cp "$src/meshes/sphere.obj" "$tmp/m/"
# Target (1, 2, 0), camera on +z: the back light 3 behind it (listed first,
# dimmest), the key light in front, a brighter side light only 0.5 behind.
cat > "$tmp/scenes/s.json" <<'JSON'
{
  "mesh": "../m/sphere.obj",
  "sam": "prebuilt.sam",
  "material": "skin",
  "scale": {"size_mm": 30},
  "lights": [
    {"type": "point", "position": [1, 2, -3], "color": [1, 0.9, 0.8], "intensity": 4.0, "shadow": false},
    {"type": "point", "position": [1, 2, 4], "intensity": 9.0},
    {"type": "point", "position": [4, 2, -0.5], "intensity": 20.0}
  ],
  "camera": {"position": [1, 2, 5], "target": [1, 2, 0], "fov_deg": 30},
  "resolution": [64, 64]
}
JSON
python3 "$relight" "$tmp/scenes/s.json" "$tmp/out" > "$tmp/log.txt" 2>&1 || fail "relight: $(cat "$tmp/log.txt")"
for kind in directional spot area environment; do
  [ -f "$tmp/out/s_$kind.json" ] || fail "no $kind variant"
  "$bin/sam_info" "$tmp/out/s_$kind.json" > "$tmp/info_$kind.txt" 2>&1 || fail "sam_info refused $kind: $(cat "$tmp/info_$kind.txt")"
done
ls "$tmp/out" | grep -q '\.tmp$' && fail "a temporary file was left"
python3 - "$tmp" <<'PY' || fail "variants"
import json, math, sys
d = sys.argv[1]
def load(k): return json.load(open(f"{d}/out/s_{k}.json"))
key, side = [1, 2, 4], [4, 2, -0.5]
for k in ("directional", "spot", "area", "environment"):
    s = load(k)
    assert s["mesh"] == f"{d}/m/sphere.obj", s["mesh"]
    assert "sam" not in s, "the prebuilt map was kept"
    kept = [l["position"] for l in s["lights"] if l["type"] == "point"]
    assert kept == [key, side], (k, kept)
for k in ("directional", "spot", "area"):
    l = load(k)["lights"][-1]
    assert l["type"] == k and l["color"] == [1, 0.9, 0.8] and l["shadow"] is False, l
E = 4.0 / 9.0  # the back light's irradiance at the target, 3 away
l = load("directional")["lights"][-1]
assert l["direction"] == [0, 0, 1] and abs(l["intensity"] - E) < 1e-12, l
l = load("spot")["lights"][-1]
assert l["position"] == [1, 2, -3] and l["direction"] == [0, 0, 1] and l["intensity"] == 4.0, l
l = load("area")["lights"][-1]
v = l["vertices"]
assert len(v) == 4 and all(abs(p[2] + 3) < 1e-9 for p in v), v
e0 = [v[1][i] - v[0][i] for i in range(3)]; e1 = [v[2][i] - v[0][i] for i in range(3)]
assert e0[0] * e1[1] - e0[1] * e1[0] > 0, "winds clockwise seen from the target: emits away from it"
xs, ys = [p[0] for p in v], [p[1] for p in v]
assert abs(max(xs) - min(xs) - 1.5) < 1e-9 and abs(max(ys) - min(ys) - 1.5) < 1e-9, v
# E = integral of L cos cos / r^2 over the square, by the midpoint rule.
n, total = 400, 0.0
for i in range(n):
    for j in range(n):
        x = min(xs) + (i + 0.5) * 1.5 / n - 1; y = min(ys) + (j + 0.5) * 1.5 / n - 2
        r2 = x * x + y * y + 9
        total += 9 / (r2 * r2)
got = l["intensity"] * total * (1.5 / n) ** 2
assert abs(got / E - 1) < 1e-3, (got, E)
s = load("environment")
assert s["environment"]["map"].endswith("scenes/studio.exr") and s["environment"]["intensity"] == 1.0, s
PY
# Straight below, seen from above: the square's sides cannot come from +y.
printf '{"mesh": "%s", "material": "skin", "scale": {"size_mm": 30}, "lights": [{"type": "point", "position": [0, -3, 0]}], "camera": {"position": [0, 5, 0], "target": [0, 0, 0], "up": [0, 0, -1]}}' \
  "$tmp/m/sphere.obj" > "$tmp/below.json"
python3 "$relight" "$tmp/below.json" "$tmp/out" --kinds area > /dev/null || fail "light below"
"$bin/sam_info" "$tmp/out/below_area.json" > /dev/null 2>&1 || fail "sam_info refused the light below"
python3 - "$tmp/out/below_area.json" <<'PY' || fail "light below: square"
import json, sys
v = json.load(open(sys.argv[1]))["lights"][0]["vertices"]
assert all(abs(p[1] + 3) < 1e-9 for p in v), v
e0 = [v[1][i] - v[0][i] for i in range(3)]; e1 = [v[2][i] - v[0][i] for i in range(3)]
assert e0[2] * e1[0] - e0[0] * e1[2] > 0, "does not face up, towards the target"
PY
refused() { # exit, message, args...
  local want=$1 msg=$2; shift 2
  python3 "$relight" "$@" > /dev/null 2> "$tmp/err.txt"; local rc=$?
  [ $rc = "$want" ] || fail "$* exited $rc, not $want: $(cat "$tmp/err.txt")"
  grep -q "$msg" "$tmp/err.txt" || fail "$*: $(cat "$tmp/err.txt")"
  [ "$(wc -l < "$tmp/err.txt")" -le 2 ] || fail "$*: more than a usage line and a message: $(cat "$tmp/err.txt")"
}
refused 2 "unknown kind 'lamp'" "$tmp/scenes/s.json" "$tmp/out" --kinds lamp
refused 2 "not a folder" "$tmp/scenes/s.json" "$tmp/nowhere"
echo '[1, 2]' > "$tmp/array.json"
refused 1 "array.json: is not a JSON object" "$tmp/array.json" "$tmp/out"
echo '{"mesh": "x.obj", "lights": [{"type": "point", "position": [0, 0, 2]}], "camera": {"position": [0, 0, 1], "target": [0, 0, 0]}}' > "$tmp/front.json"
refused 1 "no point light behind" "$tmp/front.json" "$tmp/out"
echo '{"mesh": "x.obj", "lights": [{"type": "point", "position": [0, 0, -1]}], "camera": {"position": [0, 0, 0], "target": [0, 0, 0]}}' > "$tmp/eye.json"
refused 1 "line of sight has no direction" "$tmp/eye.json" "$tmp/out"
echo '{"mesh": "x.obj", ' > "$tmp/cut.json"
refused 1 "cut.json: not JSON" "$tmp/cut.json" "$tmp/out"
refused 1 "missing.json: No such file" "$tmp/missing.json" "$tmp/out"
ls "$tmp/out" | grep -q '\.tmp$' && fail "a temporary file was left"
echo "relight_scene cli: ok"
