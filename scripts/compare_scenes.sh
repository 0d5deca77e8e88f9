#!/usr/bin/env bash
# Runs sam_compare on every comparison scene (scenes/compare_*.json) and
# writes OUT/summary.md: one table of PSNRs over the scenes, as the README's
# "Comparison results" shows, and a second one of the map against the flat
# maps: every scene but the statue gets the samples sweep 3,16,32,64, which
# scores the cut map, the flat map and the flat-scaled baseline at each N
# against the same truth (the statue's 280k vertices make that sweep take
# hours on two cores).
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
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
names = ["sam", "tsm", "transmittance", "thickness", "none"]
def db(x):
    return "inf" if x is None else "%.2f" % x
rows = ["| scene | truth samples (s) | " + " | ".join(names) + " | SAM best? |", "| --- " * (len(names) + 3) + "|"]
for d in sorted(os.listdir(out)):
    path = os.path.join(out, d, "report.json")
    if not os.path.isfile(path):
        continue
    r = json.load(open(path))
    t = {x["name"]: x for x in r["techniques"]}
    cells, best = [], True
    for n in names:
        x = t.get(n)
        if not x or not x["available"]:
            cells.append("n/a")
            continue
        cells.append("%s / %s / %s" % (db(x["psnr_differing_db"]), db(x["psnr_db"]), db(x["psnr_translucency_db"])))
    sam = t.get("sam")
    for n in names[1:]:
        x = t.get(n)
        if sam and x and x["available"]:
            for k in ("psnr_differing_db", "psnr_translucency_db"):
                if sam[k] is not None and x[k] is not None and sam[k] <= x[k]:
                    best = False
    tr = r["truth"]
    rows.append("| %s | %d (%.0f) | %s | %s |" % (d, tr["samples"], tr["seconds"], " | ".join(cells), "yes" if best else "no"))
text = "PSNR in dB: differing pixels / all object pixels / translucency normalised\n\n" + "\n".join(rows) + "\n"
# The sweep: PSNR of all object pixels from each point's RMSE, cut and flat.
def psnr(rmse):
    import math
    return "inf" if rmse <= 0 else "%.2f" % (20 * math.log10(255 / rmse))
sweep_rows = []
for d in sorted(os.listdir(out)):
    path = os.path.join(out, d, "report.json")
    if not os.path.isfile(path):
        continue
    r = json.load(open(path))
    points = r.get("samples_sweep", {}).get("points", [])
    if points and "flat_rmse" in points[0]:
        cells = ["%s / %s / %s" % (psnr(p["rmse"]), psnr(p["flat_rmse"]), psnr(p["flat_scaled_rmse"])) for p in points]
        cells_t = ["%s / %s / %s" % (psnr(p["rmse_translucency"]), psnr(p["flat_rmse_translucency"]),
                                     psnr(p["flat_scaled_rmse_translucency"])) for p in points]
        sweep_rows.append((d, [p["n"] for p in points], cells, cells_t))
if sweep_rows:
    ns = sweep_rows[0][1]
    text += ("\nCut map / flat map / flat-scaled baseline with the same N, PSNR of all object pixels; then of the translucency "
             "(normalised):\n\n| scene | " + " | ".join("N = %d" % n for n in ns) + " | " +
             " | ".join("translucency N = %d" % n for n in ns) + " |\n|" + " --- |" * (1 + 2 * len(ns)) + "\n")
    for d, n, cells, cells_t in sweep_rows:
        text += "| %s | %s | %s |\n" % (d, " | ".join(cells), " | ".join(cells_t))
open(os.path.join(out, "summary.md"), "w").write(text)
print(text)
PY
