#!/usr/bin/env bash
# sam_profile_image writes a PNG for presets and profile files, refuses bad
# input with one line, and never leaves a partial file. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
for m in skin marble ketchup; do
  "$bin/sam_profile_image" $m -o "$tmp/$m.png" --size 64 2> "$tmp/err.txt" || fail "$m: $(cat "$tmp/err.txt")"
  head -c 8 "$tmp/$m.png" | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "$m: not a PNG"
done
# Different materials give different images.
cmp -s "$tmp/skin.png" "$tmp/marble.png" && fail "skin and marble images are identical"
"$bin/sam_profile_image" unobtainium -o "$tmp/x.png" 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "unknown material: exit $rc"
[ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "unknown material: expected one error line"
[ ! -e "$tmp/x.png" ] || fail "output written for a bad material"
"$bin/sam_profile_image" skin -o "$tmp/nodir/x.png" 2> /dev/null && fail "missing directory accepted"
ls "$tmp/nodir" 2>/dev/null && fail "left files behind"
"$bin/sam_profile_image" skin -o "$tmp/y.png" --size 9 2> /dev/null; [ $? -eq 2 ] || fail "bad --size accepted"
# An existing picture is replaced only with --force.
"$bin/sam_profile_image" skin -o "$tmp/again.png" --size 64 2>/dev/null || fail "first write"
"$bin/sam_profile_image" skin -o "$tmp/again.png" --size 64 2> "$tmp/err.txt" && fail "replaced without --force"
grep -q "again.png exists (--force replaces it)" "$tmp/err.txt" || fail "existing output message: $(cat "$tmp/err.txt")"
"$bin/sam_profile_image" skin -o "$tmp/again.png" --size 64 --force 2>/dev/null || fail "--force"
"$bin/sam_profile_image" --help | grep -q usage || fail "--help"
echo "sam_profile_image cli: ok"
