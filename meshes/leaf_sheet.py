#!/usr/bin/env python3
"""Writes a curved leaf as one open sheet of triangles (an OBJ): a grid of
24 x 48 quads, 1 unit long, whose width follows a sine along its length,
bowed along it and cupped across. A single sheet has no back side; give it
a thickness with sam_solidify before building a map, as for a scanned leaf:

    python3 meshes/leaf_sheet.py leaf.obj
    build/bin/sam_solidify leaf.obj -o leaf_solid.obj --thickness-mm 0.5 --size-mm 80
"""
import math
import sys

ACROSS, ALONG = 24, 48


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: leaf_sheet.py OUT.obj")
    lines = []
    for j in range(ALONG + 1):
        t = j / ALONG
        half_width = 0.25 * math.sin(math.pi * t) + 0.005
        for i in range(ACROSS + 1):
            x = 2 * (i / ACROSS - 0.5) * half_width
            lines.append("v %.6f %.6f %.6f" % (x, t, 0.15 * math.sin(math.pi * t) + 0.3 * x * x))
    for j in range(ALONG):
        for i in range(ACROSS):
            a = j * (ACROSS + 1) + i + 1
            b, c, d = a + 1, a + ACROSS + 2, a + ACROSS + 1
            lines.append("f %d %d %d" % (a, b, c))
            lines.append("f %d %d %d" % (a, c, d))
    with open(sys.argv[1], "w") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
