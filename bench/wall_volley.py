#!/usr/bin/env python3
"""The tunnelling target: 1,000 crates fired at 200 m/s at a static wall 5 cm thick, the wall a
box (scenes/bench/wall_volley_1k.json) and the same wall as a triangle mesh
(scenes/bench/wall_volley_mesh_1k.json); how many crates end up past it.

  bench/wall_volley.py                     # writes the mesh scene, runs both on the CPU
  bench/wall_volley.py --write-only        # only (re)writes the mesh and its scene
  bench/wall_volley.py --configs cpu,opencl-sat   # the device's SAT path too

Each run writes every step (`rubble run --out`); a crate has passed when its centre is ever
beyond the wall's near face (x > -0.025 m), and is through when it ends beyond its far face
(x > 0.025 m). One CSV row per scene and configuration goes to
bench/results/<machine>/wall_volley.csv (--out). Python's standard library only.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BOX_SCENE = os.path.join(ROOT, "scenes", "bench", "wall_volley_1k.json")
MESH_SCENE = os.path.join(ROOT, "scenes", "bench", "wall_volley_mesh_1k.json")
MESH_FILE = os.path.join(ROOT, "scenes", "meshes", "wall_5cm.obj")
CELL = 1.0  # m, the largest quad of the mesh wall's faces

CONFIGS = {
    "cpu": ["--backend", "cpu"],
    "opencl-sat": ["--backend", "opencl", "--collision", "sat", "--solver", "pgs"],
}


def box_obj(half, cell):
    """The box [-half, half] with every face cut into quads of side at most `cell`, wound
    counter-clockwise seen from outside."""
    lines = ["# a wall %g x %g x %g m, faces cut into quads of at most %g m "
             "(bench/wall_volley.py)" % (2 * half[0], 2 * half[1], 2 * half[2], cell)]
    count = 0
    for axis in range(3):
        for side in (-1, 1):
            u, v = (axis + 1) % 3, (axis + 2) % 3
            if side < 0:
                u, v = v, u
            nu = max(1, int(-(-2 * half[u] // cell)))
            nv = max(1, int(-(-2 * half[v] // cell)))
            first = count + 1
            for j in range(nv + 1):
                for i in range(nu + 1):
                    p = [0.0, 0.0, 0.0]
                    p[axis] = side * half[axis]
                    p[u] = -half[u] + 2 * half[u] * i / nu
                    p[v] = -half[v] + 2 * half[v] * j / nv
                    lines.append("v %g %g %g" % tuple(round(c, 5) for c in p))
                    count += 1
            for j in range(nv):
                for i in range(nu):
                    a = first + j * (nu + 1) + i
                    b, c = a + 1, a + nu + 1
                    lines.append("f %d %d %d\nf %d %d %d" % (a, b, c + 1, a, c + 1, c))
    return "\n".join(lines) + "\n"


def write_mesh_scene():
    """The box scene with its wall replaced by the same box as a triangle mesh."""
    with open(BOX_SCENE) as f:
        scene = json.load(f)
    half = scene["shapes"]["wall"]["half_extents"]
    with open(MESH_FILE, "w") as f:
        f.write(box_obj(half, CELL))
    scene["name"] = "wall_volley_mesh_1k"
    scene["shapes"]["wall"] = {"type": "mesh", "file": "../meshes/wall_5cm.obj"}
    with open(MESH_SCENE, "w") as f:
        f.write(json.dumps(scene, indent=2) + "\n")


def volley(rubble, scene, config, folder):
    """(crates, passed the near face at any step, through at the end, steps, median ms/step) and
    no error, or None and (exit status, the first line of stderr)."""
    tag = os.path.splitext(os.path.basename(scene))[0] + "-" + config
    out, metrics = os.path.join(folder, tag + ".csv"), os.path.join(folder, tag + ".json")
    command = [rubble, "run", scene, "--out", out, "--metrics", metrics] + CONFIGS[config]
    print(" ".join(os.path.relpath(w, ROOT) if w.startswith(ROOT) else w for w in command),
          flush=True)
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        # The first line says why; paths are the repository's or the run's own folder.
        lines = done.stderr.strip().splitlines()
        why = lines[0].replace(ROOT + "/", "").replace(folder + "/", "") if lines else ""
        return None, (done.returncode, why)
    passed, last, final = set(), 0, {}
    with open(out) as f:
        for r in csv.DictReader(f):
            if not r["body"].startswith("crate"):
                continue
            x = float(r["px"])
            if x > -0.025:
                passed.add(r["body"])
            step = int(r["step"])
            last = max(last, step)
            if step == last:
                final[r["body"]] = x
    with open(metrics) as f:
        m = json.load(f)
    through = sum(1 for x in final.values() if x > 0.025)
    return (len(final), len(passed), through, m["steps"], m["ms_per_step"]["median"]), None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rubble", default=os.path.join(ROOT, "build", "rubble"))
    ap.add_argument("--configs", default="cpu")
    ap.add_argument("--write-only", action="store_true")
    ap.add_argument("--out", help="CSV (default bench/results/<machine>/wall_volley.csv)")
    args = ap.parse_args()
    write_mesh_scene()
    if args.write_only:
        return
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from terrain_scale import bench_run_module
    out = args.out or os.path.join(ROOT, "bench", "results", bench_run_module().machine_name(),
                                   "wall_volley.csv")
    folder = tempfile.mkdtemp(prefix="wall_volley_")
    rows = []
    for scene in (BOX_SCENE, MESH_SCENE):
        for config in args.configs.split(","):
            result, error = volley(args.rubble, scene, config, folder)
            name = os.path.splitext(os.path.basename(scene))[0]
            if result is None:
                rows.append({"scene": name, "config": config, "status": "exit %d" % error[0],
                             "note": error[1]})
                continue
            crates, passed, through, steps, median = result
            rows.append({"scene": name, "config": config, "status": "ok", "crates": crates,
                         "steps": steps, "passed_near_face": passed, "through_at_end": through,
                         "median_ms": median})
    fields = ["scene", "config", "status", "crates", "steps", "passed_near_face",
              "through_at_end", "median_ms", "note"]
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    for r in rows:
        print(", ".join("%s=%s" % (k, r.get(k, "")) for k in fields))
    print("wrote", out)


if __name__ == "__main__":
    main()
