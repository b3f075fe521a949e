#!/usr/bin/env bash
# SPH cost benchmark: the paper's dam break (parameters/dam_break.prm, ~54k markers) for a fixed
# number of steps at a fixed step; prints the time per step by phase (from summary.json),
# particle-steps per second and memory per particle.
#   benchmarks/sph_dam_break/run_benchmark.sh [STEPS=1000] [BACKEND=cpu]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
steps=${1:-1000}
backend=${2:-cpu}
out=${OUT:-$root/output/sph_benchmark}
dt=2e-4
end=$(/usr/bin/python3 -c "print($steps * $dt)")
scene=$(mktemp --suffix=.prm)
sed -e "s/set End time         = 2.5/set End time         = $end/" \
    -e "s/set Output interval  = 0.05/set Output interval  = 0/" \
    -e "s/set CFL number        = 1/set CFL number        = 0/" \
    -e "s/set Time step         = 2e-3/set Time step         = $dt\n  set Backend = $backend\n  set Max iterations = 20000/" \
    "$root/parameters/dam_break.prm" > "$scene"
"${TWINFLOW_BIN:-$root/build/twinflow}" "$scene" -o "$out"
rm -f "$scene"
/usr/bin/python3 - "$out/sph/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
steps = s["time_stepping"]["steps"]
wall = s["cost"]["wall_time_s"]
x = s["extra"]
print(f"\nSPH dam break benchmark: {s['size']['particles']} markers, {steps} steps, backend {x['backend']}")
print(f"wall time {wall:.1f} s = {1e3 * wall / steps:.1f} ms/step; particle-steps/s "
      f"{x['particle-steps per second']:.3g}; memory/particle {x['memory per particle [B]']} B; "
      f"neighbours/particle {x['neighbour entries per particle']:.1f}")
for name, sec in s["cost"]["sections"].items():
    print(f"  {name:28s} {1e3 * sec['wall_time_s'] / steps:8.2f} ms/step")
print(f"projected time for 1000 steps: {1000 * wall / steps:.0f} s (paper, RTX 2080 GPU: 151 s)")
PY
