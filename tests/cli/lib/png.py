"""Reads 8-bit PNGs (the files the tools write) with the standard library,
for the command-line tests (there is no numpy or PIL): `python3 png.py psnr
A B`, `python3 png.py differ A B` (pixels that differ), `python3 png.py
count A R G B TOL` (pixels within TOL of a colour), `python3 png.py glow A B
LEVEL`, `python3 png.py checker OUT SIZE` (writes a red and cream
checkerboard, 8-pixel squares), `python3 png.py size A` (WIDTHxHEIGHT),
`python3 png.py at A X Y` (R G B of one pixel); or import pixels() and
psnr()."""
import math
import struct
import sys
import zlib


def read(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                raise SystemExit(f"{path}: only 8-bit RGB/RGBA, non-interlaced PNGs are read here")
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, stride = zlib.decompress(idat), width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        prev = line
    return rows


def pixels(path):
    return [p for row in read(path) for p in row]


def psnr(a, b):
    """PSNR in dB of two pixel lists over their RGB samples; inf when equal."""
    if len(a) != len(b):
        raise SystemExit("sizes differ")
    se = sum((x - y) ** 2 for p, q in zip(a, b) for x, y in zip(p, q))
    return math.inf if se == 0 else 20 * math.log10(255 / math.sqrt(se / (3 * len(a))))


def main():
    cmd = sys.argv[1]
    if cmd in ("psnr", "differ"):
        a, b = pixels(sys.argv[2]), pixels(sys.argv[3])
        if cmd == "differ":
            if len(a) != len(b):
                raise SystemExit("sizes differ")
            print(sum(p != q for p, q in zip(a, b)))
            return
        v = psnr(a, b)
        print("inf" if v == math.inf else f"{v:.2f}")
    elif cmd == "glow":
        # Object pixels (not the top-left corner's backdrop in both) whose
        # luminance is at least LEVEL higher in A than in B: "glow OBJECT".
        a, b, level = pixels(sys.argv[2]), pixels(sys.argv[3]), float(sys.argv[4])
        lum = lambda p: 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
        obj = [i for i, p in enumerate(b) if p != b[0] or a[i] != b[0]]
        print(sum(1 for i in obj if lum(a[i]) >= lum(b[i]) + level), len(obj))
    elif cmd == "checker":
        # "checker PATH SIZE [KIND]": 8-bit RGB, or KIND grey (8-bit grey)
        # or rgb16 (16-bit RGB, each value's byte twice).
        size, kind = int(sys.argv[3]), sys.argv[4] if len(sys.argv) > 4 else "rgb"
        pick = lambda x, y: (230, 60, 40) if (x // 8 + y // 8) % 2 else (240, 230, 200)
        pixel = {"rgb": lambda p: bytes(p), "grey": lambda p: bytes((p[1],)),
                 "rgb16": lambda p: bytes(v for c in p for v in (c, c))}[kind]
        depth, colour = {"rgb": (8, 2), "grey": (8, 0), "rgb16": (16, 2)}[kind]
        rows = b"".join(b"\x00" + b"".join(pixel(pick(x, y)) for x in range(size)) for y in range(size))
        chunk = lambda kind, d: struct.pack(">I", len(d)) + kind + d + struct.pack(">I", zlib.crc32(kind + d))
        with open(sys.argv[2], "wb") as f:
            f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, depth, colour, 0, 0, 0)) +
                    chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
    elif cmd == "count":
        want, tol = [int(v) for v in sys.argv[3:6]], int(sys.argv[6])
        print(sum(all(abs(x - w) <= tol for x, w in zip(p, want)) for p in pixels(sys.argv[2])))
    elif cmd == "size":
        rows = read(sys.argv[2])
        print(f"{len(rows[0])}x{len(rows)}")
    elif cmd == "at":
        print(*read(sys.argv[2])[int(sys.argv[4])][int(sys.argv[3])])
    else:
        raise SystemExit(f"unknown command {cmd}")


if __name__ == "__main__":
    main()
