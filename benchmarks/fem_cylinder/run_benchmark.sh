#!/usr/bin/env bash
# FEM cost benchmark: the periodic cylinder (paper 4.1, parameters/cylinder_periodic.prm, FEM
# with the immersed cylinder) for STEPS steps of 0.01 s from rest, the whole run timed (set-up,
# adaptation, every step, monitors, summary), on 1 and 2 MPI ranks, at two sizes:
#   uniform  — Global refinements 5, no adaptation: 10,240 cells, the paper's size (8k cells,
#              Table 1: 1049 s per 1000 steps on one i9 core);
#   band AMR — Global refinements 2 + band level 5: 868 cells, the same finest cell and the
#              same C_d error (doc/benchmarks.md, "AMR pays").
# Prints s per 1000 steps and s per simulated second, and the C_d error at the end
# (after STEPS steps: steady only with STEPS >= 700).
#   benchmarks/fem_cylinder/run_benchmark.sh [STEPS=1000]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
steps=${1:-1000}
out=${OUT:-$root/output/fem_cylinder_benchmark}
bin=${TWINFLOW_BIN:-$root/build/twinflow}
end=$(/usr/bin/python3 -c "print($steps * 0.01)")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
common=(--set "Scene/Methods=fem" --set "Scene/End time=$end" --set "FEM/Time step=0.01")
declare -A sizes=(
  [uniform]='--set FEM/Global\ refinements=5 --set FEM/Mesh\ adaptation/Maximum\ level=0'
  [amr]='--set FEM/Global\ refinements=2 --set FEM/Mesh\ adaptation/Maximum\ level=5')
for size in uniform amr; do
  for np in 1 2; do
    eval "extra=(${sizes[$size]})"
    mpirun -np "$np" "$bin" "$root/parameters/cylinder_periodic.prm" "${common[@]}" "${extra[@]}" \
      -o "$out/${size}_np$np" > "$out.${size}_np$np.log" 2>&1 || { echo "run $size np$np failed"; exit 1; }
  done
done
/usr/bin/python3 - "$out" <<'PY'
import json, sys, os
out = sys.argv[1]
print("| mesh | ranks | cells | DoFs | steps | wall [s] | s per 1000 steps | s per simulated s | C_d error |")
print("|---|---|---|---|---|---|---|---|---|")
for size in ("uniform", "amr"):
    for np in (1, 2):
        s = json.load(open(os.path.join(out, f"{size}_np{np}", "fem", "summary.json")))
        steps = s["time_stepping"]["steps"]; wall = s["cost"]["wall_time_s"]
        t = s["time_stepping"]["final_time_s"]
        err = next((e["relative_error"] for e in s.get("errors", []) if e["quantity"].startswith("drag")), float("nan"))
        dofs = sum(s["size"]["dofs"].values())
        print(f"| {size} | {np} | {s['size']['cells']} | {dofs} | {steps} | {wall:.1f} | {1e3*wall/steps:.0f} | "
              f"{wall/t:.1f} | {100*err:.2f} % |")
PY
