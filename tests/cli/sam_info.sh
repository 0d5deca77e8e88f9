#!/usr/bin/env bash
# sam_info: summaries of valid meshes and .sam files, one error line and exit
# status 1 for bad ones, 2 for bad usage. Args: BIN_DIR SOURCE_DIR TMP_DIR
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > "$tmp/tet.obj"
out=$("$bin/sam_info" --mm-per-unit 10 "$tmp/tet.obj") || fail "valid mesh rejected"
grep -q "triangles: *4" <<<"$out" || fail "no triangle count in: $out"
grep -q "welded vertices: *4" <<<"$out" || fail "no welded count in: $out"
grep -q "mm^2" <<<"$out" || fail "fan areas not in mm^2: $out"
grep -q "orientation" <<<"$out" && fail "an outward tetrahedron said to face inward: $out"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n' > "$tmp/tet_in.obj"
out=$("$bin/sam_info" "$tmp/tet_in.obj") || fail "inward mesh rejected"
grep -q "orientation: *closed and facing inward" <<<"$out" || fail "an inward tetrahedron not named: $out"
grep -q "precision" <<<"$out" && fail "a tetrahedron at the origin warned of: $out"
# The same 4e6 units away, where floats are 0.25 apart: said, and by
# sam_build too (which still builds it).
printf 'v 4e6 0 0\nv 4000001 0 0\nv 4e6 1 0\nv 4e6 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > "$tmp/tet_far.obj"
out=$("$bin/sam_info" "$tmp/tet_far.obj") || fail "far mesh rejected"
grep -q "precision: *the mesh lies 4e+06 units from its origin" <<<"$out" || fail "far mesh not warned of: $out"
"$bin/sam_build" "$tmp/tet_far.obj" -o "$tmp/tet_far.sam" --material skin --mm-per-unit 1 --quiet 2> "$tmp/far.log" \
  || fail "far mesh not built: $(cat "$tmp/far.log")"
grep -q "warning: .*tet_far.obj lies 4e+06 units from its origin" "$tmp/far.log" || fail "sam_build: $(cat "$tmp/far.log")"

# A .sam file from the container's seed corpus.
sam=$(ls "$src"/fuzz/corpus/samfile/*.sam 2>/dev/null | head -1)
[ -n "$sam" ] || fail "no seed .sam file in fuzz/corpus/samfile"
out=$("$bin/sam_info" "$sam") || fail "valid .sam rejected: $out"
grep -q "SAM v[12]" <<<"$out" || fail "no SAM header in: $out"
grep -q "samples per vertex" <<<"$out" || fail "no sample count in: $out"

# Scenes and material profiles.
cat > "$tmp/scene.json" <<JSON
{"mesh": "tet.obj", "material": "marble", "scale": {"mm_per_unit": 10},
 "lights": [{"type": "point", "position": [0, 3, 0]}, {"type": "directional", "direction": [0, -1, 0]}]}
JSON
out=$("$bin/sam_info" "$tmp/scene.json") || fail "valid scene rejected"
grep -q "lights: *2 (1 point, 0 spot, 1 directional, 0 area)" <<<"$out" || fail "scene lights: $out"
out=$("$bin/sam_info" "$src/tests/data/profile_jade.json" "$src/tests/data/profile_gaussians.txt") \
  || fail "valid profiles rejected"
grep -q "8-Gaussian fit" <<<"$out" || fail "profile summary: $out"
printf '{"mesh": "tet.obj", "material": "marble", "scale": {"mm_per_unit": 10}, "lihgts": []}' > "$tmp/typo.json"
printf '{"type": "dipole", "sigma_s_prime": [1, 1, 1], "sigma_a": [0, 0, -1], "eta": 1.3}' > "$tmp/badprofile.json"

# Bad inputs: exit 1, exactly one stderr line naming the file, no stdout.
printf 'v 0 0 0\n' > "$tmp/nofaces.obj"
head -c 40 "$sam" > "$tmp/truncated.sam"
: > "$tmp/empty.off"
for bad in "$tmp/missing.obj" "$tmp/nofaces.obj" "$tmp/truncated.sam" "$tmp/empty.off" \
           "$tmp/typo.json" "$tmp/badprofile.json"; do
  "$bin/sam_info" "$bad" > "$tmp/out.txt" 2> "$tmp/err.txt"
  rc=$?
  [ $rc -eq 1 ] || fail "$bad: exit status $rc, expected 1"
  [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "$bad: expected one error line, got: $(cat "$tmp/err.txt")"
  grep -q "$(basename "$bad")" "$tmp/err.txt" || fail "$bad: error does not name the file: $(cat "$tmp/err.txt")"
  [ ! -s "$tmp/out.txt" ] || fail "$bad: printed a summary for a bad file"
done

# One bad file among good ones still fails, and the good one is summarised.
"$bin/sam_info" "$tmp/tet.obj" "$tmp/missing.obj" > "$tmp/out.txt" 2>/dev/null
[ $? -eq 1 ] || fail "mixed good/bad files should exit 1"
grep -q "tet.obj: mesh" "$tmp/out.txt" || fail "good file not summarised"

# sam_info says of a scene exactly what sam_render would: the same first
# error for a scene without an object, a scale that is 0 as a float, and a
# mesh given as the map.
printf '{"lights": [{"type": "directional", "direction": [0, -1, 0]}]}' > "$tmp/no_object.json"
printf '{"mesh": "tet.obj", "material": "marble", "scale": {"mm_per_unit": 1e-300}}' > "$tmp/tiny.json"
printf 'SAMF' > "$tmp/tet.sam"
printf '{"mesh": "tet.sam", "material": "marble", "scale": {"mm_per_unit": 10}}' > "$tmp/swapped.json"
for scene in no_object tiny swapped; do
  "$bin/sam_info" "$tmp/$scene.json" > /dev/null 2> "$tmp/info.txt" && fail "sam_info accepted $scene.json"
  "$bin/sam_render" "$tmp/$scene.json" -o "$tmp/$scene.png" > /dev/null 2> "$tmp/render.txt" \
    && fail "sam_render accepted $scene.json"
  [ "$(sed 's/^sam_info: //' "$tmp/info.txt")" = "$(sed 's/^sam_render: //' "$tmp/render.txt")" ] \
    || fail "$scene.json: sam_info says '$(cat "$tmp/info.txt")', sam_render '$(cat "$tmp/render.txt")'"
done

# Keyframes: each must have the rest mesh's topology; sam_info loads them
# and says what sam_render would.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1.2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > "$tmp/tet_pose.obj"
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nf 1 4 3 2\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n' > "$tmp/pyramid.obj"
for pose in tet_pose pyramid; do
  printf '{"mesh": "tet.obj", "material": "marble", "scale": {"mm_per_unit": 10}, "keyframes": [{"mesh": "%s.obj", "time_s": 1}]}' \
    "$pose" > "$tmp/kf_$pose.json"
done
out=$("$bin/sam_info" "$tmp/kf_tet_pose.json") || fail "a keyframe of the rest mesh's topology rejected: $out"
grep -q "keyframes: *1, each of the rest mesh's topology" <<<"$out" || fail "keyframes: $out"
"$bin/sam_info" "$tmp/kf_pyramid.json" > /dev/null 2> "$tmp/info.txt" && fail "sam_info accepted a keyframe of another mesh"
"$bin/sam_render" "$tmp/kf_pyramid.json" -o "$tmp/kf.png" --animate 2 > /dev/null 2> "$tmp/render.txt" \
  && fail "sam_render accepted a keyframe of another mesh"
grep -q "pyramid.obj: 5 vertices, the rest mesh has 4" "$tmp/info.txt" \
  && [ "$(sed 's/^sam_info: //' "$tmp/info.txt")" = "$(grep -v '^sam_render: [a-z ]*:' "$tmp/render.txt" | sed 's/^sam_render: //' | tail -1)" ] \
  || fail "keyframe of another mesh: sam_info says '$(cat "$tmp/info.txt")', sam_render '$(cat "$tmp/render.txt")'"

# A picture the GL cannot hold: sam_info checks it as sam_render does.
sed 's/"mm_per_unit": 10}/"mm_per_unit": 10}, "resolution": [16384, 16384]/' "$tmp/scene.json" > "$tmp/huge.json"
"$bin/sam_info" "$tmp/huge.json" > "$tmp/out.txt" 2> "$tmp/info.txt" && fail "sam_info accepted a 16384x16384 picture"
"$bin/sam_render" "$tmp/huge.json" -o "$tmp/huge.png" > /dev/null 2> "$tmp/render.txt" && fail "sam_render accepted it"
[ ! -s "$tmp/out.txt" ] && [ "$(sed 's/^sam_info: [^ ]*huge.json: //' "$tmp/info.txt")" = "$(sed 's/^sam_render: //' "$tmp/render.txt")" ] \
  || fail "16384x16384: sam_info says '$(cat "$tmp/info.txt")', sam_render '$(cat "$tmp/render.txt")'"

"$bin/sam_info" --help | grep -q "usage: sam_info" || fail "--help"
"$bin/sam_info" > /dev/null 2>&1; [ $? -eq 2 ] || fail "no arguments should exit 2"
"$bin/sam_info" --bogus x > /dev/null 2>&1; [ $? -eq 2 ] || fail "unknown option should exit 2"
"$bin/sam_info" --mm-per-unit -1 "$tmp/tet.obj" > /dev/null 2>&1; [ $? -eq 2 ] || fail "negative scale should exit 2"
echo "sam_info cli: ok"
