#!/usr/bin/env bash
# sam_meshgen: every shape in OBJ and PLY loads in sam_info with no repairs;
# bad options exit 2 with one line; existing files need --force; the
# committed meshes/perforated.obj is the shape's defaults. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
for shape in sphere slab torus ear knot blobs perforated; do
  for ext in obj ply; do
    "$bin/sam_meshgen" $shape -o "$tmp/$shape.$ext" --resolution 24 2> "$tmp/err.txt" \
      || fail "$shape.$ext: $(cat "$tmp/err.txt")"
    out=$("$bin/sam_info" "$tmp/$shape.$ext") || fail "$shape.$ext rejected by sam_info"
    grep -q "repairs: *no repairs" <<<"$out" || fail "$shape.$ext needed repairs: $out"
    grep -q "0 on boundaries" <<<"$out" || fail "$shape.$ext is not closed: $out"
  done
done
"$bin/sam_meshgen" sphere -o "$tmp/sphere.obj" 2> /dev/null; [ $? -ne 0 ] || fail "overwrote without --force"
"$bin/sam_meshgen" sphere -o "$tmp/sphere.obj" --force --resolution 8 2> /dev/null || fail "--force"
"$bin/sam_meshgen" cube -o "$tmp/c.obj" 2> "$tmp/err.txt"; [ $? -eq 2 ] || fail "unknown shape exit"
[ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "unknown shape: one line expected"
"$bin/sam_meshgen" sphere -o "$tmp/r.obj" --resolution -3 2> /dev/null; [ $? -ne 0 ] || fail "negative resolution"
"$bin/sam_meshgen" sphere -o "$tmp/r.obj" --resolution 2 2> "$tmp/err.txt"; [ $? -eq 2 ] || fail "resolution 2: exit $?"
grep -q "resolution 2 out of range" "$tmp/err.txt" || fail "resolution 2: $(cat "$tmp/err.txt")"
[ ! -e "$tmp/r.obj" ] || fail "partial file left"
"$bin/sam_meshgen" --help | grep -q ear || fail "--help"
# compare_perforated.json's mesh: regenerate it with this command when the shape changes.
"$bin/sam_meshgen" perforated -o "$tmp/perforated_default.obj" 2> /dev/null || fail "perforated defaults"
cmp -s "$tmp/perforated_default.obj" "$src/meshes/perforated.obj" \
  || fail "meshes/perforated.obj differs from: sam_meshgen perforated -o meshes/perforated.obj"
echo "sam_meshgen cli: ok"
