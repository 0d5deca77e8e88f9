#!/usr/bin/env bash
# scripts/summarise_compare.py: the table of sam_compare reports that
# compare_scenes.sh and held_out.sh write. SAM counts as best only when it
# is above every other available technique on all three scores (a tie, or
# another's exact picture, is not); an unavailable technique is "n/a" and
# not compared; the sweep's table appears only for runs with a sweep; the
# summary is written whole; a folder with no report is refused (exit 1), a
# missing argument is a usage error (exit 2). And held_out.sh refuses a
# case it does not have before any work. Args: BIN SRC TMP
set -u
bin=$1 src=$(cd "$2" && pwd) tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp/runs" "$tmp/empty"
fail() { echo "FAIL: $*"; exit 1; }
summarise=$src/scripts/summarise_compare.py
python3 - "$tmp/runs" <<'PY' || fail "writing the reports"
import json, os, sys
out = sys.argv[1]
def tech(name, diff, allp, trans):
    return {"name": name, "available": True, "psnr_differing_db": diff, "psnr_db": allp,
            "psnr_translucency_db": trans}
def write(d, techs, share=0.2, sweep=None):
    os.makedirs(os.path.join(out, d))
    r = {"truth": {"samples": 131072, "seconds": 3.0, "translucency_share": share},
         "techniques": techs + [{"name": "tsm", "available": False, "reason": "no UVs"}]}
    if sweep:
        r["samples_sweep"] = {"points": sweep}
    json.dump(r, open(os.path.join(out, d, "report.json"), "w"))
write("a_best", [tech("sam", 40, 45, 35), tech("none", 30, 44.9, 20), tech("thickness", 39.9, 30, 34.9)],
      sweep=[{"n": 3, "rmse": 2.55, "flat_rmse": 25.5, "flat_scaled_rmse": 0.0, "rmse_translucency": 1,
              "flat_rmse_translucency": 1, "flat_scaled_rmse_translucency": 1}])
write("b_tie", [tech("sam", 40, 45, 35), tech("none", 30, 45, 20)], share=0.000069)
write("c_exact", [tech("sam", None, None, None), tech("none", 30, 45, 20)])
write("d_other_exact", [tech("sam", 40, 45, 35), tech("none", 30, None, 20)])
PY
python3 "$summarise" "$tmp/runs" --title "Title line" > "$tmp/out.txt" 2> "$tmp/err.txt" || fail "refused: $(cat "$tmp/err.txt")"
[ -f "$tmp/runs/summary.md" ] || fail "no summary.md"
cmp -s "$tmp/runs/summary.md" "$tmp/out.txt" || fail "printed text differs from summary.md"
ls "$tmp/runs" | grep -q '\.tmp$' && fail "a temporary file was left"
row() { grep "^| $1 |" "$tmp/runs/summary.md"; }
row a_best | grep -q "| 40.00 / 45.00 / 35.00 | n/a | " || fail "a_best's cells: $(row a_best)"
row a_best | grep -q "| yes | 20.0% |$" || fail "a_best should be best: $(row a_best)"
row b_tie | grep -q "| no | 0.0069% |$" || fail "a tie should not be best: $(row b_tie)"
row c_exact | grep -q "| inf / inf / inf | .* | yes |" || fail "an exact SAM should be best: $(row c_exact)"
row d_other_exact | grep -q "| no |" || fail "another's exact picture should beat SAM: $(row d_other_exact)"
head -1 "$tmp/runs/summary.md" | grep -qx "Title line" || fail "no title"
grep -q "^| a_best | 40.00 / 20.00 / inf | " "$tmp/runs/summary.md" || fail "sweep row: $(grep -A3 'Cut map' "$tmp/runs/summary.md")"
[ "$(grep -c '^| [a-d]_' "$tmp/runs/summary.md")" = 5 ] || fail "expected 4 rows and 1 sweep row"
python3 "$summarise" "$tmp/empty" > /dev/null 2> "$tmp/err.txt"
[ $? = 1 ] || fail "an empty folder should exit 1"
grep -q "no DIR/report.json" "$tmp/err.txt" || fail "empty folder's message: $(cat "$tmp/err.txt")"
python3 "$summarise" > /dev/null 2>&1
[ $? = 2 ] || fail "no argument should exit 2"
SAM_BUILD_DIR=$(dirname "$bin") bash "$src/scripts/held_out.sh" "$tmp/held" nosuch > /dev/null 2> "$tmp/err.txt"
[ $? = 2 ] || fail "held_out.sh with an unknown case should exit 2"
grep -q "no case 'nosuch' (cases: hand_skin" "$tmp/err.txt" || fail "held_out.sh's message: $(cat "$tmp/err.txt")"
[ -e "$tmp/held" ] && fail "held_out.sh made its folder before refusing"
echo "summarise_compare: ok"
