#!/usr/bin/env python3
"""Loop subdivision of a closed triangle mesh in ASCII OFF.

    loop_subdivide.py STEPS IN.off OUT.off

Each step splits every triangle into four at its edge points and smooths
(Loop 1987): an edge point is 3/8 of its edge's ends plus 1/8 of the two
opposite corners; a vertex of valence n keeps 1 - n*beta of itself and
takes beta of each neighbour, beta = (5/8 - (3/8 + cos(2 pi / n) / 4)^2) / n.
A step gives V + E vertices and 4F triangles, and keeps the surface closed
and its orientation.

Used by fetch_scans.sh to bring a scan to the order of the SAM paper's
Happy Buddha (549k vertices): no scan in the CGAL data archive comes near
that density. Deterministic: the same input gives the same bytes (plain IEEE
double arithmetic in a fixed order, numbers written with 9 significant
digits, so they read back exactly as floats). Refuses a mesh that is not a
closed, consistently oriented triangle mesh (every edge in exactly two
triangles, once in each direction), where the rule above does not apply.
The output has no comments, as sam_mesh's OFF preflight requires.
"""
import math
import sys


def fail(message):
    sys.exit("loop_subdivide.py: " + message)


def read_off(path):
    with open(path) as f:
        tokens = [t for line in f for t in line.split("#", 1)[0].split()]
    if not tokens or tokens[0] != "OFF":
        fail("%s: not an ASCII OFF file" % path)
    try:
        nv, nf = int(tokens[1]), int(tokens[2])
        at = 4
        positions = [tuple(float(tokens[at + 3 * v + k]) for k in range(3)) for v in range(nv)]
        at += 3 * nv
        triangles = []
        for f in range(nf):
            if tokens[at] != "3":
                fail("%s: face %d has %s corners; triangles only" % (path, f, tokens[at]))
            triangles.append(tuple(int(tokens[at + 1 + k]) for k in range(3)))
            at += 4
    except (IndexError, ValueError):
        fail("%s: truncated or malformed OFF" % path)
    if any(not 0 <= i < nv for t in triangles for i in t):
        fail("%s: a face refers to a vertex that does not exist" % path)
    return positions, triangles


def subdivide(positions, triangles):
    """One Loop step; returns the new positions and triangles."""
    nv = len(positions)
    # Undirected edge -> [new vertex index, opposite corners]; directed edges
    # seen, to check orientation. Dicts keep insertion order: deterministic.
    edges = {}
    directed = set()
    for a, b, c in triangles:
        for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
            if (p, q) in directed:
                fail("edge %d-%d appears twice in the same direction (non-manifold or flipped)" % (p, q))
            directed.add((p, q))
            key = (p, q) if p < q else (q, p)
            entry = edges.setdefault(key, [nv + len(edges), []])
            entry[1].append(r)
    sums = [[0.0, 0.0, 0.0] for _ in range(nv)]
    valence = [0] * nv
    points = []
    for (p, q), (_, opposite) in edges.items():
        if len(opposite) != 2:
            fail("edge %d-%d is in %d triangles; the mesh must be closed and manifold" % (p, q, len(opposite)))
        a, b = positions[p], positions[q]
        c, d = positions[opposite[0]], positions[opposite[1]]
        points.append(tuple(0.375 * (a[k] + b[k]) + 0.125 * (c[k] + d[k]) for k in range(3)))
        for v, w in ((p, b), (q, a)):
            valence[v] += 1
            for k in range(3):
                sums[v][k] += w[k]
    moved = []
    for v in range(nv):
        n = valence[v]
        if n == 0:
            fail("vertex %d is in no triangle" % v)
        beta = (0.625 - (0.375 + 0.25 * math.cos(2.0 * math.pi / n)) ** 2) / n
        moved.append(tuple((1.0 - n * beta) * positions[v][k] + beta * sums[v][k] for k in range(3)))
    out = []
    for a, b, c in triangles:
        ab = edges[(a, b) if a < b else (b, a)][0]
        bc = edges[(b, c) if b < c else (c, b)][0]
        ca = edges[(c, a) if c < a else (a, c)][0]
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return moved + points, out


def write_off(path, positions, triangles):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(positions), len(triangles)))
        f.writelines("%.9g %.9g %.9g\n" % p for p in positions)
        f.writelines("3 %d %d %d\n" % t for t in triangles)


def main():
    if len(sys.argv) != 4 or not sys.argv[1].isdigit():
        fail("usage: loop_subdivide.py STEPS IN.off OUT.off")
    positions, triangles = read_off(sys.argv[2])
    for _ in range(int(sys.argv[1])):
        positions, triangles = subdivide(positions, triangles)
    write_off(sys.argv[3], positions, triangles)


if __name__ == "__main__":
    main()
