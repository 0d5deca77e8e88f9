#!/usr/bin/env bash
# scripts/seed_noise.sh: on a small slab in skin it prints the seed-to-seed
# noise of T per channel and both build times; the sam_build options given
# reach the builds (4 pairs per form factor are noisier than 1024); a scene
# scaled by size_mm works; a usage error exits 2, a scene without a scale
# gives one line; no copy of the scene is left beside it. Args: BIN SRC TMP
set -u
bin=$1 src=$(cd "$2" && pwd) tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
script=$src/scripts/seed_noise.sh
"$bin/sam_meshgen" slab -o "$tmp/slab.obj" --resolution 8 > /dev/null || fail "meshgen"
cat > "$tmp/scene.json" <<'JSON'
{"mesh": "slab.obj", "material": "skin", "scale": {"size_mm": 40},
 "lights": [{"type": "point", "position": [0.2, -1.5, 0.1], "intensity": 4.0}],
 "camera": {"position": [0.0, 1.3, 0.6], "target": [0.0, 0.0, 0.0], "fov_deg": 50}}
JSON
noise() { # the green channel's noise, in percent
  SAM_BIN=$bin bash "$script" "$tmp/scene.json" "$@" > "$tmp/out.txt" 2> "$tmp/err.txt" \
    || fail "seed_noise $*: $(cat "$tmp/err.txt")"
  grep -Eq '^seed noise \(relative RMSE of T between seeds 7 and 8\): [0-9.]+%, [0-9.]+%, [0-9.]+%; builds [0-9.]+ s, [0-9.]+ s$' \
    "$tmp/out.txt" || fail "output: $(cat "$tmp/out.txt")"
  sed -E 's/.*: [0-9.]+%, ([0-9.]+)%.*/\1/' "$tmp/out.txt"
}
few=$(noise --mc-samples 4) || exit 1
many=$(noise --mc-samples 1024) || exit 1
echo "seed noise in green: $few% with 4 pairs, $many% with 1024"
python3 -c "import sys; sys.exit(0 if float('$few') > 2 * float('$many') and float('$many') > 0 else 1)" \
  || fail "4 pairs ($few%) should be noisier than 1024 ($many%)"
ls -a "$tmp" | grep -q seed_noise && fail "a scene copy was left: $(ls -a "$tmp")"
# Usage and errors.
SAM_BIN=$bin bash "$script" > /dev/null 2> "$tmp/err.txt"; [ $? = 2 ] || fail "no arguments should exit 2"
grep -q "seed_noise.sh SCENE.json" "$tmp/err.txt" || fail "usage: $(cat "$tmp/err.txt")"
SAM_BIN=$bin bash "$script" "$tmp/none.json" > /dev/null 2> "$tmp/err.txt"; [ $? = 2 ] || fail "a missing scene should exit 2"
grep -q "no scene file" "$tmp/err.txt" || fail "missing scene: $(cat "$tmp/err.txt")"
sed 's/"scale": {"size_mm": 40},//' "$tmp/scene.json" > "$tmp/unscaled.json"
SAM_BIN=$bin bash "$script" "$tmp/unscaled.json" > /dev/null 2> "$tmp/err.txt" && fail "a scene without a scale ran"
grep -q "gives no scale" "$tmp/err.txt" || fail "unscaled: $(cat "$tmp/err.txt")"
echo "seed_noise cli: ok"
