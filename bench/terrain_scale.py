#!/usr/bin/env python3
"""The terrain scale target: debris_16k's pile dropped on a ~10^6-triangle terrain mesh and on
its plane, on the CPU (or with --backend opencl on the device's SAT path), side by side.

  bench/terrain_scale.py              # build/rubble, 900 steps, 708 x 708 quads of 0.5 m
  bench/terrain_scale.py --quads 100 --size 50 --steps 120 --crates 8,4,8   # a quick look
  bench/terrain_scale.py --backend opencl --out bench/results/<machine>/terrain_scale_opencl.csv
  bench/terrain_scale.py --base /work/base/rubble --repeat 3 --out .../terrain_scale_cpu.csv
  bench/terrain_scale.py --base build/rubble --extra=--recycle-contacts --extra=true --repeat 3 \
      --out .../terrain_scale_recycle_cpu.csv     # recycling off (base) and on (build)

Writes a folder of its own (--work, a new temporary one by default) holding the terrain (rolling
hills, every height at or below the plane's y = 0, so that both piles start at the same heights)
as tiles x tiles closed OBJ meshes (rubble reads at most 250,000 vertices from one file), the two
scenes and each run's metrics and last state; then one CSV row per floor under
bench/results/<machine>/ (--out): median and p90 ms/step, the broad and narrow phase's mean ms
per step, and how deep the deepest crate corner lies below the surface under it at the end
(vertically, against the triangles themselves), besides the deepest contact of the whole run
(largest_penetration_m, the metrics file's largest_penetration).
With --repeat N the two scenes run N times in turn and each row is one run. With --base PATH a
second binary (another build, e.g. main's) runs each scene right before --rubble does, in the
same repeats, so that the two are timed side by side on the same load (column binary: base or
build; ratio_to_plane against the same binary's plane runs). --extra and --base-extra add
arguments to the runs of --rubble and of --base (column args), e.g. one binary with and without
an option.
With --at-rest STEPS each scene first runs --steps steps once (with --rubble; rows of phase
drop), then a second scene is made from each run's last state (the crates where they ended,
velocities zero, simulation.sleep false so that every crate stays awake and is solved in every
step) and STEPS steps of it are timed (rows of phase rest, --repeat times, alternating with
--base), adding the columns phase, the build-rows and solve stages' mean ms per step and the
contacts after the last step; ratio_to_plane is then against the same phase's plane runs. The
two piles at rest differ only by their floors, where after a whole drop the pile on the hills
also moves more.
Python's standard library only; bench/run's machine name.
"""
import argparse
import csv
import importlib.machinery
import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The hills: a long swell and a short ripple, between -AMPLITUDE and 0 m.
SWELL_WAVELENGTH = 24.0  # m
RIPPLE_WAVELENGTH = 5.0  # m
SWELL_SHARE = 0.85  # of the amplitude; the ripple has the rest


def bench_run_module():
    """bench/run as a module, for its machine name (it has no .py suffix)."""
    path = os.path.join(ROOT, "bench", "run")
    loader = importlib.machinery.SourceFileLoader("bench_run", path)
    spec = importlib.util.spec_from_loader("bench_run", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def height(x, z, amplitude):
    """Terrain height at a grid vertex, m: 0 at the crests, -amplitude in the deepest hollow."""
    k1, k2 = 2.0 * math.pi / SWELL_WAVELENGTH, 2.0 * math.pi / RIPPLE_WAVELENGTH
    swell = 0.5 * (1.0 - math.cos(k1 * x) * math.cos(k1 * z))
    ripple = 0.5 * (1.0 - math.sin(k2 * x + 0.7) * math.sin(k2 * z + 1.3))
    return -amplitude * (SWELL_SHARE * swell + (1.0 - SWELL_SHARE) * ripple)


class Terrain:
    """n x n quads of side size / n centred on the origin, two triangles a quad."""

    def __init__(self, quads, size, amplitude):
        self.n, self.size, self.cell = quads, size, size / quads
        self.x0 = -0.5 * size
        self.h = [[height(self.x0 + self.cell * i, self.x0 + self.cell * j, amplitude)
                   for i in range(quads + 1)] for j in range(quads + 1)]

    def triangles(self):
        return 2 * self.n * self.n

    def write_tile(self, path, i0, i1, j0, j1, depth):
        """Quads [i0, i1) x [j0, j1) of the grid as a closed OBJ: the surface, a skirt down to
        y = -depth along its border and a bottom fanned from its centre. Returns the centre of
        the volume it bounds, where rubble puts a closed mesh's origin (so the body's position
        must be this point for the file's coordinates to be the world's)."""
        top, ids = [], {}
        for j in range(j0, j1 + 1):
            for i in range(i0, i1 + 1):
                ids[i, j] = len(top) + 1
                top.append((self.x0 + self.cell * i, self.h[j][i], self.x0 + self.cell * j))
        # The border, counter-clockwise seen from above (+y): along -z edge, +x edge, +z, -x.
        border = ([(i, j0) for i in range(i0, i1)] + [(i1, j) for j in range(j0, j1)] +
                  [(i, j1) for i in range(i1, i0, -1)] + [(i0, j) for j in range(j1, j0, -1)])
        bottom = {}
        vertices = list(top)
        for key in border:
            x, _, z = top[ids[key] - 1]
            vertices.append((x, -depth, z))
            bottom[key] = len(vertices)
        cx = self.x0 + self.cell * 0.5 * (i0 + i1)
        cz = self.x0 + self.cell * 0.5 * (j0 + j1)
        vertices.append((cx, -depth, cz))
        centre = len(vertices)
        faces = []
        for j in range(j0, j1):
            for i in range(i0, i1):
                a, b, c, d = ids[i, j], ids[i + 1, j], ids[i, j + 1], ids[i + 1, j + 1]
                faces += [(a, c, b), (b, c, d)]
        for k, key in enumerate(border):
            nxt = border[(k + 1) % len(border)]
            # Wound against the surface's own border edges, so that each edge is used once
            # each way.
            faces += [(ids[key], bottom[nxt], bottom[key]), (ids[key], ids[nxt], bottom[nxt])]
            faces.append((centre, bottom[key], bottom[nxt]))
        volume, mean = 0.0, [0.0, 0.0, 0.0]
        for f in faces:
            a, b, c = (vertices[k - 1] for k in f)
            v = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
            volume += v
            for k in range(3):
                mean[k] += v * (a[k] + b[k] + c[k]) / 4.0
        with open(path, "w") as out:
            out.write("# terrain tile: quads %d-%d x %d-%d of %.4g m, closed below "
                      "(bench/terrain_scale.py)\n" % (i0, i1, j0, j1, self.cell))
            out.write("".join("v %r %r %r\n" % p for p in vertices))
            out.write("".join("f %d %d %d\n" % f for f in faces))
        return [m / volume for m in mean], len(faces)

    def surface(self, x, z):
        """Height of the triangles at (x, z), m; None outside the grid. Quad (i, j) is split along
        its diagonal from (i + 1, j) to (i, j + 1), as write_tile winds it."""
        u, v = (x - self.x0) / self.cell, (z - self.x0) / self.cell
        i, j = int(math.floor(u)), int(math.floor(v))
        if not (0 <= i < self.n and 0 <= j < self.n):
            return None
        s, t = u - i, v - j
        ha, hb = self.h[j][i], self.h[j][i + 1]
        hc, hd = self.h[j + 1][i], self.h[j + 1][i + 1]
        if s + t <= 1.0:
            return ha + s * (hb - ha) + t * (hc - ha)
        return hd + (1.0 - s) * (hc - hd) + (1.0 - t) * (hb - hd)


def rotate(q, p):
    """p turned by the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    px, py, pz = p
    # t = 2 (q.xyz x p); p' = p + w t + q.xyz x t
    tx, ty, tz = 2 * (y * pz - z * py), 2 * (z * px - x * pz), 2 * (x * py - y * px)
    return (px + w * tx + y * tz - z * ty, py + w * ty + z * tx - x * tz,
            pz + w * tz + x * ty - y * tx)


def deepest_below(rows, prefix, half, surface):
    """Deepest corner of the crates (bodies named prefix...) below the surface over the last
    written step, m (0 when none is), and the crate that holds it; also how many crates are off
    the floor's extent."""
    last = max(int(r["step"]) for r in rows)
    worst, who, off = 0.0, "", 0
    for r in rows:
        if int(r["step"]) != last or not r["body"].startswith(prefix):
            continue
        c = (float(r["px"]), float(r["py"]), float(r["pz"]))
        q = (float(r["qw"]), float(r["qx"]), float(r["qy"]), float(r["qz"]))
        for sx in (-1, 1):
            for sy in (-1, 1):
                for sz in (-1, 1):
                    o = rotate(q, (sx * half[0], sy * half[1], sz * half[2]))
                    p = (c[0] + o[0], c[1] + o[1], c[2] + o[2])
                    ground = surface(p[0], p[2])
                    if ground is None:
                        off += 1
                        continue
                    if ground - p[1] > worst:
                        worst, who = ground - p[1], r["body"]
    return worst, who, off // 8


# The run's arguments and CSV config name per --backend.
BACKENDS = {"cpu": ([], "cpu-sat-pgs"),
            "opencl": (["--backend", "opencl", "--collision", "sat"], "opencl-sat-pgs")}


def run(rubble, scene, steps, folder, tag, backend, extra):
    metrics, state = os.path.join(folder, tag + ".json"), os.path.join(folder, tag + ".csv")
    command = [rubble, "run", scene, "--steps", str(steps), "--every", str(steps),
               "--metrics", metrics, "--out", state] + BACKENDS[backend][0] + extra
    print(" ".join(command), flush=True)
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit("%s failed (exit %d): %s" % (tag, done.returncode, done.stderr.strip()))
    with open(metrics) as f:
        m = json.load(f)
    with open(state) as f:
        rows = list(csv.DictReader(f))
    return m, rows


def rest_scene(scene, rows, prefix, shape, mass):
    """scene with its generated crates replaced by bodies where rows' last step left them, at
    rest (no velocity), and sleep off so that every crate is stepped in full."""
    last = max(int(r["step"]) for r in rows)
    rest = json.loads(json.dumps(scene))
    rest["name"] = scene["name"] + "_at_rest"
    rest["simulation"]["sleep"] = False
    del rest["generators"]
    for r in rows:
        if int(r["step"]) == last and r["body"].startswith(prefix):
            rest["bodies"].append({
                "name": r["body"], "shape": shape, "mass": mass,
                "position": [float(r[k]) for k in ("px", "py", "pz")],
                "orientation": [float(r[k]) for k in ("qw", "qx", "qy", "qz")]})
    return rest


def write_rows(out, results):
    """The rows so far, each with its ms per step against the median of the same binary's plane
    runs in the same phase (blank until that binary has one)."""
    for r in results:
        plane = sorted(p["median_ms"] for p in results
                       if p["scene"] == "pile_on_plane" and p["binary"] == r["binary"] and
                       p.get("phase") == r.get("phase"))
        r["ratio_to_plane"] = r["median_ms"] / plane[len(plane) // 2] if plane else ""
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    with open(out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(results[0]))
        writer.writeheader()
        writer.writerows(results)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rubble", default=os.path.join(ROOT, "build", "rubble"))
    ap.add_argument("--quads", type=int, default=708, help="quads per side (2 n^2 triangles)")
    ap.add_argument("--size", type=float, default=354.0, help="the terrain's side, m")
    ap.add_argument("--tiles", type=int, default=2, help="meshes per side")
    ap.add_argument("--amplitude", type=float, default=1.0, help="crest to deepest hollow, m")
    ap.add_argument("--steps", type=int, default=900)
    ap.add_argument("--crates", default="32,16,32", help="the grid of crates (debris_16k's)")
    ap.add_argument("--base", help="a second rubble binary run alternately with --rubble")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--extra", action="append", default=[],
                    help="an argument added to --rubble's runs (repeat for more)")
    ap.add_argument("--base-extra", action="append", default=[],
                    help="an argument added to --base's runs (repeat for more)")
    ap.add_argument("--backend", choices=sorted(BACKENDS), default="cpu",
                    help="cpu, or opencl (the device's SAT + PGS path)")
    ap.add_argument("--at-rest", type=int, metavar="STEPS",
                    help="time STEPS steps of each pile where --steps left it, at rest, no sleep")
    ap.add_argument("--work", help="folder for the meshes, scenes and runs (default: a new one)")
    ap.add_argument("--out", help="CSV (default bench/results/<machine>/terrain_scale.csv)")
    args = ap.parse_args()

    folder = args.work or tempfile.mkdtemp(prefix="terrain_scale_")
    os.makedirs(folder, exist_ok=True)
    out = args.out or os.path.join(ROOT, "bench", "results", bench_run_module().machine_name(),
                                   "terrain_scale.csv")

    with open(os.path.join(ROOT, "scenes", "bench", "debris_16k.json")) as f:
        plane_scene = json.load(f)
    count = [int(c) for c in args.crates.split(",")]
    grid = plane_scene["generators"][0]
    grid["count"] = count
    grid["origin"] = [-0.5 * (count[0] - 1) * grid["spacing"][0], grid["origin"][1],
                      -0.5 * (count[2] - 1) * grid["spacing"][2]]
    plane_scene["name"] = "pile_on_plane"
    half = plane_scene["shapes"]["crate"]["half_extents"]

    # rubble reads at most 250,000 vertices from one OBJ: the terrain is tiles x tiles meshes.
    terrain = Terrain(args.quads, args.size, args.amplitude)
    mesh_scene = json.loads(json.dumps(plane_scene))
    mesh_scene["name"] = "pile_on_terrain_mesh"
    del mesh_scene["shapes"]["floor"]
    mesh_scene["bodies"] = [b for b in mesh_scene["bodies"] if b["name"] != "floor"]
    cuts = [args.quads * k // args.tiles for k in range(args.tiles + 1)]
    mesh_triangles = 0
    for tj in range(args.tiles):
        for ti in range(args.tiles):
            name = "terrain_%d_%d" % (ti, tj)
            centre, count = terrain.write_tile(os.path.join(folder, name + ".obj"), cuts[ti],
                                               cuts[ti + 1], cuts[tj], cuts[tj + 1],
                                               2.0 * args.amplitude + 1.0)
            mesh_triangles += count
            mesh_scene["shapes"][name] = {"type": "mesh", "file": name + ".obj"}
            mesh_scene["bodies"].append({"name": name, "shape": name, "static": True,
                                         "position": centre})
    scenes = {}
    for s in (plane_scene, mesh_scene):
        scenes[s["name"]] = os.path.join(folder, s["name"] + ".json")
        with open(scenes[s["name"]], "w") as f:
            json.dump(s, f, indent=1)

    floors = {"pile_on_plane": lambda x, z: 0.0, "pile_on_terrain_mesh": terrain.surface}
    binaries = [("base", args.base, args.base_extra)] if args.base else []
    binaries.append(("build", args.rubble, args.extra))
    results = []

    def row(name, binary, extra, k, m, rows, phase):
        worst, who, off = deepest_below(rows, grid["name_prefix"], half, floors[name])
        stages = m.get("stages_ms", {})
        r = {"scene": name, "config": BACKENDS[args.backend][1], "binary": binary,
             "args": " ".join(extra), "repeat": k,
             "floor_triangles": mesh_triangles if name != "pile_on_plane" else 0,
             "surface_triangles": terrain.triangles() if name != "pile_on_plane" else 0,
             "terrain_cell_m": round(terrain.cell, 5) if name != "pile_on_plane" else "",
             "bodies": m["bodies"], "steps": m["steps"],
             "mean_ms": 1000.0 * m["wall_s"] / m["steps"],
             "median_ms": m["ms_per_step"]["median"], "p90_ms": m["ms_per_step"]["p90"],
             "stage_broad_phase_ms": stages.get("broad_phase", 0.0) / m["steps"],
             "stage_narrow_phase_ms": stages.get("narrow_phase", 0.0) / m["steps"],
             "deepest_below_surface_m": worst, "deepest_body": who, "off_floor": off,
             "largest_penetration_m": m.get("largest_penetration", ""),
             "kinetic_energy_j": m.get("kinetic_energy", {}).get("last", ""),
             "asleep": m.get("asleep", {}).get("last", "")}
        if args.at_rest:
            r.update({"phase": phase,
                      "stage_build_rows_ms": stages.get("build_contact_rows", 0.0) / m["steps"],
                      "stage_solve_ms": stages.get("solve", 0.0) / m["steps"],
                      "contacts": m.get("contact_count", {}).get("last", "")})
        results.append(r)
        write_rows(out, results)

    if not args.at_rest:
        for k in range(args.repeat):
            for name, path in scenes.items():
                for binary, rubble, extra in binaries:
                    m, rows = run(rubble, path, args.steps, folder,
                                  "%s_%s_%d" % (name, binary, k), args.backend, extra)
                    row(name, binary, extra, k, m, rows, "")
    else:
        # The drop, once per scene (with --rubble), then its last state at rest, timed.
        crate = grid["shape"]
        rest_scenes = {}
        for name, path in scenes.items():
            m, rows = run(args.rubble, path, args.steps, folder, "%s_drop" % name,
                          args.backend, args.extra)
            row(name, "build", args.extra, 0, m, rows, "drop")
            with open(path) as f:
                scene = json.load(f)
            rest_scenes[name] = os.path.join(folder, name + "_at_rest.json")
            with open(rest_scenes[name], "w") as f:
                json.dump(rest_scene(scene, rows, grid["name_prefix"], crate, grid["mass"]), f)
        for k in range(args.repeat):
            for name, path in rest_scenes.items():
                for binary, rubble, extra in binaries:
                    m, rows = run(rubble, path, args.at_rest, folder,
                                  "%s_rest_%s_%d" % (name, binary, k), args.backend, extra)
                    row(name, binary, extra, k, m, rows, "rest")
    write_rows(out, results)
    print("wrote %s (work folder %s)" % (out, folder))
    for r in results:
        print("%-5s " % r.get("phase", ""), end="")
        print("%-22s %-5s %8d tris  mean %8.2f ms  median %8.2f ms  p90 %8.2f ms  narrow %8.2f ms"
              "  deepest %.4f m (%s)  ratio %.2f" % (
                  r["scene"], r["binary"], r["floor_triangles"], r["mean_ms"], r["median_ms"],
                  r["p90_ms"], r["stage_narrow_phase_ms"], r["deepest_below_surface_m"],
                  r["deepest_body"], r["ratio_to_plane"]))


if __name__ == "__main__":
    main()
