#!/usr/bin/env bash
# glTF 2.0 from a real exporter: gltfpack (meshoptimizer) turns a textured
# OBJ into a .glb and a .gltf; both load with the OBJ's vertex and triangle
# counts, render the same picture as the OBJ (its texture from the OBJ's
# .mtl, theirs from the base colour), and a damaged file gives one line.
# Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
png() { python3 "$src/tests/cli/lib/png.py" "$@"; }
command -v gltfpack > /dev/null || fail "gltfpack is missing (scripts/deps.sh installs it)"
"$bin/sam_meshgen" ear -o "$tmp/plain.obj" --resolution 24 2>/dev/null || fail "meshgen"
png checker "$tmp/checker.png" 64
{ printf 'mtllib ear.mtl\nusemtl skin\n'; cat "$tmp/plain.obj"; } > "$tmp/ear.obj"
printf 'newmtl skin\nKd 1 1 1\nmap_Kd checker.png\n' > "$tmp/ear.mtl"
(cd "$tmp" && gltfpack -i ear.obj -o ear.glb -noq > gltfpack.txt 2>&1 && gltfpack -i ear.obj -o ear.gltf -noq \
  >> gltfpack.txt 2>&1) || fail "gltfpack: $(cat "$tmp/gltfpack.txt")"
counts() { "$bin/sam_info" "$1" 2>&1 | grep -E "^ *(triangles|render vertices):" | sed 's/(.*//' | tr -s ' '; }
want=$(counts "$tmp/ear.obj")
[ -n "$want" ] || fail "sam_info ear.obj gave no counts"
for f in ear.glb ear.gltf; do
  have=$(counts "$tmp/$f")
  [ "$have" = "$want" ] || fail "$f: counts '$have', the OBJ's '$want'"
done
echo "counts of all three: $want" | tr '\n' ' '; echo
render() { "$bin/sam_render" "$tmp/$1" -o "$tmp/$2.png" --material skin --size-mm 60 --size 160x120 --no-cache \
  2> "$tmp/$2.txt" || fail "sam_render $1: $(cat "$tmp/$2.txt")"; }
render ear.obj obj
render ear.glb glb
render ear.gltf gltf
render plain.obj plain
grep -q "albedo map: .*checker.png (map_Kd of .*ear.obj), 64x64" "$tmp/obj.txt" \
  || fail "the OBJ's texture is not named: $(cat "$tmp/obj.txt")"
grep -q "albedo map: the base colour texture of .*ear.glb" "$tmp/glb.txt" \
  || fail "the GLB's texture is not named: $(cat "$tmp/glb.txt")"
grep -q "albedo map" "$tmp/plain.txt" && fail "an untextured OBJ named a texture: $(cat "$tmp/plain.txt")"
same=$(png psnr "$tmp/obj.png" "$tmp/glb.png")
echo "OBJ against GLB: $same dB; GLB against glTF: $(png psnr "$tmp/glb.png" "$tmp/gltf.png") dB;" \
  "textured against plain OBJ: $(png psnr "$tmp/obj.png" "$tmp/plain.png") dB"
# The vertex order differs (gltfpack reorders), so the maps' Monte Carlo
# noise does; the picture must not.
python3 -c "import sys; sys.exit(0 if float('$same') >= 35 else 1)" || fail "the GLB renders another picture ($same dB)"
[ "$(png psnr "$tmp/glb.png" "$tmp/gltf.png")" = inf ] || fail "the .glb and the .gltf differ"
python3 -c "import sys; sys.exit(0 if float('$(png psnr "$tmp/obj.png" "$tmp/plain.png")') < 30 else 1)" \
  || fail "the texture made no difference"
# A damaged file: one line naming it, exit 1, no picture.
head -c 300 "$tmp/ear.glb" > "$tmp/cut.glb"
"$bin/sam_render" "$tmp/cut.glb" -o "$tmp/cut.png" --size-mm 60 > "$tmp/cut.txt" 2>&1 && fail "a cut .glb rendered"
[ "$(wc -l < "$tmp/cut.txt")" -eq 1 ] && grep -q "cut.glb" "$tmp/cut.txt" || fail "cut .glb: $(cat "$tmp/cut.txt")"
[ -e "$tmp/cut.png" ] && fail "a picture was written for a cut .glb"
# gltfpack's default quantizes the attributes (KHR_mesh_quantization, its
# UVs undone by KHR_texture_transform); -c and -cc compress them with meshopt
# (EXT_meshopt_compression), decoded here, in a .glb and in a .gltf with its
# buffer in a .bin beside it or in a data URI: each has the OBJ's counts and
# renders its picture, texture and all. A .gltf whose .bin is missing, and a
# .glb whose meshopt data is damaged, are refused in one line naming the
# buffer or the buffer view.
(cd "$tmp" && gltfpack -i ear.obj -o quantized.glb > /dev/null 2>&1 && gltfpack -i ear.obj -o packed.glb -c \
  > /dev/null 2>&1 && gltfpack -i ear.obj -o packed_more.glb -cc > /dev/null 2>&1 &&
  gltfpack -i ear.obj -o packed.gltf -c > /dev/null 2>&1) || fail "gltfpack"
python3 - "$tmp/packed.gltf" "$tmp/packed.bin" "$tmp/embedded.gltf" <<'PY' || fail "embedding the .bin"
import base64, json, sys
j = json.load(open(sys.argv[1]))
j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(open(sys.argv[2], "rb").read()).decode()
json.dump(j, open(sys.argv[3], "w"))
PY
for f in quantized.glb packed.glb packed_more.glb packed.gltf embedded.gltf; do
  [ "$(counts "$tmp/$f")" = "$want" ] || fail "$f: counts '$(counts "$tmp/$f")', the OBJ's '$want'"
  render $f ${f%.*}_${f##*.}
  grep -q "albedo map: .*$f" "$tmp/${f%.*}_${f##*.}.txt" || fail "$f: $(cat "$tmp/${f%.*}_${f##*.}.txt")"
  db=$(png psnr "$tmp/obj.png" "$tmp/${f%.*}_${f##*.}.png")
  echo "OBJ against $f: $db dB"
  python3 -c "import sys; sys.exit(0 if float('$db') >= 35 else 1)" || fail "$f renders another picture ($db dB)"
done
mv "$tmp/packed.bin" "$tmp/packed_moved.bin"
"$bin/sam_info" "$tmp/packed.gltf" > "$tmp/packed_gltf.txt" 2>&1 && fail "a .gltf without its .bin was read"
[ "$(wc -l < "$tmp/packed_gltf.txt")" -eq 1 ] && grep -q "packed.gltf: .*buffer 0: .*packed.bin" \
  "$tmp/packed_gltf.txt" || fail ".gltf without its .bin: $(cat "$tmp/packed_gltf.txt")"
python3 - "$tmp/packed.glb" "$tmp/damaged.glb" <<'PY' || fail "damaging the .glb"
import json, struct, sys
d = bytearray(open(sys.argv[1], "rb").read())
n = struct.unpack_from("<I", d, 12)[0]
views = json.loads(bytes(d[20:20 + n]))["bufferViews"]
ext = next(v["extensions"]["EXT_meshopt_compression"] for v in views if "extensions" in v)
at = 20 + ((n + 3) & ~3) + 8 + ext.get("byteOffset", 0)
d[at:at + ext["byteLength"]] = bytes(ext["byteLength"])  # its meshopt data zeroed
open(sys.argv[2], "wb").write(d)
PY
"$bin/sam_info" "$tmp/damaged.glb" > "$tmp/damaged.txt" 2>&1 && fail "a damaged compressed .glb was read"
[ "$(wc -l < "$tmp/damaged.txt")" -eq 1 ] && grep -q "damaged.glb: .*meshopt.*buffer view [0-9]*: its meshopt data does not decode" \
  "$tmp/damaged.txt" || fail "damaged compressed .glb: $(cat "$tmp/damaged.txt")"
# Draco (KHR_draco_mesh_compression), as draco_transcoder writes it from a
# GLB (positions quantized to 11 bits, UVs to 10, normals to 8): a .glb,
# and a .gltf with its .bin beside it, of the ear with normals of its own
# (Draco numbers them before the positions) load with the OBJ's counts and
# normals and render its picture. Damaged Draco data, and an accessor whose
# type or count is not the data's, are refused in one line naming the
# primitive.
command -v draco_transcoder > /dev/null || fail "draco_transcoder is missing (scripts/deps.sh installs it)"
python3 - "$tmp/ear.obj" "$tmp/normals.obj" <<'PY' || fail "writing normals"
import math, sys
lines = open(sys.argv[1]).read().split("\n")
v = [[float(x) for x in l.split()[1:4]] for l in lines if l.startswith("v ")]
faces = [[int(c.split("/")[0]) - 1 for c in l.split()[1:]] for l in lines if l.startswith("f ")]
n = [[0.0] * 3 for _ in v]
for f in faces:
    a, b, c = (v[i] for i in f[:3])
    u, w = [b[k] - a[k] for k in range(3)], [c[k] - a[k] for k in range(3)]
    cross = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
    for i in f:
        n[i] = [n[i][k] + cross[k] for k in range(3)]
out = [l for l in lines if not l.startswith("f ")]
out += ["vn %.6f %.6f %.6f" % tuple(x / (math.sqrt(sum(y * y for y in m)) or 1) for x in m) for m in n]
out += ["f " + " ".join("%s/%s" % (c, c.split("/")[0]) for c in l.split()[1:]) for l in lines if l.startswith("f ")]
open(sys.argv[2], "w").write("\n".join(out) + "\n")
PY
mkdir -p "$tmp/beside"
(cd "$tmp" && gltfpack -i normals.obj -o normals.glb -noq > /dev/null 2>&1 &&
  draco_transcoder -i normals.glb -o draco.glb > /dev/null 2>&1 &&
  draco_transcoder -i normals.glb -o beside/draco.gltf > /dev/null 2>&1) || fail "draco_transcoder"
grep -q KHR_draco_mesh_compression "$tmp/draco.glb" || fail "draco_transcoder wrote no Draco data"
normals_want=$(counts "$tmp/normals.obj")
render normals.obj normals_obj
for f in draco.glb beside/draco.gltf; do
  [ "$(counts "$tmp/$f")" = "$normals_want" ] || fail "$f: counts '$(counts "$tmp/$f")', the OBJ's '$normals_want'"
  "$bin/sam_info" "$tmp/$f" | grep -q "normals from the file" || fail "$f: its normals were not read"
  out=draco_${f##*.}
  render $f $out
  grep -q "albedo map: .*$f" "$tmp/$out.txt" || fail "$f: $(cat "$tmp/$out.txt")"
  db=$(png psnr "$tmp/normals_obj.png" "$tmp/$out.png")
  echo "OBJ against Draco $f: $db dB"
  python3 -c "import sys; sys.exit(0 if float('$db') >= 35 else 1)" || fail "$f renders another picture ($db dB)"
done
python3 - "$tmp/draco.glb" "$tmp/draco_damaged.glb" "$tmp/draco_retyped.glb" "$tmp/draco_recounted.glb" <<'PY' \
  || fail "damaging the Draco .glb"
import json, struct, sys
d = bytearray(open(sys.argv[1], "rb").read())
n = struct.unpack_from("<I", d, 12)[0]
j = json.loads(bytes(d[20:20 + n]))
p = j["meshes"][0]["primitives"][0]
view = j["bufferViews"][p["extensions"]["KHR_draco_mesh_compression"]["bufferView"]]
at = 20 + ((n + 3) & ~3) + 8 + view.get("byteOffset", 0)
damaged = bytearray(d)
damaged[at + 16:at + view["byteLength"]] = bytes(view["byteLength"] - 16)  # all but its header zeroed
open(sys.argv[2], "wb").write(damaged)
def write(path, j):
    text = json.dumps(j).encode()
    text += b" " * (-len(text) % 4)
    rest = d[20 + ((n + 3) & ~3):]
    open(path, "wb").write(d[:8] + struct.pack("<III", 20 + len(text) + len(rest), len(text), 0x4E4F534A) + text + rest)
uv = j["accessors"][p["attributes"]["TEXCOORD_0"]]
uv["componentType"] = 5123  # UVs said to be unsigned shorts
write(sys.argv[3], j)
uv["componentType"] = 5126
j["accessors"][p["attributes"]["NORMAL"]]["count"] = 100  # fewer normals than points
write(sys.argv[4], j)
PY
for f in draco_damaged draco_retyped draco_recounted; do
  "$bin/sam_render" "$tmp/$f.glb" -o "$tmp/$f.png" --size-mm 60 > "$tmp/$f.txt" 2>&1 && fail "$f.glb rendered"
  [ "$(wc -l < "$tmp/$f.txt")" -eq 1 ] && grep -q "$f.glb: mesh 0 primitive 0 (KHR_draco_mesh_compression)" \
    "$tmp/$f.txt" || fail "$f.glb: $(cat "$tmp/$f.txt")"
  [ -e "$tmp/$f.png" ] && fail "a picture was written for $f.glb"
done
grep -q "does not decode" "$tmp/draco_damaged.txt" || fail "damaged Draco data: $(cat "$tmp/draco_damaged.txt")"
grep -q "component type 5123" "$tmp/draco_retyped.txt" || fail "retyped UVs: $(cat "$tmp/draco_retyped.txt")"
grep -q "(NORMAL) has 100 elements, the Draco data of buffer view [0-9]* 384 points" "$tmp/draco_recounted.txt" \
  || fail "recounted normals: $(cat "$tmp/draco_recounted.txt")"
# A file whose materials have two textures reads each on its own faces, as
# an OBJ and as gltfpack's GLB of it: the same picture, and not the one
# of the first texture on every face.
png checker "$tmp/checker2.png" 32 grey
awk 'BEGIN { f = 0 } /^f / && f++ == 200 { print "usemtl other" } { print }' "$tmp/ear.obj" > "$tmp/two.obj"
printf 'newmtl skin\nKd 1 1 1\nmap_Kd checker.png\nnewmtl other\nKd 1 1 1\nmap_Kd checker2.png\n' > "$tmp/ear.mtl"
(cd "$tmp" && gltfpack -i two.obj -o two.glb -noq > /dev/null 2>&1) || fail "gltfpack two.obj"
for f in two.obj two.glb; do
  render $f two_${f##*.}
  grep -q "albedo maps: 2 for the materials of .*$f, each on its own faces, times the albedo" "$tmp/two_${f##*.}.txt" \
    || fail "$f: the two textures are not named: $(cat "$tmp/two_${f##*.}.txt")"
done
render ear.obj one_texture
db=$(png psnr "$tmp/two_obj.png" "$tmp/two_glb.png")
one=$(png psnr "$tmp/two_obj.png" "$tmp/one_texture.png")
echo "two textures, OBJ against GLB: $db dB; against the first texture on every face: $one dB"
python3 -c "import sys; sys.exit(0 if float('$db') >= 35 else 1)" || fail "two.glb renders another picture ($db dB)"
python3 -c "import sys; sys.exit(0 if float('$one') < 35 else 1)" || fail "the second texture is not read ($one dB)"
# With the first material's texture taken away, its faces take its
# colour (white) and the second's the second texture: two maps still.
# With no primitive using the first, the second's texture is the one map.
python3 - "$tmp/two.glb" "$tmp/two_first_plain.glb" "$tmp/two_first_unused.glb" <<'PY' || fail "editing two.glb"
import json, struct, sys
d = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", d, 12)[0]
def write(path, j):
    text = json.dumps(j).encode()
    text += b" " * (-len(text) % 4)
    rest = d[20 + ((n + 3) & ~3):]
    open(path, "wb").write(d[:8] + struct.pack("<III", 20 + len(text) + len(rest), len(text), 0x4E4F534A) + text + rest)
j = json.loads(d[20:20 + n])
del j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]
write(sys.argv[2], j)
j = json.loads(d[20:20 + n])
for mesh in j["meshes"]:
    for p in mesh["primitives"]:
        p["material"] = 1
write(sys.argv[3], j)
PY
render two_first_plain.glb two_first_plain
grep -q "albedo maps: 2 for the materials of .*two_first_plain.glb" "$tmp/two_first_plain.txt" \
  || fail "two_first_plain.glb: not two maps: $(cat "$tmp/two_first_plain.txt")"
render two_first_unused.glb two_first_unused
grep -q "albedo map: the base colour texture of .*two_first_unused.glb, 32x32" "$tmp/two_first_unused.txt" \
  || fail "two_first_unused.glb: not the used material's texture: $(cat "$tmp/two_first_unused.txt")"
printf 'newmtl skin\nKd 1 1 1\nmap_Kd checker.png\n' > "$tmp/ear.mtl"
# A base colour of 8-bit grey (TinyGLTF gives it as RGBA) or 16-bit RGB (cut to
# 8 bits) is read as the OBJ reads the same PNG: the same picture.
for kind in grey rgb16; do
  png checker "$tmp/checker_$kind.png" 64 $kind
  sed "s/checker.png/checker_$kind.png/" "$tmp/ear.mtl" > "$tmp/$kind.mtl"
  sed "s/ear.mtl/$kind.mtl/" "$tmp/ear.obj" > "$tmp/$kind.obj"
  (cd "$tmp" && gltfpack -i $kind.obj -o $kind.glb -noq > /dev/null 2>&1) || fail "gltfpack $kind.obj"
  render $kind.obj ${kind}_obj
  render $kind.glb ${kind}_glb
  grep -q "albedo map: the base colour texture of .*$kind.glb, 64x64" "$tmp/${kind}_glb.txt" \
    || fail "$kind.glb: its texture was not read: $(cat "$tmp/${kind}_glb.txt")"
  db=$(png psnr "$tmp/${kind}_obj.png" "$tmp/${kind}_glb.png")
  echo "$kind texture, OBJ against GLB: $db dB"
  python3 -c "import sys; sys.exit(0 if float('$db') >= 35 else 1)" || fail "$kind.glb renders another picture ($db dB)"
done
# A missing texture is a warning, not a failure.
rm "$tmp/checker.png"
"$bin/sam_render" "$tmp/ear.obj" -o "$tmp/untextured.png" --size-mm 60 --size 64x48 --no-cache 2> "$tmp/missing.txt" \
  || fail "a missing texture stopped the render: $(cat "$tmp/missing.txt")"
grep -q "checker.png" "$tmp/missing.txt" || fail "no warning about the missing texture: $(cat "$tmp/missing.txt")"
echo "PASS"
