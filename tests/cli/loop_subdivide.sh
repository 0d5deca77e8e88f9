#!/usr/bin/env bash
# meshes/loop_subdivide.py: a step gives V + E vertices and 4F triangles,
# keeps the mesh closed (sam_info: no repairs, no boundary) and its volume
# positive, moves an octahedron's vertices towards a sphere, writes the same
# bytes twice, and refuses an open mesh. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
subdivide=$src/meshes/loop_subdivide.py
# A unit octahedron, outward-facing: 6 vertices, 12 edges, 8 triangles.
printf 'OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n' > "$tmp/octa.off"
printf '3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n' >> "$tmp/octa.off"
python3 "$subdivide" 2 "$tmp/octa.off" "$tmp/octa2.off" || fail "two steps"
# 6 + 12 = 18 vertices, 32 triangles, 48 edges; then 18 + 48 = 66, 128.
[ "$(sed -n 2p "$tmp/octa2.off")" = "66 128 0" ] || fail "counts: $(sed -n 2p "$tmp/octa2.off")"
out=$("$bin/sam_info" "$tmp/octa2.off") || fail "sam_info rejected the result"
grep -q "repairs: *no repairs" <<<"$out" || fail "needed repairs: $out"
grep -q "0 on boundaries" <<<"$out" || fail "not closed: $out"
python3 - "$tmp/octa2.off" <<'PY' || fail "geometry"
import math, sys
lines = open(sys.argv[1]).read().split("\n")
nv, nf, _ = map(int, lines[1].split())
v = [tuple(map(float, l.split())) for l in lines[2:2 + nv]]
f = [tuple(map(int, l.split()[1:])) for l in lines[2 + nv:2 + nv + nf]]
volume = sum(a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
             + a[2] * (b[0] * c[1] - b[1] * c[0]) for a, b, c in ((v[i], v[j], v[k]) for i, j, k in f)) / 6
radii = [math.sqrt(sum(x * x for x in p)) for p in v]
# Loop's scheme shrinks a convex mesh and rounds it: every vertex inside the
# octahedron's circumsphere, closer to a sphere than the octahedron's own
# radii (1 at the corners, 0.577 at the face centres).
assert volume > 0, volume
assert max(radii) < 1 and max(radii) / min(radii) < 1.1, (min(radii), max(radii))
PY
python3 "$subdivide" 2 "$tmp/octa.off" "$tmp/again.off" || fail "second run"
cmp -s "$tmp/octa2.off" "$tmp/again.off" || fail "not deterministic"
head -n 15 "$tmp/octa.off" > "$tmp/open.off"
sed -i '2s/.*/6 7 0/' "$tmp/open.off"
python3 "$subdivide" 1 "$tmp/open.off" "$tmp/x.off" 2> "$tmp/err.txt" && fail "open mesh accepted"
grep -q "closed and manifold" "$tmp/err.txt" || fail "open mesh: $(cat "$tmp/err.txt")"
echo "loop_subdivide cli: ok"
