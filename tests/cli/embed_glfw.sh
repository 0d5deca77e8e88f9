#!/usr/bin/env bash
# examples/embed_glfw under Xvfb: a program with its own window, shader and
# vertex animation adds SAM's translucency in at most 30 lines of SAM
# calls, and where the back light shines through the shell its pixels are
# brighter than the same program's without SAM. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
png() { python3 "$src/tests/cli/lib/png.py" "$@"; }
example=$src/examples/embed_glfw.c
calls=$(( $(awk '/SAM: a map/,/end of SAM setup/' "$example" | grep -c 'sam_') + \
          $(awk '/SAM: follow the pose/,/end of SAM per frame/' "$example" | grep -c 'sam_') + \
          $(grep -c 'sam_runtime_destroy' "$example") ))
echo "embed_glfw.c: $calls lines with SAM calls"
[ "$calls" -gt 0 ] && [ "$calls" -le 30 ] || fail "$calls lines of SAM calls (at most 30)"
. "$src/tests/cli/lib/xvfb.sh"
run() { xvfb_run "$tmp" "$bin/embed_glfw" "$@"; }
run --frames 12 --size 320x240 --screenshot "$tmp/sam.png" > "$tmp/sam.txt" 2>&1 || fail "with SAM: $(cat "$tmp/sam.txt")"
run --frames 12 --size 320x240 --screenshot "$tmp/none.png" --no-sam > "$tmp/none.txt" 2>&1 \
  || fail "without SAM: $(cat "$tmp/none.txt")"
# Skin lets red through: luminance, a sixth red, rises 10 levels where red rises about 50.
read -r glow obj <<< "$(png glow "$tmp/sam.png" "$tmp/none.png" 10)"
echo "$glow of $obj object pixels at least 10 levels brighter with SAM"
# The shell is thin all over and lit from behind: most of it glows.
[ "$obj" -gt 1000 ] && [ $((glow * 4)) -ge "$obj" ] || fail "the back light does not shine through"
run --frames 1 --bogus > "$tmp/bad.txt" 2>&1 && fail "an unknown option was accepted"
grep -q "usage: embed_glfw" "$tmp/bad.txt" || fail "no usage line: $(cat "$tmp/bad.txt")"
echo "PASS"
