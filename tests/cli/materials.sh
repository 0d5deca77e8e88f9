#!/usr/bin/env bash
# Materials as artists and measurements give them: the example Burley
# materials (albedo plus a mean free path, or a scatter radius, per channel)
# and the measured table load with their fit error, preview (labelled
# curve, back-lit sphere and wedge), build and render; a broken one gives
# one line. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
png() { python3 "$src/tests/cli/lib/png.py" "$@"; }
for m in skin_burley jade_radius skin_table; do
  "$bin/sam_info" "$src/scenes/materials/$m.json" > "$tmp/$m.txt" 2>&1 || fail "sam_info $m: $(cat "$tmp/$m.txt")"
  grep -q "fitted to its source (a burley or table material): at most" "$tmp/$m.txt" \
    || fail "sam_info $m gives no fit error: $(cat "$tmp/$m.txt")"
done
# The preview: 2N x 3N/2; the back-lit jade sphere (centre of the bottom-left
# quarter) glows green, and the wedge (bottom right) darkens as it thickens.
"$bin/sam_profile_image" "$src/scenes/materials/jade_radius.json" -o "$tmp/jade.png" --size 256 2> "$tmp/p.txt" \
  || fail "sam_profile_image: $(cat "$tmp/p.txt")"
[ "$(png size "$tmp/jade.png")" = 512x384 ] || fail "preview size $(png size "$tmp/jade.png")"
read -r r g b <<< "$(png at "$tmp/jade.png" 128 328)"
[ "$g" -gt "$r" ] && [ "$g" -gt "$b" ] && [ "$g" -gt 40 ] || fail "the jade sphere is not green: $r $g $b"
read -r r1 g1 b1 <<< "$(png at "$tmp/jade.png" 290 340)"
read -r r2 g2 b2 <<< "$(png at "$tmp/jade.png" 490 340)"
[ "$g1" -gt "$g2" ] || fail "the wedge does not darken with thickness: $g1 then $g2"
echo "jade: sphere centre $r $g $b, wedge $g1 -> $g2 (green)"
# Build and render a sphere in the artist's skin, and in the jade given by radius.
"$bin/sam_meshgen" sphere -o "$tmp/ball.obj" --resolution 16 2> /dev/null || fail "meshgen"
for m in skin_burley jade_radius; do
  "$bin/sam_render" "$tmp/ball.obj" -o "$tmp/ball_$m.png" --material "$src/scenes/materials/$m.json" --size-mm 12 \
    --size 96x96 --no-cache 2> "$tmp/r.txt" || fail "sam_render $m: $(cat "$tmp/r.txt")"
done
[ "$(png psnr "$tmp/ball_skin_burley.png" "$tmp/ball_jade_radius.png")" != inf ] || fail "two materials, one picture"
# A broken material: one line naming the file and the key, exit 1.
printf '{"type": "burley", "albedo": [0.8, 0.5, 0.4], "scatter_radius": [1, 0, 1]}' > "$tmp/bad.json"
"$bin/sam_profile_image" "$tmp/bad.json" -o "$tmp/bad.png" 2> "$tmp/bad.txt"; rc=$?
[ $rc -eq 1 ] && [ "$(wc -l < "$tmp/bad.txt")" -eq 1 ] && grep -q "bad.json.*scatter_radius\[1\]" "$tmp/bad.txt" \
  || fail "bad material (exit $rc): $(cat "$tmp/bad.txt")"
[ -e "$tmp/bad.png" ] && fail "a picture for a bad material"
echo "PASS"
