#!/usr/bin/env bash
# bench/opencl_pipeline.sh: ms/step of the debris scenes for cpu-sat-pgs, cpu-particles-jacobi
# and opencl-particles-jacobi side by side, with the per-stage breakdown (medians of the run's
# steps; stage times are totals over the run divided by its steps).
# usage: bench/opencl_pipeline.sh [BUILD_DIR] [STEPS] [SCENES...]
#   defaults: build-gpu, 60 steps, debris_1k debris_4k debris_16k (add debris_64k by name)
#   RUBBLE_BENCH_CONFIGS picks the configurations (default: all three), e.g.
#   RUBBLE_BENCH_CONFIGS=opencl-particles-jacobi for the device alone
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-gpu}
steps=${2:-60}
shift $(( $# > 2 ? 2 : $# ))
scenes=("$@")
((${#scenes[@]})) || scenes=(debris_1k debris_4k debris_16k)
spacing=${RUBBLE_BENCH_SPACING:-0.5}
read -r -a configs <<<"${RUBBLE_BENCH_CONFIGS:-cpu-sat-pgs cpu-particles-jacobi opencl-particles-jacobi}"
out=$(mktemp -d)
printf '%-11s %-24s %9s %9s %8s %8s %8s %8s %8s %9s\n' scene config median_ms p90_ms integ grid collide rows solve contacts
for scene in "${scenes[@]}"; do
  for config in "${configs[@]}"; do
    IFS=- read -r backend collision solver <<<"$config"
    metrics="$out/$scene-$config.json"
    "$build/rubble" run "scenes/bench/$scene.json" --steps "$steps" --backend "$backend" \
      --collision "$collision" --solver "$solver" --particle-spacing "$spacing" \
      --metrics "$metrics" --quiet >/dev/null
    python3 - "$scene" "$config" "$metrics" <<'PY'
import json, sys
scene, config, path = sys.argv[1:]
m = json.load(open(path))
n = max(1, m["steps"])
s = {k: v / n for k, v in m["stages_ms"].items()}
print(f'{scene:<11} {config:<24} {m["ms_per_step"]["median"]:9.2f} {m["ms_per_step"]["p90"]:9.2f} '
      f'{s["integrate_velocities"] + s["integrate_positions"]:8.2f} {s["broad_phase"]:8.2f} '
      f'{s["narrow_phase"]:8.2f} {s["build_contact_rows"]:8.2f} {s["solve"]:8.2f} '
      f'{m["contact_count"]["last"]:9d}')
PY
  done
done
rm -rf "$out"
