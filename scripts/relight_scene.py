#!/usr/bin/env python3
"""Writes variants of a staged scene whose back light is another kind of light.

sam_render stages a bare mesh with a key light in front and a back point
light (--write-scene). This turns that back light, the point light farthest
behind the camera's target, into a directional light along the same line, a
spot light in its place aimed at the target, a square area light there facing
the target, or the bundled studio environment in its stead. The first three
give the point light's irradiance at the target (the object's centre); nearer
and farther parts of the object get what a light of that kind gives them. The
environment takes its own intensity, 1. It is how the held-out scenes of
docs/comparison.md were lit by each kind of light.

writes OUT_DIR/NAME_KIND.json, atomically: paths made absolute (the mesh, a
profile file, the albedo and environment maps, keyframe meshes), any prebuilt
"sam" dropped so that the map is built for the scene's own mesh

example:
  build/bin/sam_render meshes/scans/bunny.off -o b.png --material marble --size-mm 80 \\
      --size 400x400 --write-scene bunny.json
  scripts/relight_scene.py bunny.json . --kinds directional
  build/bin/sam_compare bunny_directional.json -o cmp_bunny_directional --no-cache
"""
import argparse
import copy
import json
import math
import os
import sys

KINDS = ("directional", "spot", "area", "environment")
STUDIO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "studio.exr"))


class SceneError(Exception):
    pass


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a, what):
    length = math.sqrt(dot(a, a))
    if not length > 0:
        raise SceneError(f"{what} has no direction (two points coincide)")
    return [x / length for x in a]


def vector(x, what):
    if not (isinstance(x, list) and len(x) == 3 and all(isinstance(c, (int, float)) for c in x)):
        raise SceneError(f"{what} is not [x, y, z]: {json.dumps(x)}")
    return [float(c) for c in x]


def absolute(scene, scene_dir):
    """Paths in a scene resolve against its file; the variants live elsewhere."""
    def fix(p):
        return p if os.path.isabs(p) else os.path.normpath(os.path.join(scene_dir, p))
    if isinstance(scene.get("mesh"), str):
        scene["mesh"] = fix(scene["mesh"])
    m = scene.get("material")
    if isinstance(m, str) and (os.sep in m or m.endswith(".json")):
        scene["material"] = fix(m)
    if isinstance(scene.get("albedo_map"), str):
        scene["albedo_map"] = fix(scene["albedo_map"])
    env = scene.get("environment")
    if isinstance(env, dict) and isinstance(env.get("map"), str):
        env["map"] = fix(env["map"])
    keyframes = scene.get("keyframes")
    for k in keyframes if isinstance(keyframes, list) else []:
        if isinstance(k, dict) and isinstance(k.get("mesh"), str):
            k["mesh"] = fix(k["mesh"])


def square_radiance(irradiance, half_side, dist):
    """Radiance of a square facing a point head-on that gives it this
    irradiance: E = 4 L s atan(s), s = a / sqrt(a^2 + d^2) (the projected
    solid angle of a rectangle over a parallel point, four quadrants)."""
    s = half_side / math.sqrt(half_side**2 + dist**2)
    return irradiance / (4 * s * math.atan(s))


def relit(scene, kind, scene_dir):
    if not isinstance(scene, dict):
        raise SceneError("is not a JSON object")
    if "mesh" not in scene:
        raise SceneError('has no "mesh" (a scene sam_render --write-scene staged names one)')
    camera, lights = scene.get("camera"), scene.get("lights", [])
    if not isinstance(camera, dict) or "target" not in camera or "position" not in camera:
        raise SceneError('has no "camera" with a position and a target')
    if not isinstance(lights, list):
        raise SceneError('"lights" is not a list')
    target = vector(camera["target"], "camera target")
    view = unit(sub(target, vector(camera["position"], "camera position")), "the camera's line of sight")
    points = [l for l in lights if isinstance(l, dict) and l.get("type") == "point"]
    behind = [(dot(sub(vector(l.get("position"), "a point light's position"), target), view), i)
              for i, l in enumerate(points)]
    behind = [b for b in behind if b[0] > 0]
    if not behind:
        raise SceneError("has no point light behind the camera's target to turn into another kind")
    back = points[max(behind)[1]]
    others = [l for l in lights if l is not back]
    p = vector(back["position"], "the back light's position")
    to_target = sub(target, p)
    towards = unit(to_target, "the back light")
    dist = math.sqrt(dot(to_target, to_target))
    color, intensity = back.get("color", [1, 1, 1]), float(back.get("intensity", 1.0))
    irradiance = intensity / dist**2
    out = copy.deepcopy(scene)
    out.pop("sam", None)
    absolute(out, scene_dir)
    if kind == "directional":
        light = {"type": "directional", "direction": towards, "intensity": irradiance}
    elif kind == "spot":
        light = {"type": "spot", "position": p, "direction": towards, "inner_angle_deg": 15,
                 "outer_angle_deg": 25, "intensity": intensity}
    elif kind == "area":
        up = [0, 1, 0] if abs(towards[1]) < 0.9 else [1, 0, 0]
        u = unit(cross(towards, up), "the area light's side")
        w = cross(u, towards)
        h = 0.25 * dist  # half the side: a square half the distance across
        quad = [[p[i] + a * h * u[i] + b * h * w[i] for i in range(3)] for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        if dot(cross(sub(quad[1], quad[0]), sub(quad[2], quad[0])), towards) < 0:
            quad.reverse()  # it emits on the side its vertices wind counter-clockwise around
        light = {"type": "area", "vertices": quad, "intensity": square_radiance(irradiance, h, dist)}
    else:
        out["environment"] = {"map": STUDIO, "intensity": 1.0, "rotation_deg": 0}
        out["lights"] = others
        return out
    light.update({"color": color, "shadow": back.get("shadow", True)})
    out["lights"] = others + [light]
    return out


def main():
    ap = argparse.ArgumentParser(prog="relight_scene.py", description=__doc__.split("\n\n")[0],
                                 epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", help="a scene with a camera and a back point light (sam_render --write-scene)")
    ap.add_argument("out_dir", help="an existing folder for the variants")
    ap.add_argument("--kinds", default=",".join(KINDS), help="comma-separated from %s (default: all)" % ", ".join(KINDS))
    a = ap.parse_args()
    kinds = a.kinds.split(",")
    bad = [k for k in kinds if k not in KINDS]
    if bad:
        ap.error(f"unknown kind {bad[0]!r} (choose from {', '.join(KINDS)})")
    if not os.path.isdir(a.out_dir):
        ap.error(f"{a.out_dir}: not a folder")
    try:
        with open(a.scene) as f:
            scene = json.load(f)
        variants = [(k, relit(scene, k, os.path.dirname(os.path.abspath(a.scene)))) for k in kinds]
    except OSError as e:
        sys.exit(f"relight_scene.py: {a.scene}: {e.strerror}")
    except json.JSONDecodeError as e:
        sys.exit(f"relight_scene.py: {a.scene}: not JSON: {e}")
    except SceneError as e:
        sys.exit(f"relight_scene.py: {a.scene}: {e}")
    name = os.path.splitext(os.path.basename(a.scene))[0]
    for kind, out in variants:
        path = os.path.join(a.out_dir, f"{name}_{kind}.json")
        tmp = path + ".tmp"
        try:
            with open(tmp, "w") as f:
                json.dump(out, f, indent=2)
            os.replace(tmp, path)
        except OSError as e:
            if os.path.exists(tmp):
                os.remove(tmp)
            sys.exit(f"relight_scene.py: {path}: {e.strerror}")
        print(f"relight_scene.py: wrote {path}")


if __name__ == "__main__":
    main()
