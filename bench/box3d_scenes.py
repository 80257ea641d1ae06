#!/usr/bin/env python3
"""Writes scenes/bench/junkyard.json, many_pyramids.json and large_pyramid.json: Box3D's
benchmark scenes (shared/benchmarks.c of ../shared/peers/box3d, its release sizes) in rubble's
scene format, so that rubble and the box3d peer runner step the same bodies.

  bench/box3d_scenes.py            # writes the three files
  bench/box3d_scenes.py --check    # exits 1 when a file differs from what it would write

What carries over from benchmarks.c and its benchmark program (benchmark/main.c): the counts,
shapes, sizes and spacing of the bodies, their densities (Box3D's default 1000 kg/m^3, 100 for
the pyramids' boxes), friction 0.6 and restitution 0 (b3DefaultShapeDef), gravity -10 m/s^2
(b3DefaultWorldDef), dt 1/60 s, the steps of each benchmark, and whether bodies may sleep
(the pyramids are kept awake: simulation.sleep false). The ground, a static box whose top face
is y = 0 in Box3D, is a plane at y = 0 here (the runner makes it a box again). Box3D places a
body by its origin, rubble by its centre of mass: a rock's position is its origin plus its
hull's centroid. Junkyard's kinematic pusher (a 16-sided cylinder, radius 4 m, circling at
6 deg/s) is left out: rubble has no kinematic bodies yet; without it the rocks fall, settle and
may sleep, in both engines.
"""
import argparse
import itertools
import json
import math
import os
import struct
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "scenes", "bench")

DT = 1.0 / 60.0
GRAVITY = [0, -10, 0]
FRICTION = 0.6            # b3DefaultSurfaceMaterial
DEFAULT_DENSITY = 1000.0  # b3DefaultShapeDef, kg/m^3
PYRAMID_DENSITY = 100.0   # CreateLargePyramid, CreateSmallPyramid


def f32(x):
    """x rounded to a 32-bit float, as Box3D computes it, then to the shortest decimal."""
    v = struct.unpack("f", struct.pack("f", x))[0]
    return float("%.7g" % v)


def header(name, steps, sleep):
    return {
        "format": "rubble-scene",
        "version": 1,
        "name": name,
        "simulation": {"dt": DT, "steps": steps, "gravity": GRAVITY, "sleep": sleep},
        "materials": {"default": {"friction": FRICTION, "restitution": 0.0}},
    }


def floor_body():
    return {"name": "floor", "shape": "floor", "static": True}


FLOOR_SHAPE = {"type": "plane", "normal": [0, 1, 0], "offset": 0}


def row(prefix, shape, density, count, origin, spacing):
    """A grid generator: `count` [x, y, z] bodies from `origin`, unrotated."""
    return {"type": "grid", "shape": shape, "density": density, "count": count,
            "origin": [f32(c) for c in origin], "spacing": [f32(s) for s in spacing],
            "name_prefix": prefix}


# ---- The rock of b3CreateRock: 10 points of a Fibonacci lattice on a sphere.

def rock_points(radius):
    phi = (1.0 + math.sqrt(5.0)) / 2.0
    theta = 2.0 * math.pi / phi
    n = 10
    points = []
    for i in range(n):
        z = 1.0 - (2.0 * i + 1.0) / n
        r = math.sqrt(1.0 - z * z)
        points.append((radius * r * math.cos(i * theta), radius * r * math.sin(i * theta),
                       radius * z))
    return [tuple(f32(c) for c in p) for p in points]


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def hull_centroid(points):
    """Centre of volume of the convex hull of a few points in general position (every point on
    the hull): the faces are the triples with every other point on one side."""
    inside = tuple(sum(p[k] for p in points) / len(points) for k in range(3))
    volume, moment = 0.0, [0.0, 0.0, 0.0]
    for a, b, c in itertools.combinations(points, 3):
        n = cross(sub(b, a), sub(c, a))
        sides = [dot(n, sub(p, a)) for p in points if p not in (a, b, c)]
        if not (all(s < 1e-9 for s in sides) or all(s > -1e-9 for s in sides)):
            continue
        # A tetrahedron from the inner point to the face.
        v = abs(dot(n, sub(a, inside))) / 6.0
        volume += v
        for k in range(3):
            moment[k] += v * (inside[k] + a[k] + b[k] + c[k]) / 4.0
    return tuple(m / volume for m in moment)


# ---- The scenes.

def junkyard():
    """CreateJunkyard: 24 layers of 21 x 21 rocks (radius 1.5 m) 4 m apart in a walled yard."""
    doc = header("junkyard", 500, True)
    rock = rock_points(1.5)
    centre = hull_centroid(rock)
    doc["shapes"] = {
        "floor": FLOOR_SHAPE,
        "rock": {"type": "convex", "vertices": [list(p) for p in rock]},
        # The four walls of the ground body (at y = -1): offset boxes 16 m high.
        "wall_x": {"type": "box", "half_extents": [1, 8, 50]},
        "wall_z": {"type": "box", "half_extents": [50, 8, 1]},
    }
    doc["bodies"] = [floor_body()] + [
        {"name": name, "shape": shape, "static": True, "position": position}
        for name, shape, position in [("wall_x0", "wall_x", [-50, 7, 0]),
                                      ("wall_x1", "wall_x", [50, 7, 0]),
                                      ("wall_z0", "wall_z", [0, 7, -50]),
                                      ("wall_z1", "wall_z", [0, 7, 50])]]
    # Origins at (-40 + 4 X, 25 + 4 Y, -40 + 4 Z); rubble places the centre of mass.
    doc["generators"] = [row("rock", "rock", DEFAULT_DENSITY, [21, 24, 21],
                             [-40 + centre[0], 25 + centre[1], -40 + centre[2]], [4, 4, 4])]
    return doc


def many_pyramids():
    """CreateManyPyramids: 14 x 14 pyramids of 55 unit boxes (base 10), awake."""
    doc = header("many_pyramids", 100, False)
    base, extent, rows, columns = 10, 0.5, 14, 14
    ground = extent * columns * (base + 1.0)
    base_width = 2.0 * extent * base
    first_z = -ground + 2.0 * extent
    delta_z = 2.0 * (ground - 2.0 * extent) / (rows - 1.0)
    doc["shapes"] = {"floor": FLOOR_SHAPE,
                     "box": {"type": "box", "half_extents": [extent, extent, extent]}}
    doc["bodies"] = [floor_body()]
    # Level i of every pyramid of column j: a row of base - i boxes, repeated along z.
    generators = []
    for j in range(columns):
        centre_x = -ground + j * (base_width + 2.0 * extent) + 2.0 * extent
        for i in range(base):
            x = (i + 1.0) * extent + centre_x - 0.5
            y = (2.0 * i + 1.0) * extent
            generators.append(row("p%d_%d_" % (j, i), "box", PYRAMID_DENSITY, [base - i, 1, rows],
                                  [x, y, first_z], [2.0 * extent, 1.0, delta_z]))
    doc["generators"] = generators
    return doc


def large_pyramid():
    """CreateLargePyramid: one pyramid of 5,050 unit boxes (base 100), awake."""
    doc = header("large_pyramid", 200, False)
    base, h = 100, 0.5
    doc["shapes"] = {"floor": FLOOR_SHAPE, "box": {"type": "box", "half_extents": [h, h, h]}}
    doc["bodies"] = [floor_body()]
    doc["generators"] = [
        row("l%d_" % i, "box", PYRAMID_DENSITY, [base - i, 1, 1],
            [(i + 1.0) * h - h * base, (2.0 * i + 1.0) * h, 0.0], [2.0 * h, 1.0, 1.0])
        for i in range(base)]
    return doc


SCENES = {"junkyard": junkyard, "many_pyramids": many_pyramids, "large_pyramid": large_pyramid}


def text(doc):
    return json.dumps(doc, indent=1) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true",
                    help="compare the files with what would be written; exit 1 if any differs")
    ap.add_argument("--out", default=OUT, help="folder of the scene files")
    args = ap.parse_args()
    stale = []
    for name, make in SCENES.items():
        path = os.path.join(args.out, name + ".json")
        want = text(make())
        if args.check:
            try:
                with open(path) as f:
                    have = f.read()
            except OSError:
                have = None
            if have != want:
                stale.append(path)
            continue
        with open(path, "w") as f:
            f.write(want)
        print("wrote %s" % os.path.relpath(path, ROOT))
    if stale:
        print("box3d_scenes: out of date: %s (run bench/box3d_scenes.py)" % ", ".join(stale),
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
