#!/usr/bin/env bash
# A textured mesh as MeshLab and Metashape save it as PLY: binary, its UVs
# in a per-corner `texcoord` list after the corners, its texture named in a
# `comment TextureFile` header line. It loads with the OBJ's vertex and
# triangle counts (UV seams and all), names its texture, and renders the
# OBJ's picture; with two texture pages (each face's in `texnumber`), the
# picture of the OBJ whose two materials have those textures. Args: BIN SRC TMP
set -u
bin=$1 src=$2 tmp=$3
rm -rf "$tmp" && mkdir -p "$tmp"
fail() { echo "FAIL: $*"; exit 1; }
png() { python3 "$src/tests/cli/lib/png.py" "$@"; }
"$bin/sam_meshgen" ear -o "$tmp/plain.obj" --resolution 24 2>/dev/null || fail "meshgen"
png checker "$tmp/checker.png" 64
{ printf 'mtllib ear.mtl\nusemtl skin\n'; cat "$tmp/plain.obj"; } > "$tmp/ear.obj"
printf 'newmtl skin\nKd 1 1 1\nmap_Kd checker.png\n' > "$tmp/ear.mtl"
# ear.ply: every face on checker.png; two.ply: faces from the 201st on
# the second of two texture pages, as two.obj's second material.
png checker "$tmp/checker2.png" 32 grey
python3 - "$tmp/ear.obj" "$tmp/ear.ply" "$tmp/two.ply" <<'PY' || fail "writing the PLY"
import struct, sys
v, vt, faces = [], [], []
for line in open(sys.argv[1]):
    w = line.split()
    if not w: continue
    if w[0] == "v": v.append([float(x) for x in w[1:4]])
    elif w[0] == "vt": vt.append([float(x) for x in w[1:3]])
    elif w[0] == "f": faces.append([[int(i) - 1 for i in c.split("/")[:2]] for c in w[1:]])
for path, pages in ((sys.argv[2], ["checker.png"]), (sys.argv[3], ["checker.png", "checker2.png"])):
    head = ("ply\nformat binary_little_endian 1.0\ncomment VCGLIB generated\n"
            + "".join(f"comment TextureFile {p}\n" for p in pages) +
            f"element vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
            f"element face {len(faces)}\nproperty list uchar int vertex_indices\n"
            "property list uchar float texcoord\nproperty int texnumber\nend_header\n")
    body = b"".join(struct.pack("<3f", *p) for p in v)
    for k, f in enumerate(faces):
        body += struct.pack("<B", len(f)) + b"".join(struct.pack("<i", c[0]) for c in f)
        body += struct.pack("<B", 2 * len(f)) + b"".join(struct.pack("<2f", *vt[c[1]]) for c in f)
        body += struct.pack("<i", int(k >= 200 and len(pages) > 1))
    open(path, "wb").write(head.encode() + body)
PY
counts() { "$bin/sam_info" "$1" 2>&1 | grep -E "^ *(triangles|render vertices):" | sed 's/(.*//' | tr -s ' '; }
want=$(counts "$tmp/ear.obj")
[ -n "$want" ] || fail "sam_info ear.obj gave no counts"
have=$(counts "$tmp/ear.ply")
[ "$have" = "$want" ] || fail "ear.ply: counts '$have', the OBJ's '$want'"
render() { "$bin/sam_render" "$tmp/$1" -o "$tmp/$2.png" --material skin --size-mm 60 --size 160x120 --no-cache \
  2> "$tmp/$2.txt" || fail "sam_render $1: $(cat "$tmp/$2.txt")"; }
render ear.obj obj
render ear.ply ply
grep -q "albedo map: .*checker.png (TextureFile of .*ear.ply), 64x64" "$tmp/ply.txt" \
  || fail "the PLY's texture is not named: $(cat "$tmp/ply.txt")"
same=$(png psnr "$tmp/obj.png" "$tmp/ply.png")
echo "counts: $want" | tr '\n' ' '; echo; echo "OBJ against MeshLab's PLY: $same dB"
python3 -c "import sys; sys.exit(0 if float('$same') >= 50 else 1)" || fail "the PLY renders another picture: $same dB"
awk 'BEGIN { f = 0 } /^f / && f++ == 200 { print "usemtl other" } { print }' "$tmp/ear.obj" > "$tmp/two.obj"
printf 'newmtl skin\nKd 1 1 1\nmap_Kd checker.png\nnewmtl other\nKd 1 1 1\nmap_Kd checker2.png\n' > "$tmp/ear.mtl"
render two.obj two_obj
render two.ply two_ply
grep -q "albedo maps: 2 for the materials of .*two.ply, each on its own faces" "$tmp/two_ply.txt" \
  || fail "the PLY's two texture pages are not named: $(cat "$tmp/two_ply.txt")"
pages=$(png psnr "$tmp/two_obj.png" "$tmp/two_ply.png")
one=$(png psnr "$tmp/ply.png" "$tmp/two_ply.png")
echo "two texture pages, OBJ against PLY: $pages dB; against one page on every face: $one dB"
python3 -c "import sys; sys.exit(0 if float('$pages') >= 50 else 1)" || fail "the PLY's pages render another picture: $pages dB"
python3 -c "import sys; sys.exit(0 if float('$one') < 35 else 1)" || fail "the second page is not read ($one dB)"
