#!/usr/bin/env bash
# A stray triangle far from the object (a scan's speck, a forgotten fin)
# does not move what the tools choose for the object: sam_render sizes and
# frames the ear with a speck beside it as without one, puts its key light
# in the same place and its back light as far and as bright, and says what
# it left out; sam_build's --size-mm measures the ear alone. (Which place
# on the back light's rings wins may differ: the speck changes the map's
# tree and the shadow maps' bounds a little, and near-ties flip.)
# Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
"$bin/sam_meshgen" ear -o "$tmp/ear.obj" --resolution 24 2>/dev/null || fail "meshgen"
python3 - "$tmp/ear.obj" "$tmp/speck.obj" <<'PY' || fail "adding the speck"
import sys
lines = open(sys.argv[1]).read().splitlines()
v = [[float(x) for x in l.split()[1:4]] for l in lines if l.startswith("v ")]
lo = [min(p[c] for p in v) for c in range(3)]
hi = [max(p[c] for p in v) for c in range(3)]
size = max(hi[c] - lo[c] for c in range(3))
at = [hi[0] + 0.8 * size, hi[1] + 0.4 * size, lo[2]]
s = 0.01 * size
n = len(v)
out = lines + [f"v {at[0]} {at[1]} {at[2]}", f"v {at[0] + s} {at[1]} {at[2]}", f"v {at[0]} {at[1] + s} {at[2]}",
               f"f {n + 1} {n + 2} {n + 3}"]
open(sys.argv[2], "w").write("\n".join(out) + "\n")
PY
render() { "$bin/sam_render" "$tmp/$1.obj" -o "$tmp/$1.png" --material skin --size-mm 60 --size 160x120 --no-cache \
  --write-scene "$tmp/$1.json" 2> "$tmp/$1.txt" || fail "sam_render $1: $(cat "$tmp/$1.txt")"; }
render ear
render speck
grep -q "framing and size: 1 loose piece (3 vertices, .* of the surface) outside the object left out" "$tmp/speck.txt" \
  || fail "no line on the speck: $(cat "$tmp/speck.txt")"
grep -q "loose piece" "$tmp/ear.txt" && fail "a speck named where there is none: $(cat "$tmp/ear.txt")"
python3 - "$tmp/ear.json" "$tmp/speck.json" <<'PY' || fail "the speck moved the staging"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
def close(x, y, what, tol=1e-4):
    for u, w in zip(x, y):
        if abs(u - w) > tol * max(1.0, abs(u)):
            sys.exit(f"{what}: {x} against {y}")
close([a["scale"]["mm_per_unit"]], [b["scale"]["mm_per_unit"]], "scale")
close(a["camera"]["position"], b["camera"]["position"], "camera")
# The key light stays; the back light keeps its distance and intensity
# (which of the places on its ring scores best may differ a little: the
# speck still counts in the shadow maps' bounds).
key_a, back_a = a["lights"]
key_b, back_b = b["lights"]
close(key_a["position"], key_b["position"], "key light")
centre = [0.5 * (u + w) for u, w in zip(a["camera"]["target"], a["camera"]["target"])]
dist = lambda l: sum((p - c) ** 2 for p, c in zip(l["position"], centre)) ** 0.5
close([dist(back_a), back_a["intensity"]], [dist(back_b), back_b["intensity"]], "back light distance and intensity")
PY
"$bin/sam_build" "$tmp/speck.obj" -o "$tmp/speck.sam" --material skin --size-mm 60 --samples 4 --flat \
  2> "$tmp/build.txt" || fail "sam_build: $(cat "$tmp/build.txt")"
grep -q "size-mm measures the object without 1 loose piece" "$tmp/build.txt" \
  || fail "sam_build does not say what --size-mm measures: $(cat "$tmp/build.txt")"
"$bin/sam_info" "$tmp/speck.obj" | grep -q "loose specks: *1 piece (3 vertices, .*) outside the object; its size (--size-mm) is the diagonal" \
  || fail "sam_info does not name the speck: $("$bin/sam_info" "$tmp/speck.obj")"
"$bin/sam_info" "$tmp/ear.obj" | grep -q "loose specks" && fail "sam_info names a speck the ear has not"
"$bin/sam_info" "$tmp/speck.sam" | grep -q "loose specks: *1 piece" || fail "sam_info does not name the map's speck"
echo "PASS"
