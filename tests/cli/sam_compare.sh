#!/usr/bin/env bash
# sam_compare end to end on a tiny back-lit slab (llvmpipe): every image
# and both reports are written, the report's numbers agree with each other
# (the truth against itself is an exact match, PSNR = 20 log10(255 / RMSE),
# `none` scores below `sam` on a back-lit slab), the samples sweep plots,
# and bad input gives one error line. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
"$bin/sam_meshgen" slab -o "$tmp/slab.obj" --resolution 16 --thickness 0.06 > /dev/null || fail "meshgen"
cat > "$tmp/scene.json" <<JSON
{"mesh": "slab.obj", "material": "skin", "scale": {"mm_per_unit": 40},
 "lights": [{"type": "directional", "direction": [0.1, 1.0, 0.05], "intensity": 3.0, "shadow": true},
            {"type": "point", "position": [0.3, 1.2, 0.8], "intensity": 0.6, "shadow": true}],
 "camera": {"position": [0.0, 1.3, 0.6], "target": [0.0, 0.0, 0.0], "fov_deg": 50},
 "resolution": [48, 40]}
JSON
start=$(date +%s)
"$bin/sam_compare" "$tmp/scene.json" --out "$tmp/out" --techniques sam,none,transmittance,tsm \
  --samples-sweep 1,3,6 2> "$tmp/log.txt" || fail "sam_compare: $(cat "$tmp/log.txt")"
echo "sam_compare took $(( $(date +%s) - start )) s"
for f in truth truth_translucency sam sam_translucency none none_translucency transmittance; do
  head -c 4 "$tmp/out/$f.exr" | od -An -tx1 | grep -q "76 2f 31 01" || fail "$f.exr is not an EXR"
  head -c 8 "$tmp/out/$f.png" | od -An -tx1 | grep -q "89 50 4e 47" || fail "$f.png is not a PNG"
done
for f in sam_diff4 sam_translucency_diff4 none_diff4 rmse_vs_samples row translucency_row; do
  head -c 8 "$tmp/out/$f.png" | od -An -tx1 | grep -q "89 50 4e 47" || fail "$f.png is not a PNG"
done
grep -q "^| sam |" "$tmp/out/report.md" || fail "report.md has no sam row"
python3 - "$tmp/out/report.json" <<'PY' || fail "report.json is inconsistent"
import json, math, sys
r = json.load(open(sys.argv[1]))
t = {x["name"]: x for x in r["techniques"]}
truth = r["truth"]
assert truth["self_psnr_db"] is None and truth["self_differing_pixels"] == 0, truth
assert truth["samples"] > 0 and truth["seconds"] > 0 and truth["converged"] is True, truth
assert t["sam"]["available"] and t["none"]["available"] and t["transmittance"]["available"]
for x in t.values():
    if not x["available"]:
        continue
    assert 0 < x["pixels"] and x["differing_pixels"] <= x["pixels"], x
    for p, e in (("psnr_db", "rmse"), ("psnr_differing_db", "rmse_differing"), ("psnr_translucency_db", "rmse_translucency")):
        if x[p] is not None:
            assert abs(x[p] - 20 * math.log10(255 / x[e])) < 0.01 + 0.2 * (x[e] < 0.01), (p, x)
        else:
            assert x[e] == 0, (p, x)
    if x["psnr_db"] is not None and x["psnr_differing_db"] is not None:
        assert x["psnr_differing_db"] <= x["psnr_db"] + 1e-6, x
sam, none = t["sam"], t["none"]
assert none["psnr_db"] is not None and (sam["psnr_db"] is None or sam["psnr_db"] > none["psnr_db"]), (sam, none)
assert sam["psnr_translucency_db"] > none["psnr_translucency_db"], (sam, none)
pts = r["samples_sweep"]["points"]
assert [p["n"] for p in pts] == [1, 3, 6], pts
print("truth %d samples %.2f s; PSNR sam %s none %s transmittance %s dB; sweep RMSE %s" % (
    truth["samples"], truth["seconds"], sam["psnr_db"], none["psnr_db"], t["transmittance"]["psnr_db"],
    [round(p["rmse"], 3) for p in pts]))
PY
# A finished comparison is not overwritten without --force.
"$bin/sam_compare" "$tmp/scene.json" --out "$tmp/out" --techniques none 2> "$tmp/err.txt" && fail "overwrote a report"
grep -q "already holds a report" "$tmp/err.txt" || fail "no refusal message: $(cat "$tmp/err.txt")"
expect_error() { # label args...
  local label=$1; shift
  "$bin/sam_compare" "$@" > /dev/null 2> "$tmp/err.txt" && fail "$label: accepted"
  [ "$(wc -l < "$tmp/err.txt")" -ge 1 ] || fail "$label: no message"
  grep -q "sam_compare" "$tmp/err.txt" || fail "$label: message does not name the tool: $(cat "$tmp/err.txt")"
}
expect_error "unknown technique" "$tmp/scene.json" --out "$tmp/x" --techniques sam,foo
expect_error "bad sweep" "$tmp/scene.json" --out "$tmp/x" --samples-sweep 3,0
expect_error "bad tolerance" "$tmp/scene.json" --out "$tmp/x" --truth-tolerance 0.7
expect_error "missing scene" "$tmp/nope.json" --out "$tmp/x"
expect_error "no --out" "$tmp/scene.json"
# A run that fails before its first image leaves no output folder.
printf 'SAMFjunk' > "$tmp/bad.sam"
printf '{"sam": "bad.sam", "material": "skin", "scale": {"mm_per_unit": 10}, "resolution": [32, 32]}' > "$tmp/bad.json"
expect_error "corrupted .sam" "$tmp/bad.json" --out "$tmp/badout"
grep -q "bad.sam: truncated" "$tmp/err.txt" || fail "corrupted .sam message: $(cat "$tmp/err.txt")"
[ -e "$tmp/badout" ] && fail "a failed run left $tmp/badout"
"$bin/sam_compare" --help | grep -q "usage: sam_compare" || fail "--help"
echo "ok"
