#!/usr/bin/env python3
"""Writes scenes/city_block.json and its meshes (scenes/meshes/city_street.obj, city_buildings.obj).

Run from anywhere: python3 scenes/make_city_block.py. A street along x between two rows of
buildings, closed at both ends: the road (a flat sheet) and the pavements and buildings (closed
boxes: blocks with set-back upper floors) are static triangle meshes; a barricade of crates and
rocks in the middle of the road is blown apart by the scene's explosion, and the fragments hit
the facades, with continuous collision on.
"""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.path.join(HERE, "meshes")

ROAD_HALF_WIDTH = 4.0  # m, the road is |z| < 4
CURB_HEIGHT = 0.15  # m, the pavement's top
PAVEMENT_END = 7.0  # m, the facades stand at |z| = 7
BLOCK_DEPTH = 8.0  # m, from the facade back
STREET_HALF_LENGTH = 24.0  # m, the street runs over |x| < 24


class Obj:
    """An OBJ being written: vertices and triangles, counter-clockwise seen from outside."""

    def __init__(self, comment):
        self.lines = ["# " + comment]
        self.count = 0

    def vertex(self, p):
        self.lines.append("v %g %g %g" % tuple(round(c, 4) for c in p))
        self.count += 1
        return self.count

    def quad(self, a, b, c, d):
        """Two triangles of the quad a, b, c, d (counter-clockwise seen from the side it faces)."""
        i = [self.vertex(p) for p in (a, b, c, d)]
        self.lines.append("f %d %d %d" % (i[0], i[1], i[2]))
        self.lines.append("f %d %d %d" % (i[0], i[2], i[3]))

    def block(self, x0, x1, y0, y1, z0, z1):
        """A closed box."""
        self.quad((x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0))  # +y
        self.quad((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1))  # -y
        self.quad((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1))  # +z
        self.quad((x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0))  # -z
        self.quad((x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1))  # +x
        self.quad((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0))  # -x

    def centre_of_volume(self):
        """The centre of the volume a closed mesh bounds (sum of signed tetrahedra from the
        origin): rubble places a closed mesh by it, so the body's position must be this point
        for the file's coordinates to be the world's."""
        vertices = [tuple(float(c) for c in line.split()[1:]) for line in self.lines
                    if line.startswith("v ")]
        volume, centre = 0.0, [0.0, 0.0, 0.0]
        for line in self.lines:
            if not line.startswith("f "):
                continue
            a, b, c = (vertices[int(i) - 1] for i in line.split()[1:])
            v = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
            volume += v
            for k in range(3):
                centre[k] += v * (a[k] + b[k] + c[k]) / 4.0
        return [round(c / volume, 6) for c in centre]

    def write(self, name):
        with open(os.path.join(MESHES, name), "w") as f:
            f.write("\n".join(self.lines) + "\n")


def street():
    """The road: a flat sheet at y = 0 under the whole block. A flat mesh has no volume, so it
    keeps the file's frame."""
    obj = Obj("city block road: one flat sheet facing +y (make_city_block.py)")
    x, z = STREET_HALF_LENGTH, PAVEMENT_END + BLOCK_DEPTH
    obj.quad((-x, 0, -z), (-x, 0, z), (x, 0, z), (x, 0, -z))
    obj.write("city_street.obj")
    return obj


# (x from, x to, height, upper floors' height above it, set-back of the upper floors) per side
NORTH = [(-22, -13, 9, 6, 1.5), (-11.5, -4, 14, 0, 0), (-2.5, 6, 7, 8, 2.0), (7.5, 22, 11, 4, 1.0)]
SOUTH = [(-22, -15, 12, 0, 0), (-13.5, -3, 6, 6, 2.5), (-1.5, 9, 16, 0, 0), (10.5, 22, 8, 5, 1.5)]


def buildings():
    """Closed boxes: the pavements (their curbs face the road), the blocks on both sides of the
    street, each with an optional set-back upper part, and one block across each end."""
    obj = Obj("city block pavements and buildings: closed boxes (make_city_block.py)")
    h, x, e = CURB_HEIGHT, STREET_HALF_LENGTH, PAVEMENT_END + BLOCK_DEPTH
    obj.block(-x, x, h - 0.35, h, ROAD_HALF_WIDTH, e)
    obj.block(-x, x, h - 0.35, h, -e, -ROAD_HALF_WIDTH)
    for side, row in ((1.0, NORTH), (-1.0, SOUTH)):
        for x0, x1, height, upper, back in row:
            za, zb = sorted((side * PAVEMENT_END, side * e))
            obj.block(x0, x1, h, h + height, za, zb)
            if upper > 0:
                zc, zd = sorted((side * (PAVEMENT_END + back), side * e))
                obj.block(x0 + back, x1 - back, h + height, h + height + upper, zc, zd)
    obj.block(x, x + 6.0, 0.0, 10.0, -e, e)
    obj.block(-x - 6.0, -x, 0.0, 13.0, -e, e)
    obj.write("city_buildings.obj")
    return obj


def scene(buildings_at):
    doc = {
        "format": "rubble-scene",
        "version": 1,
        "name": "an explosion in a street of building meshes",
        "simulation": {"dt": 1.0 / 60.0, "steps": 360, "continuous": True},
        "materials": {
            "default": {"friction": 0.6, "restitution": 0.0},
            "stone": {"friction": 0.8, "restitution": 0.1},
        },
        "shapes": {
            "street": {"type": "mesh", "file": "meshes/city_street.obj"},
            "buildings": {"type": "mesh", "file": "meshes/city_buildings.obj"},
            "catch": {"type": "plane", "normal": [0, 1, 0], "offset": -2.0},
            "crate": {"type": "box", "half_extents": [0.3, 0.3, 0.3]},
            "plank": {"type": "box", "half_extents": [0.9, 0.05, 0.2]},
            "rock": {"type": "mesh", "file": "meshes/rock.obj", "scale": 0.45},
            "pipe": {"type": "capsule", "radius": 0.12, "half_height": 0.6},
        },
        "bodies": [
            {"name": "street", "shape": "street", "static": True},
            {"name": "buildings", "shape": "buildings", "static": True, "position": buildings_at},
            {"name": "catch", "shape": "catch", "static": True},
        ] + [
            # Pipes lying along the road beside the barricade (the capsule's axis turned to x).
            {"name": "pipe%d" % i, "shape": "pipe", "mass": 4.0, "position": [x, 0.12, z],
             "orientation": [0.70710678, 0, 0, 0.70710678]}
            for i, (x, z) in enumerate([(-3.2, -2.6), (-3.2, 2.6), (3.2, -2.6), (3.2, 2.6)])
        ],
        "generators": [
            # The barricade: crates stacked four high across the road.
            {"type": "grid", "shape": "crate", "mass": 8.0, "count": [3, 4, 6],
             "origin": [-0.62, 0.3, -1.55], "spacing": [0.62, 0.61, 0.62],
             "rotation_jitter": 0.02, "seed": 3, "name_prefix": "crate"},
            # Rubble heaped against it on both sides.
            {"type": "grid", "shape": "rock", "mass": 12.0, "count": [2, 2, 5],
             "origin": [-2.0, 0.35, -1.6], "spacing": [4.0, 0.6, 0.8],
             "rotation_jitter": 3.14, "seed": 5, "name_prefix": "rock", "material": "stone"},
            {"type": "grid", "shape": "plank", "mass": 10.0, "count": [1, 3, 2],
             "origin": [0.0, 2.55, -0.8], "spacing": [1.0, 0.12, 1.6],
             "rotation_jitter": 0.05, "seed": 7, "name_prefix": "plank"},
        ],
        "events": [
            {"type": "explosion", "time": 0.5, "centre": [0.0, 1.0, 0.0], "impulse": 170.0,
             "radius": 6.0},
        ],
    }
    with open(os.path.join(HERE, "city_block.json"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    street()
    scene(buildings().centre_of_volume())
