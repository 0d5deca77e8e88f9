#!/usr/bin/env bash
# A mesh whose vertices carry colours (a coloured scan): a binary PLY's
# red, green and blue bytes, an OBJ's "v x y z r g b", a glTF's COLOR_0
# (linear). Each is named among the tools' assumptions and renders the same
# picture, another than the uncoloured mesh's; a scene's "vertex_colors":
# false renders the uncoloured picture. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
png() { python3 "$src/tests/cli/lib/png.py" "$@"; }
at_least() { python3 -c "import sys; sys.exit(0 if float('$1') >= $2 else 1)"; }
"$bin/sam_meshgen" ear -o "$tmp/ear.obj" --resolution 24 2>/dev/null || fail "meshgen"
python3 - "$tmp" <<'PY' || fail "writing the coloured meshes"
import base64, json, struct, sys
tmp = sys.argv[1]
v, faces = [], []
for line in open(tmp + "/ear.obj"):
    w = line.split()
    if w and w[0] == "v": v.append([float(x) for x in w[1:4]])
    elif w and w[0] == "f": faces.append([int(c.split("/")[0]) - 1 for c in w[1:]])
lo, hi = min(p[0] for p in v), max(p[0] for p in v)
# sRGB bytes: orange on one side, blue on the other.
rgb = [(round(255 * (1 - a)), 153, round(255 * a)) for a in ((p[0] - lo) / (hi - lo) for p in v)]
with open(tmp + "/plain.obj", "w") as f:
    f.writelines("v %r %r %r\n" % tuple(p) for p in v)
    f.writelines("f %s\n" % " ".join(str(i + 1) for i in c) for c in faces)
with open(tmp + "/colors.obj", "w") as f:
    f.writelines("v %r %r %r %r %r %r\n" % (*p, *(x / 255 for x in c)) for p, c in zip(v, rgb))
    f.writelines("f %s\n" % " ".join(str(i + 1) for i in c) for c in faces)
head = ("ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
body = b"".join(struct.pack("<3f3B", *p, *c) for p, c in zip(v, rgb))
body += b"".join(struct.pack("<B", len(c)) + struct.pack("<%di" % len(c), *c) for c in faces)
open(tmp + "/colors.ply", "wb").write(head.encode() + body)
lin = lambda x: x / 12.92 if x <= 0.04045 else ((x + 0.055) / 1.055) ** 2.4
tris = [(c[0], c[k], c[k + 1]) for c in faces for k in range(1, len(c) - 1)]
pos = b"".join(struct.pack("<3f", *p) for p in v)
col = b"".join(struct.pack("<3f", *(lin(x / 255) for x in c)) for c in rgb)
idx = b"".join(struct.pack("<3I", *t) for t in tris)
data = pos + col + idx
views = [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
         {"buffer": 0, "byteOffset": len(pos), "byteLength": len(col)},
         {"buffer": 0, "byteOffset": len(pos) + len(col), "byteLength": len(idx)}]
gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "indices": 2}]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": views,
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(v), "type": "VEC3",
                       "min": [min(p[k] for p in v) for k in range(3)], "max": [max(p[k] for p in v) for k in range(3)]},
                      {"bufferView": 1, "componentType": 5126, "count": len(v), "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125, "count": 3 * len(tris), "type": "SCALAR"}]}
json.dump(gltf, open(tmp + "/colors.gltf", "w"))
PY
render() { "$bin/sam_render" "$tmp/$1" -o "$tmp/$2.png" --material skin --size-mm 60 --size 160x120 --no-cache \
  "${@:3}" 2> "$tmp/$2.txt" || fail "sam_render $1: $(cat "$tmp/$2.txt")"; }
render plain.obj plain --write-scene "$tmp/plain.json"
grep -q "vertex colours" "$tmp/plain.txt" && fail "plain.obj has no colours: $(cat "$tmp/plain.txt")"
for f in colors.ply colors.obj colors.gltf; do
  render "$f" "${f/./_}"
done
grep -q "vertex colours: the vertex colours of colors.ply, [0-9]* vertices, times the albedo" "$tmp/colors_ply.txt" \
  || fail "the PLY's colours are not named: $(cat "$tmp/colors_ply.txt")"
grep -q "vertex colours: the vertex colours of colors.obj" "$tmp/colors_obj.txt" || fail "the OBJ's colours are not named"
grep -q "vertex colours: the COLOR_0 of colors.gltf" "$tmp/colors_gltf.txt" || fail "the glTF's colours are not named"
obj=$(png psnr "$tmp/colors_ply.png" "$tmp/colors_obj.png")
gltf=$(png psnr "$tmp/colors_ply.png" "$tmp/colors_gltf.png")
plain=$(png psnr "$tmp/colors_ply.png" "$tmp/plain.png")
echo "coloured PLY against the OBJ: $obj dB, the glTF: $gltf dB, the uncoloured mesh: $plain dB"
at_least "$obj" 50 || fail "the OBJ's colours render another picture ($obj dB)"
at_least "$gltf" 40 || fail "the glTF's COLOR_0 renders another picture ($gltf dB)"
at_least "$plain" 30 && fail "the colours change nothing ($plain dB from the uncoloured picture)"

# The plain scene, its mesh the coloured PLY: with "vertex_colors": false,
# the uncoloured picture.
python3 - "$tmp/plain.json" "$tmp/off.json" "$tmp/colors.ply" <<'PY' || fail "editing the scene"
import json, sys
s = json.load(open(sys.argv[1]))
s["mesh"] = sys.argv[3]
s["vertex_colors"] = False
json.dump(s, open(sys.argv[2], "w"))
PY
"$bin/sam_render" "$tmp/off.json" -o "$tmp/off.png" --no-cache 2> "$tmp/off.txt" || fail "off.json: $(cat "$tmp/off.txt")"
off=$(png psnr "$tmp/plain.png" "$tmp/off.png")
echo "\"vertex_colors\": false against the uncoloured mesh: $off dB"
at_least "$off" 50 || fail "\"vertex_colors\": false renders another picture ($off dB)"

