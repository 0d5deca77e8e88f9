#!/usr/bin/env bash
# sam_compare end to end on a tiny back-lit slab (llvmpipe): every image
# and both reports are written, the report's numbers agree with each other
# (the truth against itself is an exact match, PSNR = 20 log10(255 / RMSE),
# `none` scores below `sam` and `thickness` on a back-lit slab; every
# technique by default), the samples sweep plots,
# an animated slab compares chosen frames against truths of their poses,
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
"$bin/sam_compare" "$tmp/scene.json" -o "$tmp/out" --samples-sweep 1,3,6 2> "$tmp/log.txt" \
  || fail "sam_compare: $(cat "$tmp/log.txt")"
echo "sam_compare took $(( $(date +%s) - start )) s"
for f in truth truth_translucency sam sam_translucency none none_translucency transmittance thickness \
  thickness_translucency; do
  head -c 4 "$tmp/out/$f.exr" | od -An -tx1 | grep -q "76 2f 31 01" || fail "$f.exr is not an EXR"
  head -c 8 "$tmp/out/$f.png" | od -An -tx1 | grep -q "89 50 4e 47" || fail "$f.png is not a PNG"
done
for f in sam_diff4 sam_translucency_diff4 none_diff4 thickness_diff4 rmse_vs_samples row translucency_row; do
  head -c 8 "$tmp/out/$f.png" | od -An -tx1 | grep -q "89 50 4e 47" || fail "$f.png is not a PNG"
done
grep -q "^| sam |" "$tmp/out/report.md" || fail "report.md has no sam row"
grep -q "^| thickness |" "$tmp/out/report.md" || fail "report.md has no thickness row"
python3 - "$tmp/out/report.json" <<'PY' || fail "report.json is inconsistent"
import json, math, sys
r = json.load(open(sys.argv[1]))
t = {x["name"]: x for x in r["techniques"]}
truth = r["truth"]
assert truth["self_psnr_db"] is None and truth["self_differing_pixels"] == 0, truth
assert truth["samples"] > 0 and truth["seconds"] > 0 and truth["converged"] is True, truth
assert [x["name"] for x in r["techniques"]] == ["sam", "none", "tsm", "transmittance", "thickness"], r["techniques"]
assert t["sam"]["available"] and t["none"]["available"] and t["transmittance"]["available"]
assert t["thickness"]["available"]
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
assert t["thickness"]["psnr_translucency_db"] > none["psnr_translucency_db"], (t["thickness"], none)
pts = r["samples_sweep"]["points"]
assert [p["n"] for p in pts] == [1, 3, 6], pts
assert all(p["cut_budget"] == 32 for p in pts), pts
assert r["map"] == "cut", r["map"]
print("truth %d samples %.2f s; PSNR sam %s none %s transmittance %s thickness %s dB; sweep RMSE %s" % (
    truth["samples"], truth["seconds"], sam["psnr_db"], none["psnr_db"], t["transmittance"]["psnr_db"],
    t["thickness"]["psnr_db"], [round(p["rmse"], 3) for p in pts]))
PY
# A scene that names a prebuilt map beside its mesh, leaving the material
# and scale to the map's INFO: the sweep still builds each N from the mesh
# (it used to score the prebuilt map every time), in the map's material and
# scale, so it scores as the mesh scene's sweep did.
"$bin/sam_build" "$tmp/slab.obj" -o "$tmp/slab.sam" --material skin --mm-per-unit 40 --quiet 2> /dev/null \
  || fail "sam_build slab"
sed 's/^{"mesh": "slab.obj",.*$/{"mesh": "slab.obj", "sam": "slab.sam",/' "$tmp/scene.json" > "$tmp/prebuilt.json"
grep -q '"material"' "$tmp/prebuilt.json" && fail "the prebuilt scene still names a material"
grep -q slab.sam "$tmp/prebuilt.json" || fail "the prebuilt scene names no map"
"$bin/sam_compare" "$tmp/prebuilt.json" -o "$tmp/prebuilt" --techniques sam --samples-sweep 1,6 \
  2> "$tmp/prebuilt_log.txt" || fail "sam_compare with a prebuilt map: $(cat "$tmp/prebuilt_log.txt")"
python3 - "$tmp/prebuilt/report.json" "$tmp/out/report.json" <<'PY' || fail "the sweep of a scene with a prebuilt map"
import json, sys
pts = json.load(open(sys.argv[1]))["samples_sweep"]["points"]
assert [p["n"] for p in pts] == [1, 6] and pts[0]["rmse"] != pts[1]["rmse"], pts
mesh = {p["n"]: p["rmse"] for p in json.load(open(sys.argv[2]))["samples_sweep"]["points"]}
assert all(abs(p["rmse"] - mesh[p["n"]]) <= 1e-6 * max(1.0, mesh[p["n"]]) for p in pts), (pts, mesh)
PY
# --whole-cut: each point stores all of an N-entry cut, not N of a 32-entry
# one, and the report and plot say so.
"$bin/sam_compare" "$tmp/scene.json" -o "$tmp/whole" --techniques sam --samples-sweep 2,16 --whole-cut \
  2> "$tmp/whole_log.txt" || fail "sam_compare --whole-cut: $(cat "$tmp/whole_log.txt")"
grep -q "whole cut stored" "$tmp/whole/sweep.gnuplot" || fail "the whole cut's plot does not say so"
grep -q "^| 16 | 16 |" "$tmp/whole/report.md" || fail "report.md's sweep has no budget: $(cat "$tmp/whole/report.md")"
python3 - "$tmp/whole/report.json" "$tmp/out/report.json" <<'PY' || fail "the whole cut's sweep"
import json, sys
r = json.load(open(sys.argv[1]))
pts = r["samples_sweep"]["points"]
assert [(p["n"], p["cut_budget"]) for p in pts] == [(2, 2), (16, 16)], pts
rmse = lambda report: [x for x in report["techniques"] if x["name"] == "sam"][0]["rmse"]
# The map shown is the whole 16-entry cut too, not 16 of 32 as by default.
shown, fitted = rmse(r), rmse(json.load(open(sys.argv[2])))
assert abs(shown - pts[1]["rmse"]) <= 1e-4 * max(1.0, shown), (shown, pts)
assert shown != fitted, (shown, fitted)
PY
# An animated scene: the slab bends up (period 0.8 s) and --frames 0,2 at 10 fps compares the rest pose and
# the full bend (t = 0.2 s), each against a truth of its own pose, in frame_0000/ and frame_0002/.
sed 's/^ "camera"/ "deformers": [{"type": "bend", "axis": [1, 0, 0], "direction": [0, 1, 0], "angle_deg": 120,\
                "length": 1.0, "period_s": 0.8}],\
 "camera"/' "$tmp/scene.json" > "$tmp/anim.json"
grep -q deformers "$tmp/anim.json" || fail "the animated scene has no deformers"
start=$(date +%s)
"$bin/sam_compare" "$tmp/anim.json" -o "$tmp/anim" --frames 0,2 --fps 10 --techniques sam,none \
  2> "$tmp/anim_log.txt" || fail "sam_compare --frames: $(cat "$tmp/anim_log.txt")"
echo "sam_compare --frames 0,2 took $(( $(date +%s) - start )) s"
grep -q "ignored" "$tmp/anim_log.txt" && fail "still says the deformers are ignored: $(cat "$tmp/anim_log.txt")"
for k in 0000 0002; do
  for f in truth truth_translucency sam sam_translucency none; do
    [ -s "$tmp/anim/frame_$k/$f.exr" ] && [ -s "$tmp/anim/frame_$k/$f.png" ] \
      || fail "frame $k has no $f: $(ls "$tmp/anim/frame_$k")"
  done
  [ -s "$tmp/anim/frame_$k/report.json" ] || fail "frame $k has no report.json"
done
[ -e "$tmp/anim/frame_0001" ] && fail "compared frame 1, which was not asked for"
[ -e "$tmp/anim/truth.exr" ] && fail "--frames also wrote the single-pose layout"
python3 - "$tmp/anim" "$tmp/out/report.json" "$src/tests/cli/lib" <<'PY' || fail "the animated comparison is inconsistent"
import json, sys
anim, static = sys.argv[1], json.load(open(sys.argv[2]))
sys.path.insert(0, sys.argv[3])
from png import pixels as png, psnr

summary = json.load(open(anim + "/report.json"))
assert summary["fps"] == 10 and [f["frame"] for f in summary["frames"]] == [0, 2], summary
assert [f["dir"] for f in summary["frames"]] == ["frame_0000", "frame_0002"], summary
frames = {k: json.load(open("%s/frame_%04d/report.json" % (anim, k))) for k in (0, 2)}
for k, r in frames.items():
    assert r["frame"] == k and abs(r["time_s"] - k / 10) < 1e-6, r
    assert r["truth"]["self_psnr_db"] is None, r["truth"]
t0 = {x["name"]: x for x in frames[0]["techniques"]}
t2 = {x["name"]: x for x in frames[2]["techniques"]}
# Frame 0 is the rest pose: the same comparison as the static scene's.
ts = {x["name"]: x for x in static["techniques"]}
for name in ("sam", "none"):
    assert abs(t0[name]["psnr_db"] - ts[name]["psnr_db"]) < 1e-3, (name, t0[name], ts[name])
# The pose changed the truth.
truth0, truth2 = png(anim + "/frame_0000/truth.png"), png(anim + "/frame_0002/truth.png")
assert psnr(truth0, truth2) < 35, psnr(truth0, truth2)
# At the bend SAM scores above `none`, and against the truth of its own pose far above the stale
# comparison with the rest pose's truth (whole images).
assert t2["sam"]["psnr_db"] > t2["none"]["psnr_db"] + 3, (t2["sam"], t2["none"])
assert t2["sam"]["psnr_translucency_db"] > t2["none"]["psnr_translucency_db"] + 3, (t2["sam"], t2["none"])
sam2 = png(anim + "/frame_0002/sam.png")
posed, stale = psnr(sam2, truth2), psnr(sam2, truth0)
assert posed > stale + 3, (posed, stale)
print("bent slab, frame 2: PSNR sam %.2f none %.2f dB; whole image against the posed truth %.2f, against the "
      "rest truth %.2f dB; the two truths %.2f dB apart" % (t2["sam"]["psnr_db"], t2["none"]["psnr_db"],
      posed, stale, psnr(truth0, truth2)))
PY
# Without --frames an animated scene compares frame 0 in the single-pose layout, and says how to pick frames.
"$bin/sam_compare" "$tmp/anim.json" -o "$tmp/anim0" --techniques sam 2> "$tmp/anim0_log.txt" \
  || fail "animated scene without --frames: $(cat "$tmp/anim0_log.txt")"
grep -q "comparing frame 0.*--frames LIST" "$tmp/anim0_log.txt" \
  || fail "no note on --frames: $(cat "$tmp/anim0_log.txt")"
[ -s "$tmp/anim0/truth.exr" ] && grep -q '"frame": 0,' "$tmp/anim0/report.json" \
  || fail "frame 0 layout: $(ls "$tmp/anim0")"
# A finished comparison is not overwritten without --force.
"$bin/sam_compare" "$tmp/scene.json" -o "$tmp/out" --techniques none 2> "$tmp/err.txt" && fail "overwrote a report"
grep -q "already holds a report" "$tmp/err.txt" || fail "no refusal message: $(cat "$tmp/err.txt")"
expect_error() { # label args...
  local label=$1; shift
  "$bin/sam_compare" "$@" > /dev/null 2> "$tmp/err.txt" && fail "$label: accepted"
  [ "$(wc -l < "$tmp/err.txt")" -ge 1 ] || fail "$label: no message"
  grep -q "sam_compare" "$tmp/err.txt" || fail "$label: message does not name the tool: $(cat "$tmp/err.txt")"
}
expect_error "unknown technique" "$tmp/scene.json" -o "$tmp/x" --techniques sam,foo
grep -q '"foo"' "$tmp/err.txt" && grep -q "thickness" "$tmp/err.txt" \
  || fail "unknown technique message: $(cat "$tmp/err.txt")"
expect_error "bad sweep" "$tmp/scene.json" -o "$tmp/x" --samples-sweep 3,0
expect_error "--whole-cut, flat map" "$tmp/scene.json" -o "$tmp/x" --whole-cut --map flat
grep -q "without --map flat" "$tmp/err.txt" || fail "--whole-cut --map flat message: $(cat "$tmp/err.txt")"
"$bin/sam_compare" "$tmp/slab.obj" -o "$tmp/x" 2> "$tmp/err.txt" && fail "sam_compare took a bare mesh"
grep -q "needs a scene.*--write-scene" "$tmp/err.txt" || fail "bare mesh: $(cat "$tmp/err.txt")"
expect_error "bad tolerance" "$tmp/scene.json" -o "$tmp/x" --truth-tolerance 0.7
expect_error "missing scene" "$tmp/nope.json" -o "$tmp/x"
expect_error "no -o" "$tmp/scene.json"
grep -q "missing -o DIR" "$tmp/err.txt" || fail "no -o message: $(cat "$tmp/err.txt")"
# The old spelling --out still works, with a warning naming the new one.
"$bin/sam_compare" "$tmp/nope.json" --out "$tmp/x" 2> "$tmp/err.txt"
grep -q "warning: --out is now -o" "$tmp/err.txt" || fail "--out gave no warning: $(cat "$tmp/err.txt")"
expect_error "--frames, static scene" "$tmp/scene.json" -o "$tmp/x" --frames 0,2
grep -q 'scene.json has no "deformers" or "keyframes"' "$tmp/err.txt" \
  || fail "static --frames message: $(cat "$tmp/err.txt")"
expect_error "bad frame" "$tmp/anim.json" -o "$tmp/x" --frames 0,x
grep -q '"0,x"' "$tmp/err.txt" || fail "bad --frames message: $(cat "$tmp/err.txt")"
expect_error "frames out of order" "$tmp/anim.json" -o "$tmp/x" --frames 4,2
grep -q "got 2 after 4" "$tmp/err.txt" || fail "order message: $(cat "$tmp/err.txt")"
expect_error "bad fps" "$tmp/anim.json" -o "$tmp/x" --frames 2 --fps 0
expect_error "--fps alone" "$tmp/anim.json" -o "$tmp/x" --fps 24
expect_error "--frames with a sweep" "$tmp/anim.json" -o "$tmp/x" --frames 2 --samples-sweep 3
[ -e "$tmp/x" ] && fail "a refused run left $tmp/x"
# A run that fails before its first image leaves no output folder.
printf 'SAMFjunk' > "$tmp/bad.sam"
printf '{"sam": "bad.sam", "material": "skin", "scale": {"mm_per_unit": 10}, "resolution": [32, 32]}' > "$tmp/bad.json"
expect_error "corrupted .sam" "$tmp/bad.json" -o "$tmp/badout"
grep -q "bad.sam: truncated" "$tmp/err.txt" || fail "corrupted .sam message: $(cat "$tmp/err.txt")"
[ -e "$tmp/badout" ] && fail "a failed run left $tmp/badout"
"$bin/sam_compare" --help | grep -q "usage: sam_compare" || fail "--help"
echo "ok"
