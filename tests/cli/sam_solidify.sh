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

"$bin/sam_solidify" --help | grep -q "examples:" || fail "--help"
echo "sam_solidify cli: ok"
