#!/usr/bin/env bash
# sam_render renders a scene headless (llvmpipe) to EXR + PNG + vertex dump,
# identically twice; bad scenes and options give one error line and no
# output. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
cp "$src/meshes/ear.obj" "$tmp/ear.obj"
cat > "$tmp/scene.json" <<JSON
{"mesh": "ear.obj", "material": "skin", "scale": {"mm_per_unit": 60},
 "lights": [{"type": "point", "position": [0.1, 0.0, -1.2], "intensity": 6.0},
            {"type": "area", "vertices": [[-1,1,1],[1,1,1],[1,1,-1],[-1,1,-1]], "intensity": 0.5, "shadow": false}],
 "resolution": [96, 96]}
JSON
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/a.exr" --png "$tmp/a.png" --dump-vertices "$tmp/a.csv" --passes 3 \
  2> "$tmp/log.txt" || fail "render: $(cat "$tmp/log.txt")"
grep -q "GPU ms.*: irradiance" "$tmp/log.txt" || fail "no pass timings: $(cat "$tmp/log.txt")"
head -c 4 "$tmp/a.exr" | od -An -tx1 | grep -q "76 2f 31 01" || fail "not an EXR"
head -c 8 "$tmp/a.png" | od -An -tx1 | grep -q "89 50 4e 47 0d 0a 1a 0a" || fail "not a PNG"
[ "$(head -1 "$tmp/a.csv")" = "vertex,ld_r,ld_g,ld_b,t_r,t_g,t_b" ] || fail "vertex dump header"
awk -F, 'NR > 1 && $5 > 0 { lit++ } END { exit !(lit > 0) }' "$tmp/a.csv" || fail "no vertex has translucency"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/b.exr" --passes 3 2>/dev/null || fail "second render"
cmp -s "$tmp/a.exr" "$tmp/b.exr" || fail "two renders of the same scene differ"
# The EGL device platform (what a headless NVIDIA driver offers) renders the same picture.
SAM_EGL_DEVICE=0 "$bin/sam_render" "$tmp/scene.json" -o "$tmp/dev.exr" --passes 3 2> "$tmp/dev.txt" \
  || fail "SAM_EGL_DEVICE=0: $(cat "$tmp/dev.txt")"
cmp -s "$tmp/a.exr" "$tmp/dev.exr" || fail "the EGL device's render differs from the surfaceless one"
for bad in 99 x; do
  SAM_EGL_DEVICE=$bad "$bin/sam_render" "$tmp/scene.json" -o "$tmp/bad.exr" 2> "$tmp/bad.txt" \
    && fail "SAM_EGL_DEVICE=$bad rendered"
  grep -q "SAM_EGL_DEVICE is" "$tmp/bad.txt" || fail "SAM_EGL_DEVICE=$bad: $(cat "$tmp/bad.txt")"
  [ -e "$tmp/bad.exr" ] && fail "SAM_EGL_DEVICE=$bad left a file"
done
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/none.exr" --technique none --passes 3 2>/dev/null || fail "technique none"
cmp -s "$tmp/a.exr" "$tmp/none.exr" && fail "technique none looks the same as sam"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/t.exr" --translucency-only 2>/dev/null || fail "--translucency-only"
# The comparison techniques: each gives translucency of its own through the ear.
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/tn.exr" --technique none --translucency-only --diffusion texture 2>/dev/null \
  || fail "technique none, translucency only"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/tr.exr" --technique transmittance --translucency-only 2>/dev/null \
  || fail "technique transmittance"
cmp -s "$tmp/tr.exr" "$tmp/t.exr" && fail "transmittance looks the same as sam"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/tsm.exr" --technique tsm --translucency-only --diffusion texture 2>/dev/null \
  || fail "technique tsm"
cmp -s "$tmp/tsm.exr" "$tmp/tn.exr" && fail "tsm gave no translucency"
printf '{"mesh": "ear.obj", "material": "skin", "scale": {"mm_per_unit": 60}, "technique": "transmittance", "lights": [{"type": "point", "position": [0.1, 0.0, -1.2], "intensity": 6.0}], "resolution": [32, 32]}' > "$tmp/trscene.json"
"$bin/sam_render" "$tmp/trscene.json" -o "$tmp/trs.exr" 2>/dev/null || fail "the scene's technique transmittance"
# Local thickness: measured on load, light through the ear of its own (its T in the dump), twice the same.
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/th.exr" --technique thickness --translucency-only \
  --dump-vertices "$tmp/th.csv" 2> "$tmp/th.txt" || fail "technique thickness: $(cat "$tmp/th.txt")"
cmp -s "$tmp/th.exr" "$tmp/t.exr" && fail "thickness looks the same as sam"
cmp -s "$tmp/th.exr" "$tmp/tn.exr" && fail "thickness gave no translucency"
awk -F, 'NR > 1 && $5 > 0 { lit++ } END { exit !(lit > 0) }' "$tmp/th.csv" || fail "no vertex has thickness translucency"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/th2.exr" --technique thickness --translucency-only 2>/dev/null \
  || fail "technique thickness, again"
cmp -s "$tmp/th.exr" "$tmp/th2.exr" || fail "two thickness renders differ"
sed 's/"technique": "transmittance"/"technique": "thickness"/' "$tmp/trscene.json" > "$tmp/thscene.json"
"$bin/sam_render" "$tmp/thscene.json" -o "$tmp/ths.exr" 2>/dev/null || fail "the scene's technique thickness"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/nd.exr" --diffusion none --passes 3 2>/dev/null || fail "--diffusion none"
cmp -s "$tmp/a.exr" "$tmp/nd.exr" && fail "screen diffusion changed nothing"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/pi.exr" --diffusion preintegrated --passes 3 2>/dev/null \
  || fail "--diffusion preintegrated"
cmp -s "$tmp/pi.exr" "$tmp/nd.exr" && fail "pre-integrated shading changed nothing"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/tx.exr" --diffusion texture --passes 3 2> "$tmp/tx.txt" \
  || fail "--diffusion texture: $(cat "$tmp/tx.txt")"
grep -q warning "$tmp/tx.txt" && fail "the ear has UVs, yet texture space fell back"
cmp -s "$tmp/tx.exr" "$tmp/nd.exr" && fail "texture-space diffusion changed nothing"
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > "$tmp/tet.off"
printf '{"mesh": "tet.off", "material": "skin", "scale": {"mm_per_unit": 10}, "diffusion": "texture", "lights": [{"type": "directional", "direction": [0, -1, 0]}], "resolution": [32, 32]}' > "$tmp/tet.json"
"$bin/sam_render" "$tmp/tet.json" -o "$tmp/tet.exr" 2> "$tmp/tet.txt" || fail "no-UV texture fallback: $(cat "$tmp/tet.txt")"
[ "$(grep -c 'warning: texture-space diffusion falls back to screen space: the mesh has no UVs' "$tmp/tet.txt")" -eq 1 ] \
  || fail "expected one fallback warning: $(cat "$tmp/tet.txt")"
# Two triangles stacked on the same UVs: overlapping charts fall back too.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0.1 0.1\nvt 0.9 0.1\nvt 0.1 0.9\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\n' > "$tmp/stack.obj"
printf '{"mesh": "stack.obj", "material": "skin", "scale": {"mm_per_unit": 10}, "diffusion": "texture", "lights": [{"type": "directional", "direction": [0, -1, 0]}], "resolution": [32, 32]}' > "$tmp/stack.json"
"$bin/sam_render" "$tmp/stack.json" -o "$tmp/stack.exr" 2> "$tmp/stack.txt" || fail "overlap fallback: $(cat "$tmp/stack.txt")"
[ "$(grep -c 'falls back to screen space: .*more than one triangle' "$tmp/stack.txt")" -eq 1 ] \
  || fail "expected one overlap warning: $(cat "$tmp/stack.txt")"
# A real scan's UVs from u = -0.05: the layout moves into the atlas, with a note, and does not fall back.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt -0.05 0.1\nvt 0.9 0.1\nvt -0.05 0.9\nvt 0.99 0.9\nf 1/1 3/3 2/2\nf 1/2 2/4 4/3\n' > "$tmp/past.obj"
sed 's/stack.obj/past.obj/' "$tmp/stack.json" > "$tmp/past.json"
"$bin/sam_render" "$tmp/past.json" -o "$tmp/past.exr" 2> "$tmp/past.txt" || fail "UVs past [0,1]: $(cat "$tmp/past.txt")"
grep -q "falls back" "$tmp/past.txt" && fail "UVs past [0,1] fell back: $(cat "$tmp/past.txt")"
grep -q "the UVs reach past \[0,1\] (u -0.05..0.99, v 0.1..0.9): texture-space diffusion scales them by 0.962" \
  "$tmp/past.txt" || fail "no note on the moved UVs: $(cat "$tmp/past.txt")"
# The diffusion settings: each kernel and optimisation renders, and changes the picture where it should.
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/eq1.exr" --sss-kernel eq1 --sss-samples 9 --passes 3 2>/dev/null || fail "--sss-kernel eq1"
cmp -s "$tmp/eq1.exr" "$tmp/a.exr" && fail "the eq.-1 kernel gave the fit2d picture"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/opt.exr" --diffusion texture --optimize culled,clipped,depth-sized \
  --texels-per-pixel 2 --atlas-size 512 --passes 3 2>/dev/null || fail "--optimize"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/tm.exr" --png "$tmp/r.png" --tonemap reinhard --exposure 1 --passes 3 2>/dev/null \
  || fail "--tonemap"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/tm.exr" --png "$tmp/aces.png" --passes 3 --force 2>/dev/null || fail "aces png"
cmp -s "$tmp/r.png" "$tmp/aces.png" && fail "--tonemap reinhard --exposure 1 gave the default PNG"

expect_error() { # status label args...
  local want=$1 label=$2; shift 2
  "$bin/sam_render" "$@" -o "$tmp/bad.exr" > /dev/null 2> "$tmp/err.txt"
  local rc=$?
  [ $rc -eq "$want" ] || fail "$label: exit $rc, expected $want ($(cat "$tmp/err.txt"))"
  [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "$label: expected one line: $(cat "$tmp/err.txt")"
  ls "$tmp"/bad.exr* > /dev/null 2>&1 && fail "$label: left output"
  return 0
}
# A picture the GL cannot hold fails before the map is built, naming the limit.
start=$(date +%s)
expect_error 1 "16384x16384" "$tmp/scene.json" --size 16384x16384
grep -qE "16384x16384 (picture passes the GL's GL_MAX_[A-Z_]+ of|RGBA32F picture)" "$tmp/err.txt" \
  || fail "16384x16384: $(cat "$tmp/err.txt")"
[ $(( $(date +%s) - start )) -le 10 ] || fail "16384x16384 took $(( $(date +%s) - start )) s to be refused"
printf '{"material": "skin", "scale": {"mm_per_unit": 1}}' > "$tmp/nomesh.json"
printf '{"mesh": "ear.obj", "material": "skin", "scale": {"mm_per_unit": "sixty"}}' > "$tmp/type.json"
printf '{"mesh": "gone.obj", "material": "skin", "scale": {"mm_per_unit": 60}}' > "$tmp/missing.json"
printf '{"mesh": "ear.obj", "material": "skin", "scale": {"mm_per_unit": 60}, "lights": [{"type": "point", "position": [0,0,1], "intensity": -1}]}' > "$tmp/negative.json"
head -c 200 "$tmp/a.exr" > /dev/null
"$bin/sam_build" "$tmp/ear.obj" -o "$tmp/ear.sam" --material skin --mm-per-unit 60 --quiet 2>/dev/null || fail "build"
head -c 300 "$tmp/ear.sam" > "$tmp/broken.sam"
printf '{"sam": "broken.sam"}' > "$tmp/broken.json"
expect_error 2 "bad kernel" "$tmp/scene.json" --sss-kernel gauss
expect_error 2 "even samples" "$tmp/scene.json" --sss-samples 18
expect_error 2 "bad optimisation" "$tmp/scene.json" --optimize culled,fast
expect_error 2 "atlas too small" "$tmp/scene.json" --atlas-size 32
expect_error 2 "bad tonemap" "$tmp/scene.json" --tonemap filmic
expect_error 2 "--cache with --no-cache" "$tmp/scene.json" --cache "$tmp/cache" --no-cache
expect_error 1 "missing key" "$tmp/nomesh.json"
expect_error 1 "wrong type" "$tmp/type.json"
expect_error 1 "missing mesh" "$tmp/missing.json"
expect_error 1 "negative intensity" "$tmp/negative.json"
expect_error 1 "corrupted .sam" "$tmp/broken.json"
expect_error 2 "bad technique" "$tmp/scene.json" --technique dipole
grep -q '"dipole"' "$tmp/err.txt" && grep -q "thickness" "$tmp/err.txt" || fail "bad technique message: $(cat "$tmp/err.txt")"
printf '{"mesh": "ear.obj", "material": "skin", "scale": {"mm_per_unit": 60}, "technique": "thin"}' > "$tmp/badtech.json"
expect_error 1 "the scene's unknown technique" "$tmp/badtech.json"
grep -q 'unknown technique "thin" (expected sam, none, tsm, transmittance, thickness)' "$tmp/err.txt" \
  || fail "scene technique message: $(cat "$tmp/err.txt")"
expect_error 1 "tsm without texture space" "$tmp/scene.json" --technique tsm --diffusion screen
grep -q "tsm technique needs texture-space diffusion" "$tmp/err.txt" || fail "tsm message: $(cat "$tmp/err.txt")"
"$bin/sam_render" "$tmp/tet.json" -o "$tmp/bad.exr" --technique tsm 2> "$tmp/err.txt" && fail "tsm without UVs rendered"
grep -q "tsm technique needs texture-space diffusion, which cannot run: the mesh has no UVs" "$tmp/err.txt" \
  || fail "tsm without UVs message: $(cat "$tmp/err.txt")"
ls "$tmp"/bad.exr* > /dev/null 2>&1 && fail "tsm without UVs left output"
expect_error 2 "bad passes" "$tmp/scene.json" --passes 0
expect_error 2 "bad diffusion" "$tmp/scene.json" --diffusion blur
# A prebuilt .sam renders too, with its recorded material and scale.
printf '{"sam": "ear.sam", "lights": [{"type": "point", "position": [0.1, 0.0, -1.2], "intensity": 6.0}], "resolution": [64, 64]}' > "$tmp/sam.json"
"$bin/sam_render" "$tmp/sam.json" -o "$tmp/s.exr" 2>/dev/null || fail "scene with a .sam"
# A scene pairing a mesh with its prebuilt .sam renders; a .sam built from
# another mesh is refused.
printf '{"mesh": "ear.obj", "sam": "ear.sam", "material": "skin", "scale": {"mm_per_unit": 60}, "resolution": [32, 32]}' > "$tmp/pair.json"
"$bin/sam_render" "$tmp/pair.json" -o "$tmp/pair.exr" 2>/dev/null || fail "mesh with its own .sam"
"$bin/sam_meshgen" sphere -o "$tmp/other.obj" --resolution 8 2>/dev/null || fail "meshgen"
printf '{"mesh": "other.obj", "sam": "ear.sam", "material": "skin", "scale": {"mm_per_unit": 60}}' > "$tmp/other.json"
expect_error 1 ".sam from another mesh" "$tmp/other.json"
grep -q "was built from another mesh (ear.obj" "$tmp/err.txt" || fail "mismatch message: $(cat "$tmp/err.txt")"
# --animate: one numbered picture per frame of the scene's deformers, each a new pose.
cat > "$tmp/anim.json" <<JSON
{"mesh": "ear.obj", "material": "skin", "scale": {"mm_per_unit": 60},
 "lights": [{"type": "point", "position": [0.1, 0.0, -1.2], "intensity": 6.0}],
 "deformers": [{"type": "bend", "axis": [0, 1, 0], "direction": [0, 0, 1], "angle_deg": 60, "length": 1.0,
                "period_s": 0.4}],
 "resolution": [48, 48]}
JSON
"$bin/sam_render" "$tmp/anim.json" -o "$tmp/anim.exr" --png "$tmp/anim.png" --animate 3 --fps 10 2> "$tmp/anim.txt" \
  || fail "--animate: $(cat "$tmp/anim.txt")"
for k in 0000 0001 0002; do
  [ -s "$tmp/anim_$k.exr" ] && [ -s "$tmp/anim_$k.png" ] || fail "--animate wrote no frame $k: $(ls "$tmp")"
done
[ -e "$tmp/anim.exr" ] && fail "--animate also wrote the unnumbered name"
cmp -s "$tmp/anim_0000.exr" "$tmp/anim_0001.exr" && fail "frames 0 and 1 of a bending ear are the same picture"
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/bad.exr" --animate 2 2> "$tmp/err.txt" && fail "--animate without deformers"
grep -q 'has no "deformers" or "keyframes" to animate' "$tmp/err.txt" || fail "no-deformers message: $(cat "$tmp/err.txt")"
# --animate with a keyframe: the same sphere at another size has the rest mesh's topology.
"$bin/sam_meshgen" sphere -o "$tmp/sphere.obj" --resolution 8 --extent 1 > /dev/null 2>&1 || fail "meshgen sphere"
"$bin/sam_meshgen" sphere -o "$tmp/pose.obj" --resolution 8 --extent 1.4 > /dev/null 2>&1 || fail "meshgen pose"
cat > "$tmp/keys.json" <<JSON
{"mesh": "sphere.obj", "material": "skin", "scale": {"mm_per_unit": 30},
 "lights": [{"type": "point", "position": [0.2, 0.3, -2.0], "intensity": 6.0}],
 "keyframes": [{"mesh": "pose.obj", "time_s": 0.1}], "resolution": [32, 32]}
JSON
"$bin/sam_render" "$tmp/keys.json" -o "$tmp/keys.exr" --animate 2 --fps 10 2> "$tmp/keys.txt" \
  || fail "--animate keyframes: $(cat "$tmp/keys.txt")"
[ -s "$tmp/keys_0000.exr" ] && [ -s "$tmp/keys_0001.exr" ] || fail "--animate keyframes wrote no frames: $(ls "$tmp")"
cmp -s "$tmp/keys_0000.exr" "$tmp/keys_0001.exr" && fail "frames 0 and 1 of a growing sphere are the same picture"
"$bin/sam_meshgen" sphere -o "$tmp/pose.obj" --resolution 12 --extent 1.4 --force > /dev/null 2>&1 || fail "meshgen pose 12"
"$bin/sam_render" "$tmp/keys.json" -o "$tmp/bad.exr" --animate 2 2> "$tmp/err.txt" && fail "a keyframe of another topology"
grep -q 'pose.obj: .* vertices, the rest mesh has' "$tmp/err.txt" || fail "topology message: $(cat "$tmp/err.txt")"
expect_error 2 "--animate with --passes" "$tmp/anim.json" --animate 2 --passes 3
# The old spelling --frames still works, with a warning naming --passes.
"$bin/sam_render" "$tmp/scene.json" -o "$tmp/old.exr" --frames 2 2> "$tmp/old.txt" || fail "--frames: $(cat "$tmp/old.txt")"
grep -q "warning: --frames is now --passes" "$tmp/old.txt" || fail "--frames gave no warning: $(cat "$tmp/old.txt")"
expect_error 2 "bad --fps" "$tmp/anim.json" --animate 2 --fps 0
"$bin/sam_render" --help | grep -q "usage: sam_render" || fail "--help"
echo "sam_render cli: ok"
