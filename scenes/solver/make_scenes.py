#!/usr/bin/env python3
"""Writes the solver test set (scenes/solver/*.json): the Solver2D set made three-dimensional.

Run from anywhere: python3 scenes/solver/make_scenes.py. Each scene names the body the suite
(`rubble solvers --suite`) watches "top" when the scene is meant to stand: its drift decides
"stands" (docs/solvers.md, "The solver test set").
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
DT = 1.0 / 60.0


def scene(name, shapes, bodies, materials=None, joints=None, generators=None, steps=300):
    doc = {
        "format": "rubble-scene",
        "version": 1,
        "name": name,
        "simulation": {"dt": DT, "steps": steps},
        "materials": materials or {"default": {"friction": 0.6, "restitution": 0.0}},
        "shapes": dict({"ground": {"type": "plane"}}, **shapes),
        "bodies": [{"name": "floor", "shape": "ground", "static": True}] + bodies,
    }
    if joints:
        doc["joints"] = joints
    if generators:
        doc["generators"] = generators
    with open(os.path.join(HERE, name + ".json"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def r(v):
    return round(v, 6)


def box(name, shape, mass, pos, **extra):
    b = {"name": name, "shape": shape, "mass": mass, "position": [r(p) for p in pos]}
    b.update(extra)
    return b


def quat_z(angle):
    return [r(math.cos(angle / 2)), 0.0, 0.0, r(math.sin(angle / 2))]


def stack_20():
    bodies = [box("top" if i == 19 else "b%d" % i, "crate", 1.0, (0, 0.5 + i, 0))
              for i in range(20)]
    scene("stack_20", {"crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}}, bodies)


def pyramid_20():
    bodies = []
    for row in range(20):
        for k in range(20 - row):
            x = (k - (19 - row) / 2.0) * 1.05
            name = "top" if row == 19 else "r%d_%d" % (row, k)
            bodies.append(box(name, "crate", 1.0, (x, 0.5 + row, 0)))
    scene("pyramid_20", {"crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}}, bodies)


def card_house():
    # Cards 0.04 m thick, 1 m tall, 0.7 m deep lean in pairs (A-frames) at 20 degrees from the
    # vertical, with flat cards bridging neighbouring frames; three storeys.
    thick, height, depth = 0.02, 0.5, 0.35
    lean = math.radians(20.0)
    half_w = height * math.sin(lean) + thick * math.cos(lean)  # half the A-frame's foot width
    frame_h = 2 * height * math.cos(lean) + thick * math.sin(lean)
    shapes = {"card": {"type": "box", "half_extents": [thick, height, depth]},
              "flat": {"type": "box", "half_extents": [0.0, 0.0, 0.0]}}
    gap = 0.1
    pitch = 2 * half_w + gap
    flat_half = pitch / 2 + half_w * 0.6
    shapes["flat"]["half_extents"] = [r(flat_half), thick, depth]
    bodies = []
    base = 0.0
    storeys = 3
    for s in range(storeys):
        frames = storeys - s
        for f in range(frames):
            cx = (f - (frames - 1) / 2.0) * pitch
            cy = base + height * math.cos(lean) + thick * math.sin(lean)
            off = height * math.sin(lean)
            top = s == storeys - 1
            bodies.append({"name": "top" if top else "c%d_%d_l" % (s, f), "shape": "card",
                           "mass": 0.05, "position": [r(cx - off), r(cy), 0],
                           "orientation": quat_z(-lean)})
            bodies.append({"name": "c%d_%d_r" % (s, f), "shape": "card", "mass": 0.05,
                           "position": [r(cx + off), r(cy), 0], "orientation": quat_z(lean)})
        base += frame_h
        if s < storeys - 1:
            for f in range(frames - 1):
                cx = (f - (frames - 2) / 2.0) * pitch
                bodies.append(box("f%d_%d" % (s, f), "flat", 0.05, (cx, base + thick, 0)))
            base += 2 * thick
    scene("card_house", shapes, bodies,
          materials={"default": {"friction": 0.7, "restitution": 0.0}})


def arch():
    # A semicircular arch of 13 equal voussoirs (inner radius 4 m, outer 5 m, 1 m deep) on the
    # floor, held by friction 0.6 between its blocks.
    n, r_in, r_out, half_depth = 13, 4.0, 5.0, 0.5
    half = math.pi / n / 2
    # The block at angle 0, as a trapezoid in x-y: its centroid is its centre of mass.
    corners = [(r_in * math.cos(-half), r_in * math.sin(-half)),
               (r_out * math.cos(-half), r_out * math.sin(-half)),
               (r_out * math.cos(half), r_out * math.sin(half)),
               (r_in * math.cos(half), r_in * math.sin(half))]
    area = cx = 0.0
    for i in range(4):
        x0, y0 = corners[i]
        x1, y1 = corners[(i + 1) % 4]
        c = x0 * y1 - x1 * y0
        area += c
        cx += (x0 + x1) * c
    area *= 0.5
    cx /= 6.0 * area
    verts = [[r(x), r(y), z] for (x, y) in corners for z in (-half_depth, half_depth)]
    bodies = []
    for i in range(n):
        angle = (i + 0.5) * math.pi / n
        name = "top" if i == n // 2 else "v%d" % i
        bodies.append({"name": name, "shape": "voussoir", "mass": 10.0,
                       "position": [r(cx * math.cos(angle)), r(cx * math.sin(angle)), 0],
                       "orientation": quat_z(angle)})
    scene("arch", {"voussoir": {"type": "convex", "vertices": verts}}, bodies,
          materials={"default": {"friction": 0.6, "restitution": 0.0}})


def heavy_on_light(ratio):
    # Three light unit boxes stacked, a heavy one (ratio times heavier, twice as wide) on top.
    shapes = {"crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
              "big": {"type": "box", "half_extents": [1.0, 0.5, 1.0]}}
    bodies = [box("b%d" % i, "crate", 1.0, (0, 0.5 + i, 0)) for i in range(3)]
    bodies.append(box("top", "big", float(ratio), (0, 3.5, 0)))
    scene("heavy_on_light_%d" % ratio, shapes, bodies)


def light_under_heavy():
    # A light box between heavy ones: 100 kg, 1 kg, 100 kg, 100 kg.
    shapes = {"crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}}
    masses = [100.0, 1.0, 100.0, 100.0]
    bodies = [box("top" if i == 3 else "b%d" % i, "crate", m, (0, 0.5 + i, 0))
              for i, m in enumerate(masses)]
    scene("light_under_heavy", shapes, bodies)


def friction_ramp():
    # A 1 m thick ramp at 25 degrees (tan 0.466), five boxes side by side with friction 0.8,
    # 0.6, 0.4, 0.2 and 0 (against the ramp's 1): the first two stick, the others slide.
    angle = math.radians(25.0)
    frictions = [0.8, 0.6, 0.4, 0.2, 0.0]
    materials = {"default": {"friction": 1.0, "restitution": 0.0}}
    for i, mu in enumerate(frictions):
        materials["m%d" % i] = {"friction": mu * mu, "restitution": 0.0}  # sqrt(1 * mu^2) = mu
    shapes = {"ramp": {"type": "box", "half_extents": [8.0, 0.5, 4.0]},
              "crate": {"type": "box", "half_extents": [0.4, 0.4, 0.4]}}
    ramp_centre = (0.0, 4.0, 0.0)
    normal = (-math.sin(angle), math.cos(angle))
    bodies = [{"name": "ramp", "shape": "ramp", "static": True, "position": list(ramp_centre),
               "orientation": quat_z(angle)}]
    for i, mu in enumerate(frictions):
        along = 3.0  # up the ramp from its centre, m
        d = 0.5 + 0.4
        x = ramp_centre[0] + along * math.cos(angle) + d * normal[0]
        y = ramp_centre[1] + along * math.sin(angle) + d * normal[1]
        z = -3.2 + 1.6 * i
        bodies.append({"name": "top" if i == 0 else "box%d" % i, "shape": "crate", "mass": 1.0,
                       "position": [r(x), r(y), r(z)], "orientation": quat_z(angle),
                       "material": "m%d" % i})
    scene("friction_ramp", shapes, bodies, materials=materials)


def overlap_recovery():
    # A pyramid of 4 rows whose boxes overlap their neighbours and the floor by half their
    # size: the solver pushes them apart without throwing them.
    bodies = []
    rows = 4
    for row in range(rows):
        for k in range(rows - row):
            x = (k - (rows - 1 - row) / 2.0) * 0.5
            bodies.append(box("r%d_%d" % (row, k), "crate", 1.0, (x, 0.25 + 0.5 * row, 0)))
    scene("overlap_recovery", {"crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
          bodies)


def ragdoll_pile():
    # 12 ragdolls in layers of four, 2.3 m apart, each layer shifted so that they tangle.
    gens = []
    for i in range(12):
        layer, k = divmod(i, 4)
        x = (-0.8 if k < 2 else 0.8) + 0.35 * (layer % 2)
        z = (-0.5 if k % 2 == 0 else 0.5) + 0.25 * (layer % 2)
        gens.append({"type": "ragdoll", "name_prefix": "doll%d" % i,
                     "position": [r(x), r(1.6 + 2.3 * layer), r(z)]})
    scene("ragdoll_pile", {}, [], generators=gens)


def chain_40():
    # 40 links 0.25 m long joined end to end by ball joints, the first to a static pin 12 m up,
    # laid out horizontally; a 1 m ball of 50 kg (100 times a link) hangs at the end.
    link_half = 0.125
    shapes = {"link": {"type": "box", "half_extents": [link_half, 0.03, 0.03]},
              "pin": {"type": "sphere", "radius": 0.05},
              "ball": {"type": "sphere", "radius": 0.5}}
    top_y = 12.0
    bodies = [{"name": "pin", "shape": "pin", "static": True, "position": [0, top_y, 0]}]
    joints = []
    prev = "pin"
    for i in range(40):
        name = "l%d" % i
        bodies.append(box(name, "link", 0.5, (link_half * (2 * i + 1), top_y, 0)))
        joints.append({"type": "ball", "a": prev, "b": name, "anchor": [r(2 * link_half * i),
                                                                       top_y, 0]})
        prev = name
    end = 2 * link_half * 40
    bodies.append(box("ball", "ball", 50.0, (end + 0.5, top_y, 0)))
    joints.append({"type": "ball", "a": prev, "b": "ball", "anchor": [r(end), top_y, 0]})
    scene("chain_40", shapes, bodies, joints=joints)


def confined():
    # 4 walls 6 m apart and a lid; 216 spheres and boxes dropped into it in a jittered grid.
    shapes = {"wall": {"type": "box", "half_extents": [0.25, 3.0, 3.5]},
              "side": {"type": "box", "half_extents": [3.5, 3.0, 0.25]},
              "lid": {"type": "box", "half_extents": [3.5, 0.25, 3.5]},
              "ball": {"type": "sphere", "radius": 0.35},
              "crate": {"type": "box", "half_extents": [0.3, 0.3, 0.3]}}
    bodies = [{"name": "wall_l", "shape": "wall", "static": True, "position": [-3.25, 3, 0]},
              {"name": "wall_r", "shape": "wall", "static": True, "position": [3.25, 3, 0]},
              {"name": "wall_b", "shape": "side", "static": True, "position": [0, 3, -3.25]},
              {"name": "wall_f", "shape": "side", "static": True, "position": [0, 3, 3.25]},
              {"name": "lid", "shape": "lid", "static": True, "position": [0, 6.25, 0]}]
    gens = [{"type": "grid", "shape": "ball", "mass": 1.0, "count": [6, 3, 6],
             "origin": [-2.25, 0.5, -2.25], "spacing": [0.9, 1.8, 0.9], "name_prefix": "s"},
            {"type": "grid", "shape": "crate", "mass": 1.0, "count": [6, 3, 6],
             "origin": [-2.25, 1.4, -2.25], "spacing": [0.9, 1.8, 0.9], "rotation_jitter": 0.3,
             "seed": 3, "name_prefix": "c"}]
    scene("confined", shapes, bodies, generators=gens)


if __name__ == "__main__":
    stack_20()
    pyramid_20()
    card_house()
    arch()
    heavy_on_light(100)
    heavy_on_light(1000)
    light_under_heavy()
    friction_ramp()
    overlap_recovery()
    ragdoll_pile()
    chain_40()
    confined()
