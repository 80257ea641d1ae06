#!/usr/bin/env bash
# bench/explosion.sh: frame time of scenes/explosion.json with 1,024 to 65,536 crates in the wall,
# everything on the CPU (--backend cpu: SAT and PGS) against the crates offloaded to the OpenCL
# device (--backend opencl: the crates on the device, the ragdoll and props on the CPU), side by
# side in one run; with offloading also the host's own time per step, what it waited for the
# device, and the share of the device's time hidden behind the host's work.
# usage: bench/explosion.sh [BUILD_DIR] [STEPS] [SIZES...]
#   defaults: build, 90 steps (the explosion is at step 30), sizes 1024 4096 16384 65536.
#   The 65,536 case runs RUBBLE_BENCH_LARGE_STEPS steps (default 60) to keep the whole script
#   within a few minutes on 2 cores; RUBBLE_BENCH_CSV=FILE also writes the table as CSV.
# Each size is the scene with the crate grid's count, origin and the explosion's radius changed
# (written into a temporary folder): the wall grows in width, height and thickness, its front
# face and the props stay where they are, and the explosion still reaches the whole wall.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
steps=${2:-90}
shift $(($# > 2 ? 2 : $#))
sizes=("$@")
((${#sizes[@]})) || sizes=(1024 4096 16384 65536)
large_steps=${RUBBLE_BENCH_LARGE_STEPS:-60}
csv=${RUBBLE_BENCH_CSV:-}
[[ -x "$build/rubble" ]] || { echo "bench/explosion.sh: no $build/rubble (build first)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# The variant of scenes/explosion.json with n crates.
make_scene() {
  python3 - "$1" "$2" <<'PY'
import json, sys
n, path = int(sys.argv[1]), sys.argv[2]
counts = {1024: (32, 8, 4), 4096: (64, 8, 8), 16384: (128, 16, 8), 65536: (128, 32, 16)}
if n not in counts:
    sys.exit(f"bench/explosion.sh: no wall of {n} crates (choose from {sorted(counts)})")
scene = json.load(open("scenes/explosion.json"))
grid = next(g for g in scene["generators"] if g.get("debris"))
x, y, z = counts[n]
sx, sy, sz = grid["spacing"]
front = grid["origin"][2] + (4 - 1) * sz  # the front row of the shipped 32 x 8 x 4 wall
grid["count"] = [x, y, z]
grid["origin"] = [-(x - 1) * sx / 2, grid["origin"][1], front - (z - 1) * sz]
# The blast sits behind the wall's back row and reaches its far corners.
blast = scene["events"][0]
back = front - (z - 1) * sz
blast["centre"][2] = back - 1.1
far = ((x * sx / 2) ** 2 + (y * sy) ** 2 + (z * sz + 1.1) ** 2) ** 0.5
blast["radius"] = max(blast["radius"], round(1.1 * far, 1))
scene["name"] = f"explosion_{n}"
json.dump(scene, open(path, "w"), indent=1)
PY
}

header='debris,backend,steps,median_ms,p90_ms,host_ms,wait_ms,device_ms,hidden_share,contacts_max'
[[ -n "$csv" ]] && echo "$header" >"$csv"
printf '%7s %-7s %5s %9s %9s %8s %8s %9s %7s %12s\n' debris backend steps median_ms p90_ms \
  host_ms wait_ms device_ms hidden contacts_max
for n in "${sizes[@]}"; do
  scene="$out/explosion_$n.json"
  make_scene "$n" "$scene"
  run_steps=$steps
  ((n < 65536)) || run_steps=$large_steps
  for backend in cpu opencl; do
    metrics="$out/$n-$backend.json"
    "$build/rubble" run "$scene" --steps "$run_steps" --backend "$backend" --metrics "$metrics" \
      --quiet >/dev/null
    python3 - "$n" "$backend" "$metrics" "$csv" <<'PY'
import json, sys
n, backend, path, csv = sys.argv[1:]
m = json.load(open(path))
med, p90 = m["ms_per_step"]["median"], m["ms_per_step"]["p90"]
if backend == "opencl":
    host = m["host_ms_per_step"]["median"]
    wait = m["device_wait_ms_per_step"]["median"]
    device = m["device_ms_per_step"]["median"]
    hidden = m["device_hidden_share"]
else:
    # Everything on the CPU: the whole step is the host's, nothing runs beside it.
    host, wait, device, hidden = med, 0.0, 0.0, 0.0
row = [n, backend, m["steps"], med, p90, host, wait, device, hidden, m["contact_count"]["max"]]
print(f"{n:>7} {backend:<7} {m['steps']:>5} {med:9.2f} {p90:9.2f} {host:8.2f} {wait:8.2f} "
      f"{device:9.2f} {hidden:7.3f} {m['contact_count']['max']:12d}")
if csv:
    with open(csv, "a") as f:
        f.write(",".join(f"{v:.3f}" if isinstance(v, float) else str(v) for v in row) + "\n")
PY
  done
done
