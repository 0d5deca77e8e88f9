#!/usr/bin/env bash
# Runs sam_compare on every comparison scene (scenes/compare_*.json) and
# writes OUT/summary.md: one table of PSNRs over the scenes, as the README's
# "Comparison results" shows. The armadillo and the statue (the paper's
# Fig. 10 sweeps its Happy Buddha) also get the samples sweep; the statue's
# stops at N = 20, as its samples at N = 50 (279,890 vertices x 50 x 16
# bytes) exceed the 128 MiB storage block that llvmpipe allows.
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
  case $name in
    armadillo) extra=(--samples-sweep 3,5,10,20,50) ;;
    statue) extra=(--samples-sweep 3,5,10,20) ;;
  esac
  echo "compare_scenes.sh: $name" >&2
  start=$(date +%s)
  "$bin/sam_compare" "$scene" --out "$out/$name" --force "${extra[@]}" 2> "$out/$name.log" \
    || { tail -5 "$out/$name.log" >&2; exit 1; }
  echo "compare_scenes.sh: $name done in $(( $(date +%s) - start )) s" >&2
done
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
names = ["sam", "tsm", "transmittance", "none"]
def db(x):
    return "inf" if x is None else "%.2f" % x
rows = ["| scene | truth samples (s) | " + " | ".join(names) + " | SAM best? |", "| --- " * 7 + "|"]
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
open(os.path.join(out, "summary.md"), "w").write(text)
print(text)
PY
