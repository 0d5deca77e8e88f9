#!/usr/bin/env bash
# sam_solidify gives a single sheet thickness: what it writes is closed, and
# sam_build finds a back side for every vertex of it where the sheet had
# none (and says so, naming sam_solidify). Bad input gives one line (exit 2
# for usage, 1 for failures), an existing file survives without --force,
# and nothing is written on failure. Args: BIN_DIR SOURCE_DIR TMP_DIR
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
one_line() { [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "$1: expected one error line, got: $(cat "$tmp/err.txt")"; }

# A gently curved 16 x 16-quad leaf, 1 unit across, with UVs.
awk 'BEGIN {
  n = 16
  for (j = 0; j <= n; ++j) for (i = 0; i <= n; ++i) {
    x = i / n - 0.5; y = j / n - 0.5
    printf "v %.6f %.6f %.6f\nvt %.6f %.6f\n", x, y, 0.1 * (x * x + y * y), i / n, j / n
  }
  for (j = 0; j < n; ++j) for (i = 0; i < n; ++i) {
    a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 2; d = a + n + 1
    printf "f %d/%d %d/%d %d/%d\nf %d/%d %d/%d %d/%d\n", a, a, b, b, c, c, a, a, c, c, d, d
  }
}' > "$tmp/leaf.obj"

"$bin/sam_solidify" "$tmp/leaf.obj" -o "$tmp/solid.obj" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt" \
  || fail "solidify: $(cat "$tmp/err.txt")"
grep -q "1 open part 1 mm thick (0.02 units), 0 closed parts kept, 64 rim edges" "$tmp/err.txt" \
  || fail "summary: $(cat "$tmp/err.txt")"
grep -q -- "--mm-per-unit 50" "$tmp/err.txt" || fail "summary does not give the scale"
"$bin/sam_info" "$tmp/solid.obj" > "$tmp/info.txt" 2>&1 || fail "sam_info: $(cat "$tmp/info.txt")"
grep -q "0 on boundaries" "$tmp/info.txt" || fail "solid is not closed: $(cat "$tmp/info.txt")"
grep -q "welded vertices:   578 " "$tmp/info.txt" || fail "solid's vertex count: $(cat "$tmp/info.txt")"
grep -q "attributes:        UVs" "$tmp/info.txt" || fail "UVs lost: $(cat "$tmp/info.txt")"
# PLY too, and the same thickness given through the size.
"$bin/sam_solidify" "$tmp/leaf.obj" -o "$tmp/solid.ply" --thickness-mm 1 --size-mm 71.0 2> "$tmp/err.txt" \
  || fail "solidify to PLY: $(cat "$tmp/err.txt")"
"$bin/sam_info" "$tmp/solid.ply" > "$tmp/info.txt" 2>&1 || fail "sam_info PLY: $(cat "$tmp/info.txt")"
grep -q "0 on boundaries" "$tmp/info.txt" || fail "PLY solid is not closed"

# A textured sheet's albedo goes with an OBJ (its .mtl and PNG, named by
# file name, so the three move together) and reads back pixel for pixel;
# a PLY says it is not carried. Without --force an existing companion
# stops the write before anything is written.
python3 "$src/tests/cli/lib/png.py" checker "$tmp/checker.png" 32
printf 'newmtl leaf\nKd 1 1 1\nmap_Kd checker.png\n' > "$tmp/leaf_tex.mtl"
{ echo "mtllib leaf_tex.mtl"; echo "usemtl leaf"; cat "$tmp/leaf.obj"; } > "$tmp/leaf_tex.obj"
mkdir -p "$tmp/out"
"$bin/sam_solidify" "$tmp/leaf_tex.obj" -o "$tmp/out/tex.obj" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt" \
  || fail "textured solidify: $(cat "$tmp/err.txt")"
grep -q "wrote $tmp/out/tex.mtl and $tmp/out/tex_albedo.png, from .*checker.png (map_Kd of " "$tmp/err.txt" \
  || fail "textured summary: $(cat "$tmp/err.txt")"
grep -q "^mtllib tex.mtl$" "$tmp/out/tex.obj" || fail "the OBJ names no material library"
grep -q "^map_Kd tex_albedo.png$" "$tmp/out/tex.mtl" || fail "the material names no texture"
[ "$(python3 "$src/tests/cli/lib/png.py" psnr "$tmp/checker.png" "$tmp/out/tex_albedo.png")" = inf ] \
  || fail "the texture changed on the way"
mv "$tmp/out" "$tmp/moved"
"$bin/sam_render" "$tmp/moved/tex.obj" -o "$tmp/tex.png" --material skin --mm-per-unit 50 --size 64x48 --no-cache \
  > "$tmp/render.txt" 2>&1 || fail "render of the moved solid: $(cat "$tmp/render.txt")"
grep -q "albedo map: .*tex_albedo.png (map_Kd of .*moved/tex.obj)" "$tmp/render.txt" \
  || fail "the renderer did not take the texture: $(cat "$tmp/render.txt")"
"$bin/sam_solidify" "$tmp/leaf_tex.obj" -o "$tmp/tex.ply" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt" \
  || fail "textured solidify to PLY: $(cat "$tmp/err.txt")"
grep -q "note: .*checker.png (map_Kd of .*) is not carried: a PLY holds none" "$tmp/err.txt" || fail "PLY note: $(cat "$tmp/err.txt")"
touch "$tmp/stop_albedo.png"
"$bin/sam_solidify" "$tmp/leaf_tex.obj" -o "$tmp/stop.obj" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "existing texture without --force: exit $rc"
one_line "existing texture without --force"
[ ! -e "$tmp/stop.obj" ] && [ ! -e "$tmp/stop.mtl" ] && [ ! -s "$tmp/stop_albedo.png" ] \
  || fail "existing texture without --force: something was written"
"$bin/sam_solidify" "$tmp/leaf_tex.obj" -o "$tmp/stop.obj" --thickness-mm 1 --mm-per-unit 50 --force 2> /dev/null \
  && [ -s "$tmp/stop_albedo.png" ] || fail "--force did not write the texture"
touch "$tmp/stop2.mtl"
"$bin/sam_solidify" "$tmp/leaf_tex.obj" -o "$tmp/stop2.obj" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "existing material library without --force: exit $rc"
[ ! -e "$tmp/stop2.obj" ] && [ ! -s "$tmp/stop2.mtl" ] && [ ! -e "$tmp/stop2_albedo.png" ] \
  || fail "existing material library without --force: something was written"
# A name the material lines cannot hold: the OBJ is written without the
# texture, and a note says why.
"$bin/sam_solidify" "$tmp/leaf_tex.obj" -o "$tmp/my leaf.obj" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt" \
  || fail "a name with a blank: $(cat "$tmp/err.txt")"
grep -q "is not carried: .*blanks" "$tmp/err.txt" || fail "a name with a blank: $(cat "$tmp/err.txt")"
[ -s "$tmp/my leaf.obj" ] && [ ! -e "$tmp/my leaf.mtl" ] || fail "a name with a blank: wrong files"
# A glTF's base colour (gltfpack embeds the PNG as it is) goes the same way.
if command -v gltfpack > /dev/null; then
  (cd "$tmp" && gltfpack -i leaf_tex.obj -o leaf_tex.glb -noq > /dev/null) || fail "gltfpack"
  "$bin/sam_solidify" "$tmp/leaf_tex.glb" -o "$tmp/glb.obj" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt" \
    || fail "solidify of a glb: $(cat "$tmp/err.txt")"
  grep -q "from the base colour texture of .*leaf_tex.glb" "$tmp/err.txt" || fail "glb texture: $(cat "$tmp/err.txt")"
  [ "$(python3 "$src/tests/cli/lib/png.py" psnr "$tmp/checker.png" "$tmp/glb_albedo.png")" = inf ] \
    || fail "the glb's texture changed on the way"
fi

# The sheet has no back side, and sam_build names the way out; the solid
# gives every vertex one.
"$bin/sam_build" "$tmp/leaf.obj" -o "$tmp/leaf.sam" --material skin --mm-per-unit 50 --quiet 2> "$tmp/err.txt" \
  || fail "build of the sheet: $(cat "$tmp/err.txt")"
grep -q "100.0% have none" "$tmp/err.txt" || fail "the sheet had a back side: $(cat "$tmp/err.txt")"
grep -q "sam_solidify" "$tmp/err.txt" || fail "the warning does not name sam_solidify"
"$bin/sam_build" "$tmp/solid.obj" -o "$tmp/solid.sam" --material skin --mm-per-unit 50 --quiet 2> "$tmp/err.txt" \
  || fail "build of the solid: $(cat "$tmp/err.txt")"
grep -q " (0.0% have none)" "$tmp/err.txt" || fail "the solid has vertices without a back side: $(cat "$tmp/err.txt")"
grep -q "warning" "$tmp/err.txt" && fail "the solid's build warned: $(cat "$tmp/err.txt")"

# A closed mesh is refused and nothing is written.
"$bin/sam_solidify" "$tmp/solid.obj" -o "$tmp/x.obj" --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "closed mesh: exit $rc"
one_line "closed mesh"
grep -q "is closed" "$tmp/err.txt" || fail "closed mesh: $(cat "$tmp/err.txt")"
[ ! -e "$tmp/x.obj" ] || fail "closed mesh: output written"
# An existing file survives without --force, and is replaced with it.
cp "$tmp/solid.obj" "$tmp/keep.obj"
"$bin/sam_solidify" "$tmp/leaf.obj" -o "$tmp/solid.obj" --thickness-mm 2 --mm-per-unit 50 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "overwrite without --force: exit $rc"
one_line "overwrite without --force"
cmp -s "$tmp/solid.obj" "$tmp/keep.obj" || fail "existing file changed without --force"
"$bin/sam_solidify" "$tmp/leaf.obj" -o "$tmp/solid.obj" --thickness-mm 2 --mm-per-unit 50 --force 2> /dev/null \
  || fail "--force refused"
cmp -s "$tmp/solid.obj" "$tmp/keep.obj" && fail "--force did not replace the file"

# Bad input: one line, usage exit status, no output file.
for args in "$tmp/leaf.obj -o $tmp/x.obj --mm-per-unit 50" \
            "$tmp/leaf.obj -o $tmp/x.obj --thickness-mm 1" \
            "$tmp/leaf.obj -o $tmp/x.obj --thickness-mm 1 --mm-per-unit 50 --size-mm 70" \
            "$tmp/leaf.obj -o $tmp/x.obj --thickness-mm 0 --mm-per-unit 50" \
            "$tmp/leaf.obj -o $tmp/x.obj --thickness-mm abc --mm-per-unit 50" \
            "$tmp/leaf.obj -o $tmp/x.obj --thickness-mm 1e-6 --mm-per-unit 50" \
            "$tmp/leaf.obj -o $tmp/x.obj --thickness-mm 500 --mm-per-unit 50" \
            "$tmp/leaf.obj -o $tmp/x.obj --thickness-mm 1 --mm-per-unit -2" \
            "-o $tmp/x.obj --thickness-mm 1 --mm-per-unit 50" \
            "$tmp/leaf.obj --thickness-mm 1 --mm-per-unit 50 --bogus"; do
  "$bin/sam_solidify" $args 2> "$tmp/err.txt"; rc=$?
  [ $rc -eq 2 ] || fail "'$args': exit $rc"
  one_line "'$args'"
  [ ! -e "$tmp/x.obj" ] || fail "'$args': output written"
done
# Failures: a missing mesh, an output of another kind, a missing folder.
for args in "$tmp/none.obj -o $tmp/x.obj" "$tmp/leaf.obj -o $tmp/x.stl" "$tmp/leaf.obj -o $tmp/nodir/x.obj"; do
  "$bin/sam_solidify" $args --thickness-mm 1 --mm-per-unit 50 2> "$tmp/err.txt"; rc=$?
  [ $rc -eq 1 ] || fail "'$args': exit $rc"
  one_line "'$args'"
  [ ! -e "$tmp/x.obj" ] && [ ! -e "$tmp/x.stl" ] || fail "'$args': output written"
done

"$bin/sam_solidify" --help | grep -q "^examples" || fail "--help"
echo "sam_solidify cli: ok"
