#!/usr/bin/env bash
# sam_render on a bare mesh: one command, no scene file, every assumption
# said; the thin parts glow; the saved scene renders the same picture; a
# turntable; outputs refused before any work. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
png() { python3 "$src/tests/cli/lib/png.py" "$@"; }
cp "$src/meshes/ear.obj" "$tmp/ear.obj"
cache=(--cache "$tmp/cache")
# No size given: said loudly, with each other assumption on a line of its own.
"$bin/sam_render" "$tmp/ear.obj" -o "$tmp/ear.png" --size 96x72 "${cache[@]}" --write-scene "$tmp/ear.json" \
  2> "$tmp/log.txt" || fail "bare mesh: $(cat "$tmp/log.txt")"
for what in "size: NOT GIVEN; assuming" "material: skin (not given)" "camera: up" "key light:" "back light:" \
            "exposure: .* read from the picture" "wrote the scene to"; do
  grep -q "^sam_render: $what" "$tmp/log.txt" || fail "no \"$what\" line: $(cat "$tmp/log.txt")"
done
head -c 8 "$tmp/ear.png" | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "-o ear.png is not a PNG"
grep -q "most translucency of 25 places tried" "$tmp/log.txt" || fail "the ear's back light: $(cat "$tmp/log.txt")"
# A single sheet lets no light through: the back light and the map say so, and why.
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n' > "$tmp/sheet.obj"
"$bin/sam_render" "$tmp/sheet.obj" -o "$tmp/sheet.png" --size 48x36 --size-mm 40 "${cache[@]}" 2> "$tmp/sheet.txt" \
  || fail "a sheet: $(cat "$tmp/sheet.txt")"
grep -q "^sam_render: back light: .*none of the 25 places tried sends any translucency" "$tmp/sheet.txt" \
  || fail "the sheet's back light claims translucency: $(cat "$tmp/sheet.txt")"
grep -q "^sam_render: warning: 100% of the vertices .*single sheet" "$tmp/sheet.txt" \
  || fail "no warning on the sheet's dark map: $(cat "$tmp/sheet.txt")"
[ "$(python3 -c "import sys; sys.path.insert(0, '$src/tests/cli/lib'); import png; r = png.read('$tmp/ear.png'); print(len(r[0]), len(r))")" = "96 72" ] \
  || fail "--size 96x72 not honoured"
# The saved scene names the cached map and the exposure: the same picture, no build.
"$bin/sam_render" "$tmp/ear.json" -o "$tmp/again.png" --size 96x72 "${cache[@]}" 2> "$tmp/again.txt" \
  || fail "the saved scene: $(cat "$tmp/again.txt")"
grep -q "building the map" "$tmp/again.txt" && fail "the saved scene built the map again"
[ "$(png differ "$tmp/ear.png" "$tmp/again.png")" = 0 ] || fail "the saved scene renders another picture"
# The saved scene's map given another material and scale: rendered, with a warning for each in the tool's name.
sed 's/"material":[[:space:]]*"skin"/"material": "marble"/' "$tmp/ear.json" > "$tmp/marble.json"
python3 -c "import json; s = json.load(open('$tmp/marble.json')); s['scale'] = {'size_mm': 500}; json.dump(s, open('$tmp/marble.json', 'w'))"
"$bin/sam_render" "$tmp/marble.json" -o "$tmp/marble.png" --size 48x36 "${cache[@]}" 2> "$tmp/marble.txt" \
  || fail "another material: $(cat "$tmp/marble.txt")"
grep -q "^sam_render: warning: .* was built for skin; the scene renders it as marble" "$tmp/marble.txt" \
  || fail "no material warning: $(cat "$tmp/marble.txt")"
grep -q "^sam_render: warning: .* mm per unit; the scene renders it at" "$tmp/marble.txt" \
  || fail "no scale warning: $(cat "$tmp/marble.txt")"
# A given size is used as given, and the cached map of the first run is not (another scale).
"$bin/sam_render" "$tmp/ear.obj" -o "$tmp/given.exr" --size-mm 70 --material marble --size 48x36 "${cache[@]}" \
  2> "$tmp/given.txt" || fail "--size-mm: $(cat "$tmp/given.txt")"
grep -q "^sam_render: size: 70 mm across (given)" "$tmp/given.txt" || fail "given size: $(cat "$tmp/given.txt")"
grep -q "building the map" "$tmp/given.txt" || fail "another scale read the cached map"
head -c 4 "$tmp/given.exr" | od -An -tx1 | grep -q "76 2f 31 01" || fail "-o given.exr is not an EXR"
# A scene naming its prebuilt map takes the material from the map, and "size_mm" against the map's own
# positions: the picture of the mesh's scene, and another one at twice the size (it was ignored).
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/ear70.sam" --material marble --size-mm 70 --quiet 2>/dev/null \
  || fail "sam_build ear70"
for k in mesh:70 sam:70 sam:140; do
  if [ "${k%%:*}" = mesh ]; then what='"material": "marble"'; else what='"sam": "ear70.sam"'; fi
  printf '{"mesh": "ear.obj", %s, "scale": {"size_mm": %s}, "resolution": [48, 36],
           "lights": [{"type": "point", "position": [0, 0, -2]}]}' "$what" "${k#*:}" > "$tmp/pre.json"
  "$bin/sam_render" "$tmp/pre.json" -o "$tmp/pre_${k/:/_}.png" --exposure 0 "${cache[@]}" 2> "$tmp/pre.txt" \
    || fail "prebuilt scene $k: $(cat "$tmp/pre.txt")"
done
[ "$(png differ "$tmp/pre_mesh_70.png" "$tmp/pre_sam_70.png")" = 0 ] \
  || fail "the prebuilt map renders another picture than its mesh's scene"
[ "$(png differ "$tmp/pre_sam_70.png" "$tmp/pre_sam_140.png")" = 0 ] && fail "size_mm was ignored with a prebuilt map"
# The thin parts glow: with sam, at the same exposure, a part of the picture is clearly brighter than with none.
for t in sam none; do
  "$bin/sam_render" "$tmp/ear.obj" -o "$tmp/$t.png" --technique $t --exposure 0 --size-mm 70 --size 96x72 \
    "${cache[@]}" 2>/dev/null || fail "--technique $t"
done
read -r glow obj <<< "$(png glow "$tmp/sam.png" "$tmp/none.png" 20)"
echo "$glow of $obj object pixels at least 20 levels brighter with sam than with none"
# The ear's thin plate is a fifth of what the camera sees; at least 5% of the object must glow.
[ "$obj" -gt 0 ] && [ $((glow * 20)) -ge "$obj" ] || fail "the thin parts do not glow"
# A turntable: numbered pictures, each another view.
"$bin/sam_render" "$tmp/ear.obj" -o "$tmp/turn.png" --turntable 3 --size-mm 70 --size 48x36 "${cache[@]}" \
  2> "$tmp/turn.txt" || fail "--turntable: $(cat "$tmp/turn.txt")"
for k in 0000 0001 0002; do [ -s "$tmp/turn_$k.png" ] || fail "--turntable wrote no picture $k"; done
grep -q "^sam_render: .*turn_0000.png .. .*turn_0002.png: 48x36, .*3 frames" "$tmp/turn.txt" \
  || fail "the turntable's last line does not name the pictures written: $(tail -1 "$tmp/turn.txt")"
# A mesh wound inside out is turned, and the tool says so in its own name.
awk '/^f / { print $1, $2, $4, $3; next } { print }' "$src/meshes/sphere.obj" > "$tmp/inward.obj"
"$bin/sam_render" "$tmp/inward.obj" -o "$tmp/inward.png" --size-mm 40 --size 48x36 "${cache[@]}" \
  2> "$tmp/inward.txt" || fail "an inward mesh: $(cat "$tmp/inward.txt")"
grep -q "^sam_render: warning: .*inward.obj is closed and faces inward" "$tmp/inward.txt" \
  || fail "the inward warning: $(cat "$tmp/inward.txt")"
[ "$(png differ "$tmp/turn_0000.png" "$tmp/turn_0001.png")" = 0 ] && fail "turntable pictures 0 and 1 are the same"
# The up axis: guessed and said so, or given (either case, the sign optional); the camera and the saved
# scene follow it, and the picture is another one.
grep -q "^sam_render: camera: up +Y (guessed; --up to change), from the front (+Z)" "$tmp/log.txt" \
  || fail "the guessed up axis: $(grep camera "$tmp/log.txt")"
for k in "+X:+Z:1, 0, 0" "-y:-Z:0, -1, 0" "z:-Y:0, 0, 1" "-Z:+Y:0, 0, -1"; do
  IFS=: read -r axis front vec <<< "$k"
  "$bin/sam_render" "$tmp/ear.obj" -o "$tmp/up.png" --up "$axis" --size-mm 70 --size 48x36 --force \
    --write-scene "$tmp/up.json" "${cache[@]}" 2> "$tmp/up.txt" || fail "--up $axis: $(cat "$tmp/up.txt")"
  want=$(echo "$axis" | tr 'xyz' 'XYZ'); [ "${want:0:1}" = - ] || want=+${want#+}
  grep -q "^sam_render: camera: up $want (given), from the front ($front)" "$tmp/up.txt" \
    || fail "--up $axis: $(grep camera "$tmp/up.txt")"
  python3 -c "import json, sys; u = json.load(open('$tmp/up.json'))['camera']['up']; sys.exit(u != [$vec])" \
    || fail "--up $axis: the saved camera's up is not [$vec]: $(cat "$tmp/up.json")"
done
"$bin/sam_render" "$tmp/ear.obj" -o "$tmp/upx.png" --up +X --size-mm 70 --size 48x36 "${cache[@]}" 2>/dev/null \
  || fail "--up +X"
"$bin/sam_render" "$tmp/ear.obj" -o "$tmp/upy.png" --up +Y --size-mm 70 --size 48x36 "${cache[@]}" 2>/dev/null \
  || fail "--up +Y"
[ "$(png differ "$tmp/upx.png" "$tmp/upy.png")" = 0 ] && fail "--up +X renders the picture of --up +Y"
# A scene whose only light is inside the object, and one with no light at all: a warning each.
"$bin/sam_meshgen" sphere -o "$tmp/sphere.obj" --resolution 12 2>/dev/null || fail "meshgen sphere"
printf '{"mesh": "sphere.obj", "material": "skin", "scale": {"size_mm": 30}, "resolution": [32, 32], "lights": [{"type": "point", "position": [0.05, 0, 0]}]}' > "$tmp/inside.json"
"$bin/sam_render" "$tmp/inside.json" -o "$tmp/inside.png" "${cache[@]}" 2> "$tmp/inside.txt" || fail "light inside: $(cat "$tmp/inside.txt")"
grep -q "warning: light 0 (point) at 0.05 0 0 is inside the object" "$tmp/inside.txt" || fail "no inside warning: $(cat "$tmp/inside.txt")"
printf '{"mesh": "sphere.obj", "material": "skin", "scale": {"size_mm": 30}, "resolution": [32, 32]}' > "$tmp/dark.json"
"$bin/sam_render" "$tmp/dark.json" -o "$tmp/dark.png" "${cache[@]}" 2> "$tmp/dark.txt" || fail "no lights: $(cat "$tmp/dark.txt")"
grep -q "warning: .*dark.json has no lights and no environment" "$tmp/dark.txt" || fail "no dark warning: $(cat "$tmp/dark.txt")"
# Outputs that cannot be written, and options that do not fit, are refused at once: one line, nothing built.
expect_error() { # label args...
  local label=$1; shift
  "$bin/sam_render" "$@" "${cache[@]}" > /dev/null 2> "$tmp/err.txt"; local rc=$?
  [ $rc -ne 0 ] || fail "$label: exit 0"
  [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "$label: expected one line: $(cat "$tmp/err.txt")"
  return 0
}
mkdir -p "$tmp/folder"
expect_error "a folder" "$tmp/ear.obj" -o "$tmp/folder"
grep -q "is a folder" "$tmp/err.txt" || fail "folder message: $(cat "$tmp/err.txt")"
expect_error "a missing folder" "$tmp/ear.obj" -o "$tmp/nowhere/x.png"
grep -q "does not exist" "$tmp/err.txt" || fail "missing folder message: $(cat "$tmp/err.txt")"
if ! touch /proc/sam_probe 2> /dev/null; then # permission bits say yes (to root), the folder says no
  expect_error "a folder that takes no file" "$tmp/ear.obj" -o /proc/x.png
  grep -q "cannot write in /proc" "$tmp/err.txt" || fail "a folder that takes no file: $(cat "$tmp/err.txt")"
fi
expect_error "an unknown format" "$tmp/ear.obj" -o "$tmp/x.jpg"
grep -q "must end in .png or .exr" "$tmp/err.txt" || fail "format message: $(cat "$tmp/err.txt")"
expect_error "--size-mm with a scene" "$tmp/ear.json" -o "$tmp/x.png" --size-mm 50
expect_error "--up with a scene" "$tmp/ear.json" -o "$tmp/x.png" --up +Z
grep -q -- "--up are for a bare mesh" "$tmp/err.txt" || fail "--up with a scene: $(cat "$tmp/err.txt")"
expect_error "an unknown --up" "$tmp/ear.obj" -o "$tmp/x.png" --up w
grep -q -- '--up must be +X, -X, +Y, -Y, +Z or -Z, got "w"' "$tmp/err.txt" || fail "--up w: $(cat "$tmp/err.txt")"
expect_error "both sizes" "$tmp/ear.obj" -o "$tmp/x.png" --size-mm 50 --mm-per-unit 2
expect_error "--png beside a PNG" "$tmp/ear.obj" -o "$tmp/x.png" --png "$tmp/y.png"
expect_error "a bad --size" "$tmp/ear.obj" -o "$tmp/x.png" --size 96by72
expect_error "an unknown option" "$tmp/ear.obj" -o "$tmp/x.png" --sizemm 50
grep -q 'unknown option "--sizemm"' "$tmp/err.txt" || fail "unknown option message: $(cat "$tmp/err.txt")"
expect_error "no -o" "$tmp/ear.obj"
grep -q "missing -o" "$tmp/err.txt" || fail "missing -o message: $(cat "$tmp/err.txt")"
ls "$tmp"/x.* "$tmp"/y.* > /dev/null 2>&1 && fail "a refused run left output"
# An existing picture is replaced only with --force (a turntable's numbered ones too), and is checked first.
expect_error "an existing output" "$tmp/ear.obj" -o "$tmp/ear.png"
grep -q "ear.png exists (--force replaces it)" "$tmp/err.txt" || fail "existing output message: $(cat "$tmp/err.txt")"
expect_error "an existing turntable picture" "$tmp/ear.obj" -o "$tmp/turn.png" --turntable 3
"$bin/sam_render" "$tmp/ear.obj" -o "$tmp/ear.png" --size 96x72 "${cache[@]}" --force 2>/dev/null || fail "--force"
echo "sam_render bare mesh cli: ok"
