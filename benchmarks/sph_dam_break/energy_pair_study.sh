#!/usr/bin/env bash
# What the energy costs in time: the Martin & Moyce collapse at alpha = 1
# (parameters/stability/dam_break_alpha1.prm) with the default consistent operators and with
# SPH/Energy-conserving pair, at a/10, a/20 and a/40 (the spacing and the step halved together,
# CFL 0.2), each a whole run to t = 0.18 s. scripts/study.py writes the table (study.md, study.csv)
# and plots each error (the energy rise above E0, the front) against wall time and particle count;
# scripts/study_series.py draws one line per path.
# ~7 min on 2 cores (the pair at a/40 takes 5 of them).
#   benchmarks/sph_dam_break/energy_pair_study.sh [OUT=output/study_energy_pair]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:-$root/output/study_energy_pair}
/usr/bin/python3 "$root/scripts/study.py" "$root/parameters/stability/dam_break_alpha1.prm" --zip \
    --vary "SPH/Energy-conserving pair=false,false,false,true,true,true" \
    --vary "SPH/Particle spacing=0.005715,0.0028575,0.00142875,0.005715,0.0028575,0.00142875" \
    --vary "SPH/Time step=5e-4,2.5e-4,1.25e-4,5e-4,2.5e-4,1.25e-4" \
    --out "$out" ${TWINFLOW_BIN:+--twinflow "$TWINFLOW_BIN"}
# one line per path: energy.png / energy.md (doc/figures/sph_energy_pair_study.png)
/usr/bin/python3 "$root/scripts/study_series.py" "$out/study.csv" \
    --series "default operators:SPH/Energy-conserving pair=false" \
    --series "energy-conserving pair:SPH/Energy-conserving pair=true" \
    --quantity "energy rise above the initial value (max over the run)" --out "$out/energy" \
    --title "Martin & Moyce, alpha = 1, a/10 - a/40: energy rise above E0 against cost"
