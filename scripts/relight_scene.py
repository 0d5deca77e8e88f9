#!/usr/bin/env python3
"""Writes variants of a staged scene whose back light is another kind of light.

sam_render stages a bare mesh with a key light in front and a back point
light (--write-scene). This turns that back light, the point light farthest
behind the camera's target, into a directional light along the same line, a
spot light at its place aimed at the target, a square area light there facing
the target, or the bundled studio environment, each giving about the point
light's irradiance at the target. It is how the held-out scenes of
docs/comparison.md were lit by each kind of light.

usage: scripts/relight_scene.py SCENE.json OUT_DIR [--kinds directional,spot,area,environment]
writes OUT_DIR/NAME_KIND.json (the mesh path made absolute, any prebuilt "sam" dropped)

example:
  build/bin/sam_render meshes/scans/bunny.off -o b.png --material marble --size-mm 80 \\
      --size 400x400 --write-scene bunny.json
  scripts/relight_scene.py bunny.json . --kinds directional
  build/bin/sam_compare bunny_directional.json -o cmp_bunny_directional --no-cache
"""
import argparse
import json
import math
import os
import sys

KINDS = ("directional", "spot", "area", "environment")


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    length = math.sqrt(dot(a, a))
    return [x / length for x in a]


def relit(scene, kind, scene_dir):
    camera = scene.get("camera")
    points = [l for l in scene.get("lights", []) if l.get("type") == "point"]
    if not camera or not points:
        raise ValueError("needs a camera and a point light (a scene sam_render --write-scene staged)")
    target, view = camera["target"], unit(sub(camera["target"], camera["position"]))
    back = max(points, key=lambda l: dot(sub(l["position"], target), view))
    others = [l for l in scene["lights"] if l is not back]
    p = back["position"]
    dist = math.sqrt(dot(sub(target, p), sub(target, p)))
    towards = unit(sub(target, p))
    color, intensity = back.get("color", [1, 1, 1]), back.get("intensity", 1.0)
    irradiance = intensity / dist**2
    out = dict(scene)
    out.pop("sam", None)
    if not os.path.isabs(out["mesh"]):
        out["mesh"] = os.path.normpath(os.path.join(scene_dir, out["mesh"]))
    if kind == "directional":
        light = {"type": "directional", "direction": towards, "intensity": irradiance}
    elif kind == "spot":
        light = {"type": "spot", "position": p, "direction": towards, "inner_angle_deg": 15,
                 "outer_angle_deg": 25, "intensity": intensity}
    elif kind == "area":
        # A square half the distance across; radiance times its solid angle
        # (about area / d^2) gives the point light's irradiance.
        up = [0, 1, 0] if abs(towards[1]) < 0.9 else [1, 0, 0]
        u = unit(cross(towards, up))
        w = cross(u, towards)
        h = 0.25 * dist
        quad = [[p[i] + a * h * u[i] + b * h * w[i] for i in range(3)] for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        if dot(cross(sub(quad[1], quad[0]), sub(quad[2], quad[0])), towards) < 0:
            quad.reverse()  # it emits on the side its vertices wind counter-clockwise around
        light = {"type": "area", "vertices": quad, "intensity": irradiance * dist**2 / (2 * h) ** 2}
    else:
        studio = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "studio.exr")
        out["environment"] = {"map": os.path.normpath(studio), "intensity": 1.0, "rotation_deg": 0}
        out["lights"] = others
        return out
    light.update({"color": color, "shadow": back.get("shadow", True)})
    out["lights"] = others + [light]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("out_dir")
    ap.add_argument("--kinds", default=",".join(KINDS))
    a = ap.parse_args()
    kinds = a.kinds.split(",")
    bad = [k for k in kinds if k not in KINDS]
    if bad:
        sys.exit(f"relight_scene.py: unknown kind {bad[0]!r} (choose from {', '.join(KINDS)})")
    try:
        with open(a.scene) as f:
            scene = json.load(f)
        name = os.path.splitext(os.path.basename(a.scene))[0]
        for kind in kinds:
            out = relit(scene, kind, os.path.dirname(os.path.abspath(a.scene)))
            path = os.path.join(a.out_dir, f"{name}_{kind}.json")
            tmp = path + ".tmp"
            with open(tmp, "w") as f:
                json.dump(out, f, indent=2)
            os.replace(tmp, path)
            print(f"relight_scene.py: wrote {path}")
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"relight_scene.py: {a.scene}: {e}")


if __name__ == "__main__":
    main()
