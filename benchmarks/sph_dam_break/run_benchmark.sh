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
# The committed scene with its step, output and method overridden (--set: robust to the scene's
# own values changing); SPH alone, a fixed step, no CFL control, no snapshots.
"${TWINFLOW_BIN:-$root/build/twinflow}" "$root/parameters/dam_break.prm" \
    --set "Scene/Methods=sph" --set "Scene/End time=$end" --set "Scene/Output interval=0" \
    --set "Scene/Snapshot times=" --set "SPH/CFL number=0" --set "SPH/Time step=$dt" \
    --set "SPH/Backend=$backend" --set "SPH/Max iterations=20000" -o "$out"
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
