#!/usr/bin/env bash
# sam_preview renders a .sam to a PNG in which the back-lit thin shell
# glows, refuses bad input with one line and leaves no file. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
"$bin/sam_meshgen" ear -o "$tmp/ear.obj" --resolution 24 2>/dev/null || fail "meshgen"
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/ear.sam" --material skin --mm-per-unit 60 --quiet 2>/dev/null || fail "build"
"$bin/sam_preview" "$tmp/ear.sam" -o "$tmp/ear.png" --size 64 2> "$tmp/err.txt" || fail "$(cat "$tmp/err.txt")"
head -c 8 "$tmp/ear.png" | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "not a PNG"
# A different material gives a different picture (the map carries it).
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/marble.sam" --material marble --mm-per-unit 60 --quiet 2>/dev/null || fail "build"
"$bin/sam_preview" "$tmp/marble.sam" -o "$tmp/marble.png" --size 64 2>/dev/null || fail "marble preview"
cmp -s "$tmp/ear.png" "$tmp/marble.png" && fail "skin and marble previews are identical"
head -c 100 "$tmp/ear.sam" > "$tmp/broken.sam"
for args in "$tmp/broken.sam -o $tmp/x.png" "$tmp/missing.sam -o $tmp/x.png" "$tmp/ear.sam -o $tmp/nodir/x.png"; do
  "$bin/sam_preview" $args 2> "$tmp/err.txt"; rc=$?
  [ $rc -eq 1 ] || fail "$args: exit $rc"
  [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "$args: expected one error line: $(cat "$tmp/err.txt")"
  [ ! -e "$tmp/x.png" ] || fail "$args: wrote output"
done
"$bin/sam_preview" "$tmp/ear.sam" -o "$tmp/y.png" --view w 2>/dev/null; [ $? -eq 2 ] || fail "bad --view"
# An existing picture is replaced only with --force.
"$bin/sam_preview" "$tmp/ear.sam" -o "$tmp/ear.png" --size 64 2> "$tmp/err.txt" && fail "replaced without --force"
grep -q "ear.png exists (--force replaces it)" "$tmp/err.txt" || fail "existing output message: $(cat "$tmp/err.txt")"
"$bin/sam_preview" "$tmp/ear.sam" -o "$tmp/ear.png" --size 64 --force 2>/dev/null || fail "--force"
"$bin/sam_preview" --help | grep -q usage || fail "--help"
echo "sam_preview cli: ok"
