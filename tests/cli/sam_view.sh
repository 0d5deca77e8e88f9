#!/usr/bin/env bash
# sam_view under Xvfb, driven by --script: switching the technique changes
# the picture, the samples view draws lines, a screenshot's scene file gives
# the same PNG in sam_render, a resize resizes the screenshot, the map is
# cached, and bad input, a missing EXR and a lost context give messages,
# not crashes. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
png() { python3 "$src/tests/cli/lib/png.py" "$@"; }
. "$src/tests/cli/lib/xvfb.sh"
view() { xvfb_run "$tmp" "$bin/sam_view" "$@"; }
"$bin/sam_meshgen" ear -o "$tmp/ear.obj" --resolution 24 2>/dev/null || fail "meshgen"
cat > "$tmp/run.txt" <<SCRIPT
# orbit, zoom, then: final, technique none, samples view, resized
0.0 drag left 160 120 260 120
0.0 scroll 6
0.0 screenshot $tmp/final
0.0 key T
0.0 screenshot $tmp/none
0.0 key T
0.0 key T
0.0 key T
0.0 key D
0.0 key D
0.0 key D
0.0 key V
0.0 key V
0.0 key V
0.0 mouse 100 120
0.0 screenshot $tmp/samples
0.0 resize 200 150
0.3 screenshot $tmp/small
0.3 quit
SCRIPT
view "$tmp/ear.obj" --size 320x240 --cache "$tmp/cache" --truth "$tmp/missing.exr" --script "$tmp/run.txt" \
  2> "$tmp/log.txt" || fail "scripted run: $(cat "$tmp/log.txt")"
grep -q "building the map" "$tmp/log.txt" || fail "no build message: $(cat "$tmp/log.txt")"
grep -q "missing.exr" "$tmp/log.txt" || fail "no message for the missing truth EXR"
for s in final none samples small; do
  for e in exr png json; do [ -s "$tmp/$s.$e" ] || fail "no $s.$e"; done
done
# The technique changes the picture.
[ "$(png differ "$tmp/final.png" "$tmp/none.png")" -gt 200 ] || fail "sam and none look alike"
# The samples view draws lines (yellow) over the same picture.
lines=$(png count "$tmp/samples.png" 255 217 26 40)
[ "$lines" -ge 15 ] || fail "the samples view drew $lines line pixels"
# The screenshot's scene reproduces it in sam_render.
"$bin/sam_render" "$tmp/final.json" -o "$tmp/r.exr" --png "$tmp/r.png" 2>/dev/null || fail "sam_render of final.json"
psnr=$(png psnr "$tmp/final.png" "$tmp/r.png")
[ "$psnr" = inf ] || python3 -c "import sys; sys.exit(float('$psnr') < 40)" || fail "sam_render gives $psnr dB"
"$bin/sam_render" "$tmp/none.json" -o "$tmp/n.exr" --png "$tmp/n.png" 2>/dev/null || fail "sam_render of none.json"
# Without translucency the picture is the front light alone; a staged mesh's viewer tried 25 back lights
# on its runtime first, and one pixel at a shadow's edge came out a level apart (101.8 dB).
psnr=$(png psnr "$tmp/none.png" "$tmp/n.png")
[ "$psnr" = inf ] || python3 -c "import sys; sys.exit(float('$psnr') < 60)" || fail "none.json gives $psnr dB"
head -c 24 "$tmp/small.png" | od -An -tx1 | tr -d ' \n' | grep -q "000000c800000096" || fail "resize: small.png is not 200x150"
# A bending slab on the fixed clock (--fps 10): SPACE plays it, and two
# frames later (t = 0.2 s, the full bend of a 0.8 s period) the picture has changed.
"$bin/sam_meshgen" slab -o "$tmp/slab.obj" --resolution 16 --thickness 0.06 > /dev/null || fail "meshgen slab"
cat > "$tmp/bend.json" <<JSON
{"mesh": "slab.obj", "material": "skin", "scale": {"mm_per_unit": 40},
 "lights": [{"type": "point", "position": [0.0, -1.2, 0.3], "intensity": 2.0, "shadow": true}],
 "deformers": [{"type": "bend", "axis": [1, 0, 0], "direction": [0, 1, 0], "angle_deg": 120, "length": 1.0,
                "period_s": 0.8}],
 "camera": {"position": [0.0, 1.3, 0.6], "target": [0.0, 0.0, 0.0], "fov_deg": 50}}
JSON
printf '0 screenshot %s/rest\n0 key SPACE\n0.2 screenshot %s/bent\n0.2 quit\n' "$tmp" "$tmp" > "$tmp/play.txt"
view "$tmp/bend.json" --size 96x80 --fps 10 --cache "$tmp/cache" --script "$tmp/play.txt" 2> "$tmp/log3.txt" \
  || fail "animated run: $(cat "$tmp/log3.txt")"
[ "$(png differ "$tmp/rest.png" "$tmp/bent.png")" -gt 300 ] || fail "playing did not move the slab"
# A second run uses the cached map; a lost context ends with a message.
printf '0.0 lose-context\n' > "$tmp/lose.txt"
view "$tmp/ear.obj" --size 64x64 --cache "$tmp/cache" --script "$tmp/lose.txt" 2> "$tmp/log2.txt"; rc=$?
[ $rc -eq 1 ] || fail "lost context: exit $rc"
grep -q "using the cached map" "$tmp/log2.txt" || fail "the cache was not used: $(cat "$tmp/log2.txt")"
grep -q "GL context was lost" "$tmp/log2.txt" || fail "no message for the lost context"
# A driver without OpenGL 4.3 core (Mesa told to offer 3.3): one line, exit 1.
MESA_GL_VERSION_OVERRIDE=3.3 view "$tmp/ear.obj" --size 64x64 --cache "$tmp/cache" 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "cannot open a window with OpenGL 4.3 core" "$tmp/err.txt" \
  || fail "GL 3.3 only: exit $rc: $(cat "$tmp/err.txt")"
# The staging's assumptions (one line each, "size:", "material:", ...), then the cache line and the error.
[ "$(grep -v "^xvfb-run:" "$tmp/err.txt" | grep -vc "^sam_view: \(size\|material\|camera\|key light\): ")" -eq 2 ] \
  || fail "GL 3.3 only: expected the cache line and one error: $(cat "$tmp/err.txt")"
grep -q "^sam_view: size: NOT GIVEN; assuming" "$tmp/err.txt" || fail "a bare mesh's size was not said: $(cat "$tmp/err.txt")"
# No display at all: one line, exit 1.
DISPLAY= WAYLAND_DISPLAY= "$bin/sam_view" "$tmp/ear.obj" --cache "$tmp/cache" 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "cannot reach a window system" "$tmp/err.txt" || fail "no display: exit $rc: $(cat "$tmp/err.txt")"
# A bare mesh's up axis is staged before any window: given, it is said so.
DISPLAY= WAYLAND_DISPLAY= "$bin/sam_view" "$tmp/ear.obj" --up x --cache "$tmp/cache" 2> "$tmp/err.txt"
grep -q "^sam_view: camera: up +X (given), from the front (+Z)" "$tmp/err.txt" || fail "--up x: $(cat "$tmp/err.txt")"
"$bin/sam_view" "$tmp/ear.obj" --up sideways 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 2 ] && grep -q -- '--up must be +X, -X, +Y, -Y, +Z or -Z, got "sideways"' "$tmp/err.txt" \
  || fail "--up sideways: exit $rc: $(cat "$tmp/err.txt")"
"$bin/sam_view" "$tmp/bend.json" --up +Z 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q -- "--up is for a bare mesh; .*bend.json is seen from its own camera" "$tmp/err.txt" \
  || fail "--up with a scene: exit $rc: $(cat "$tmp/err.txt")"
# Bad input: one message, exit 1 or 2, no window needed.
"$bin/sam_view" "$tmp/missing.obj" --cache "$tmp/cache" 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "missing.obj" "$tmp/err.txt" || fail "missing mesh: exit $rc: $(cat "$tmp/err.txt")"
printf 'garbage\n' > "$tmp/broken.obj"
"$bin/sam_view" "$tmp/broken.obj" --cache "$tmp/cache" 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "broken mesh: exit $rc"
printf '0.0 key NOPE\n' > "$tmp/bad.txt"
"$bin/sam_view" "$tmp/ear.obj" --script "$tmp/bad.txt" 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "bad.txt:1: unknown key \"NOPE\"" "$tmp/err.txt" || fail "bad script: $(cat "$tmp/err.txt")"
"$bin/sam_view" "$tmp/ear.obj" --size 12x12 2>/dev/null; [ $? -eq 2 ] || fail "bad --size"
"$bin/sam_view" --help | grep -q "usage: sam_view" || fail "--help"
echo "sam_view cli: ok"
