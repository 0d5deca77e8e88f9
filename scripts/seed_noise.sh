#!/usr/bin/env bash
# Monte Carlo noise of a map: builds SCENE's mesh twice with seeds 7 and 8
# (the scene's material and scale, plus any sam_build options given), renders
# each with --dump-vertices and prints the relative RMSE of per-vertex T
# between the two (red, green, blue; over the RMS of T) and each build's
# time. With independent estimates of equal variance, the noise of one
# build is this over sqrt(2).
#
#   scripts/seed_noise.sh SCENE.json [sam_build options...]
#   scripts/seed_noise.sh scenes/ear_backlit.json --mc-samples 256
#
# The scene's copies (naming each map) go beside it for the renders, so
# its relative paths hold, and are removed at the end with the maps.
# Needs build/bin (SAM_BIN to use another folder of programs).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${SAM_BIN:-$root/build/bin}
usage() { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 1 ] || usage
case $1 in -h|--help) usage ;; esac
scene=$1; shift
[ -f "$scene" ] || { echo "seed_noise: no scene file '$scene'" >&2; exit 2; }
[ -x "$bin/sam_build" ] || { echo "seed_noise: no $bin/sam_build; run scripts/build.sh first" >&2; exit 2; }
tmp=$(mktemp -d)
copies=()
cleanup() { rm -rf "$tmp"; [ ${#copies[@]} -eq 0 ] || rm -f "${copies[@]}"; }
trap cleanup EXIT
# The mesh, material and scale as sam_build takes them, one argument a line.
python3 - "$scene" > "$tmp/args.txt" <<'PY'
import json, os, sys
path = sys.argv[1]
try:
    s = json.load(open(path))
except (OSError, ValueError) as e:
    sys.exit("seed_noise: %s: %s" % (path, e))
here = os.path.dirname(os.path.abspath(path))
def need(key):
    if key not in s:
        sys.exit("seed_noise: %s has no \"%s\"" % (path, key))
    return s[key]
args = [os.path.join(here, need("mesh"))]
material = need("material")
if not isinstance(material, str):
    sys.exit("seed_noise: %s: \"material\" is not a preset name or a profile file" % path)
# A profile file resolves against the scene, as the scene loader resolves it.
if os.path.exists(os.path.join(here, material)):
    material = os.path.join(here, material)
args += ["--material", material]
scale = s.get("scale", {})
if "mm_per_unit" in scale:
    args += ["--mm-per-unit", repr(scale["mm_per_unit"])]
elif "size_mm" in scale:
    args += ["--size-mm", repr(scale["size_mm"])]
else:
    sys.exit("seed_noise: %s gives no scale (mm_per_unit or size_mm)" % path)
print("\n".join(args))
PY
mapfile -t build_args < "$tmp/args.txt"
dir=$(dirname "$scene")
for seed in 7 8; do
  start=$(date +%s.%N)
  "$bin/sam_build" "${build_args[@]}" --seed "$seed" -o "$tmp/$seed.sam" "$@" > "$tmp/build$seed.txt" 2>&1 \
    || { cat "$tmp/build$seed.txt" >&2; exit 1; }
  echo "$start $(date +%s.%N)" > "$tmp/time$seed.txt"
  copy="$dir/.seed_noise_$$_$seed.json"
  copies+=("$copy")
  python3 - "$scene" "$tmp/$seed.sam" "$copy" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["sam"] = sys.argv[2]
json.dump(s, open(sys.argv[3], "w"))
PY
  "$bin/sam_render" "$copy" -o "$tmp/$seed.png" --size 64x48 --dump-vertices "$tmp/$seed.csv" \
    > "$tmp/render$seed.txt" 2>&1 || { cat "$tmp/render$seed.txt" >&2; exit 1; }
done
python3 - "$tmp/7.csv" "$tmp/8.csv" "$tmp/time7.txt" "$tmp/time8.txt" <<'PY'
import csv, math, sys
def rows(path):
    return [[float(r[k]) for k in ("t_r", "t_g", "t_b")] for r in csv.DictReader(open(path))]
def seconds(path):
    start, end = open(path).read().split()
    return float(end) - float(start)
a, b = rows(sys.argv[1]), rows(sys.argv[2])
out = []
for c in range(3):
    diff = sum((x[c] - y[c]) ** 2 for x, y in zip(a, b)) / len(a)
    rms = math.sqrt(sum(((x[c] + y[c]) / 2) ** 2 for x, y in zip(a, b)) / len(a))
    out.append(100 * math.sqrt(diff) / rms if rms > 0 else 0.0)
print("seed noise (relative RMSE of T between seeds 7 and 8): %.1f%%, %.1f%%, %.1f%%; builds %.2f s, %.2f s"
      % (out[0], out[1], out[2], seconds(sys.argv[3]), seconds(sys.argv[4])))
PY
