#!/usr/bin/env bash
# sam_skygen writes half-float EXR environment maps, refuses bad input with
# one line (exit 2 for usage, 1 for failures), never overwrites without
# --force and never leaves a partial file. Args: BIN_DIR SOURCE_DIR TMP_DIR
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
one_line() { [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "$1: expected one error line, got: $(cat "$tmp/err.txt")"; }

for kind in studio outdoor; do
  "$bin/sam_skygen" $kind -o "$tmp/$kind.exr" --width 64 2> "$tmp/err.txt" || fail "$kind: $(cat "$tmp/err.txt")"
  head -c 4 "$tmp/$kind.exr" | od -An -tx1 | grep -q "76 2f 31 01" || fail "$kind: not an EXR"
  # 64 x 32 RGB halves, ZIP-compressed: far more than a header, far less than raw floats.
  size=$(wc -c < "$tmp/$kind.exr")
  [ "$size" -gt 500 ] && [ "$size" -lt $((64 * 32 * 3 * 4 + 4096)) ] || fail "$kind: odd size $size"
done
cmp -s "$tmp/studio.exr" "$tmp/outdoor.exr" && fail "studio and outdoor maps are identical"
# Deterministic: the same arguments give the same bytes.
"$bin/sam_skygen" studio -o "$tmp/again.exr" --width 64 2> /dev/null || fail "second studio run"
cmp -s "$tmp/studio.exr" "$tmp/again.exr" || fail "studio map is not deterministic"

# An existing file survives without --force, and is replaced with it.
cp "$tmp/studio.exr" "$tmp/keep.exr"
"$bin/sam_skygen" outdoor -o "$tmp/studio.exr" --width 64 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "overwrite without --force: exit $rc"
one_line "overwrite without --force"
grep -q -- "--force" "$tmp/err.txt" || fail "overwrite message does not mention --force"
cmp -s "$tmp/studio.exr" "$tmp/keep.exr" || fail "existing file changed without --force"
"$bin/sam_skygen" outdoor -o "$tmp/studio.exr" --width 64 --force 2> /dev/null || fail "--force refused"
cmp -s "$tmp/studio.exr" "$tmp/outdoor.exr" || fail "--force did not replace the file"

# Bad input: one line, usage exit status, no output file.
for args in "sunset -o $tmp/x.exr" "studio" "-o $tmp/x.exr" "studio -o $tmp/x.exr --width 7" \
            "studio -o $tmp/x.exr --width 0" "studio -o $tmp/x.exr --width abc" \
            "studio -o $tmp/x.exr --width 65" "studio -o $tmp/x.exr --width 99999" \
            "studio -o $tmp/x.exr --bogus" "studio outdoor -o $tmp/x.exr" "studio -o"; do
  "$bin/sam_skygen" $args 2> "$tmp/err.txt"; rc=$?
  [ $rc -eq 2 ] || fail "'$args': exit $rc"
  one_line "'$args'"
  [ ! -e "$tmp/x.exr" ] || fail "'$args': output written"
done
grep -q "sunset" <(("$bin/sam_skygen" sunset -o "$tmp/x.exr" 2>&1)) || fail "unknown kind not named"

# A missing directory fails cleanly and leaves nothing behind.
"$bin/sam_skygen" studio -o "$tmp/nodir/x.exr" --width 64 2> "$tmp/err.txt"; rc=$?
[ $rc -eq 1 ] || fail "missing directory: exit $rc"
one_line "missing directory"
[ -z "$(ls -A "$tmp" | grep -v -e '\.exr$' -e '^err\.txt$')" ] || fail "left files behind: $(ls "$tmp")"

"$bin/sam_skygen" --help | grep -q usage || fail "--help"
echo "sam_skygen cli: ok"
