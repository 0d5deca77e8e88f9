#!/usr/bin/env bash
# Monte Carlo noise of a map: builds SCENE's mesh twice with seeds 7 and 8
# (the scene's material and scale, plus any sam_build options given), renders
# each with --dump-vertices and prints the relative RMSE of per-vertex T
# between the two (red, green, blue) and each build's time. With independent
# estimates of equal variance, the noise of one build is this over sqrt(2).
#
#   scripts/seed_noise.sh SCENE.json [sam_build options...]
#   scripts/seed_noise.sh scenes/ear_backlit.json --mc-samples 256
#
# Writes into a temporary folder, removed at the end. Needs build/bin.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${SAM_BIN:-$root/build/bin}
[ $# -ge 1 ] || { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
scene=$1; shift
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
read -r mesh material mm < <(python3 - "$scene" <<'PY'
import json, os, sys
s = json.load(open(sys.argv[1]))
mesh = os.path.join(os.path.dirname(os.path.abspath(sys.argv[1])), s["mesh"])
scale = s.get("scale", {})
if "mm_per_unit" not in scale:
    sys.exit("seed_noise: %s gives no scale.mm_per_unit" % sys.argv[1])
print(mesh, s["material"] if isinstance(s["material"], str) else "", scale["mm_per_unit"])
PY
)
[ -n "$material" ] || { echo "seed_noise: the scene's material is not a named one" >&2; exit 2; }
for seed in 7 8; do
  start=$(date +%s.%N)
  "$bin/sam_build" "$mesh" --material "$material" --mm-per-unit "$mm" --seed "$seed" -o "$tmp/$seed.sam" "$@" \
    > "$tmp/build$seed.txt" 2>&1 || { cat "$tmp/build$seed.txt"; exit 1; }
  echo "$start $(date +%s.%N)" > "$tmp/time$seed.txt"
  python3 - "$scene" "$tmp/$seed.sam" "$tmp/scene$seed.json" <<'PY'
import json, os, sys
s = json.load(open(sys.argv[1]))
s["mesh"] = os.path.join(os.path.dirname(os.path.abspath(sys.argv[1])), s["mesh"])
s["sam"] = sys.argv[2]
json.dump(s, open(sys.argv[3], "w"))
PY
  "$bin/sam_render" "$tmp/scene$seed.json" -o "$tmp/$seed.png" --size 64x48 --dump-vertices "$tmp/$seed.csv" \
    > "$tmp/render$seed.txt" 2>&1 || { cat "$tmp/render$seed.txt"; exit 1; }
done
python3 - "$tmp/7.csv" "$tmp/8.csv" "$(cat "$tmp/time7.txt")" "$(cat "$tmp/time8.txt")" <<'PY'
import csv, math, sys
def rows(path):
    return [[float(r[k]) for k in ("t_r", "t_g", "t_b")] for r in csv.DictReader(open(path))]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
out = []
for c in range(3):
    diff = sum((x[c] - y[c]) ** 2 for x, y in zip(a, b)) / len(a)
    rms = math.sqrt(sum(((x[c] + y[c]) / 2) ** 2 for x, y in zip(a, b)) / len(a))
    out.append(100 * math.sqrt(diff) / rms if rms > 0 else 0.0)
print("seed noise (relative RMSE of T between seeds 7 and 8): %.1f%%, %.1f%%, %.1f%%; builds %.2f s, %.2f s"
      % (out[0], out[1], out[2], *(float(t[1]) - float(t[0]) for t in (sys.argv[3].split(), sys.argv[4].split()))))
PY
