#!/usr/bin/env bash
# Performance benchmark: twinflow's projection Navier-Stokes solver against deal.II's
# step-35 tutorial (same Guermond-type incremental projection, Q2/Q1 Taylor-Hood) on the
# DFG 2D-2 problem (Schaefer & Turek 1996: channel with cylinder, Re = 100, unsteady).
#
#   benchmarks/step35/run_benchmark.sh            # from the repository root (or anywhere)
#
# What it does (see doc/performance.md for the discussion of the numbers):
#   1. copies step-35 from Debian's libdeal.ii-doc (installs the package with apt-get if
#      the examples are missing; gunzips *.gz sources) into $WORK/src, configures it with
#      cmake in Release mode in $WORK/bld and builds it (make -j$JOBS);
#   2. runs step-35 ($S35_REFINES global refinements of nsbench2.inp, Re = 100,
#      dt = $DT35, $STEPS steps, no intermediate output) with 1 thread and with 2 threads
#      (DEAL_II_NUM_THREADS; step-35 is serial, only its assembly is multithreaded);
#   3. runs build/twinflow parameters/benchmarks/dfg_2d2.prm at the global refinement
#      levels $OUR_LEVELS, on 1 rank and with mpirun -np 2, with the same non-dimensional
#      time step and number of steps;
#   4. prints a table and writes it to benchmarks/step35/results.md (raw numbers:
#      $WORK/results.json).
#
# Time scaling: step-35's mesh is the DFG geometry scaled by 10 (D = 1, U_mean = 1,
# nu = 1/Re; its channel is 25 long instead of 22). Its time unit D/U_mean is 10x ours,
# so step-35's dt = 5e-3 is our dt = 5e-4 (the same CFL number).
#
# Equal DoFs: our coarse mesh (GridGenerator::channel_with_cylinder, 108 cells) and
# step-35's (nsbench2.inp, 60 cells) differ, so no refinement level gives exactly the
# same DoF count: step-35 n_of_refines = 3 has 35,440 DoFs, our levels 2 and 3 have
# 16,152 and 63,408. The table gives both of our levels and our time per step
# interpolated (power law between the two levels) to step-35's DoF count.
#
# Timings: every program is started by a small Python wrapper that timestamps its output.
#   process wall  = launch to exit (includes MPI start-up, and for twinflow the PNG plots)
#   setup         = step-35: launch to the line "Step = 2" (mesh, DoFs, matrices,
#                   initial output); twinflow: summary.json sections.setup
#   loop          = step-35: "Step = 2" to exit (all time steps + final output);
#                   twinflow: summary.json cost.wall_time_s - sections.setup (mesh
#                   generation, all time steps, monitors, final output)
#   ms/step       = loop / steps   (the number the ratio and the speed-up use)
#
# Environment overrides: STEPS (200), DT35 (5e-3), S35_REFINES (3), OUR_LEVELS ("2 3"),
# S35_THREADS ("1 2"), RANKS ("1 2"), JOBS ($(nproc)), TWINFLOW (build/twinflow),
# WORK (build-step35 in the repository root; git-ignored by build-*/), NICE ("" or "nice").
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
STEPS=${STEPS:-200}
DT35=${DT35:-5e-3}
S35_REFINES=${S35_REFINES:-3}
OUR_LEVELS=${OUR_LEVELS:-"2 3"}
S35_THREADS=${S35_THREADS:-"1 2"}
RANKS=${RANKS:-"1 2"}
JOBS=${JOBS:-$(nproc)}
TWINFLOW=${TWINFLOW:-$REPO/build/twinflow}
WORK=${WORK:-$REPO/build-step35}
NICE=${NICE:-}
SCENE=$REPO/parameters/benchmarks/dfg_2d2.prm
RESULTS_MD=$REPO/benchmarks/step35/results.md
RESULTS_JSON=$WORK/results.json
EXAMPLES=/usr/share/doc/libdeal.ii-doc/examples/step-35

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1
LOAD_START=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)

log() { printf '\n=== %s\n' "$*"; }
die() { printf 'run_benchmark.sh: %s\n' "$*" >&2; exit 1; }

[[ -x $TWINFLOW ]] || die "$TWINFLOW not found: build twinflow first (cmake --build build)"
[[ -f $SCENE ]] || die "$SCENE not found"
command -v python3 >/dev/null || die "python3 is needed (timing wrapper, table)"
command -v cmake >/dev/null || die "cmake is needed"

# ---- 1. step-35 sources and build ---------------------------------------------------------
if [[ ! -d $EXAMPLES ]]; then
  log "installing libdeal.ii-doc (step-35 sources)"
  SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO=sudo
  $SUDO apt-get install -y libdeal.ii-doc
fi
[[ -d $EXAMPLES ]] || die "$EXAMPLES still missing after installing libdeal.ii-doc"

mkdir -p "$WORK/src" "$WORK/bld"
cp -p "$EXAMPLES"/* "$WORK/src/"
for gz in "$WORK"/src/*.gz; do
  [[ -e $gz ]] || continue
  gunzip -f "$gz"
done
[[ -f $WORK/src/step-35.cc && -f $WORK/src/nsbench2.inp ]] || die "step-35.cc / nsbench2.inp missing in $WORK/src"

log "building step-35 (Release) in $WORK/bld"
( cd "$WORK/bld" && $NICE cmake -DCMAKE_BUILD_TYPE=Release ../src >cmake.log 2>&1 ) \
  || { tail -20 "$WORK/bld/cmake.log"; die "cmake failed (log: $WORK/bld/cmake.log)"; }
grep -q 'CMAKE_BUILD_TYPE:STRING=Release' "$WORK/bld/CMakeCache.txt" || die "step-35 is not configured in Release"
( cd "$WORK/bld" && $NICE make -j"$JOBS" >make.log 2>&1 ) \
  || { tail -20 "$WORK/bld/make.log"; die "make failed (log: $WORK/bld/make.log)"; }
STEP35=$WORK/bld/step-35
[[ -x $STEP35 ]] || die "step-35 binary not built"

# ---- timing wrapper ---------------------------------------------------------------------
cat >"$WORK/timed_run.py" <<'PY'
"""timed_run.py OUT.json LOG MARK_REGEX -- CMD...: run CMD (stdout+stderr to LOG) and
write {"wall_s": launch->exit, "mark_s": launch->first line matching MARK_REGEX, "rc"}."""
import json, re, subprocess, sys, time
out, logname, mark = sys.argv[1], sys.argv[2], re.compile(sys.argv[3])
cmd = sys.argv[sys.argv.index("--") + 1:]
t0 = time.perf_counter()
t_mark = None
with open(logname, "w") as log:
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
    for line in p.stdout:
        if t_mark is None and mark.search(line):
            t_mark = time.perf_counter() - t0
        log.write(line)
    rc = p.wait()
wall = time.perf_counter() - t0
json.dump({"wall_s": wall, "mark_s": t_mark, "rc": rc, "cmd": cmd}, open(out, "w"), indent=1)
sys.exit(rc)
PY

# ---- 2. step-35 runs --------------------------------------------------------------------
# step-35 runs the steps n = 2 .. floor(final_time/dt): final_time = (STEPS + 1.5) dt
# gives exactly STEPS steps.
T35=$(python3 -c "print(repr(($STEPS + 1.5) * $DT35))")
RUN35=$WORK/run
mkdir -p "$RUN35"
cp "$WORK/src/nsbench2.inp" "$RUN35/"
cat >"$RUN35/parameter-file.prm" <<EOF
# generated by benchmarks/step35/run_benchmark.sh (DFG 2D-2, Re = 100)
set Method_Form = rotational
subsection Physical data
  set initial_time = 0.
  set final_time   = $T35
  set Reynolds     = 100
end
subsection Time step data
  set dt = $DT35
end
subsection Space discretization
  set n_of_refines = $S35_REFINES
  set pressure_fe_degree = 1
end
subsection Data solve velocity
  set max_iterations = 1000
  set eps            = 1e-8
  set Krylov_size    = 30
  set off_diagonals  = 70
  set diag_strength  = 0.1
  set update_prec    = 10
end
# only the initial and the final state are written
set output_interval = 100000000
set verbose = false
EOF

for th in $S35_THREADS; do
  log "step-35: n_of_refines = $S35_REFINES, dt = $DT35, $STEPS steps, $th thread(s)"
  rm -f "$RUN35"/solution-*.vtk
  ( cd "$RUN35" && DEAL_II_NUM_THREADS=$th $NICE python3 "$WORK/timed_run.py" \
      "timing_t$th.json" "log_t$th.txt" '^Step = 2 ' -- "$STEP35" ) \
    || { tail -20 "$RUN35/log_t$th.txt"; die "step-35 failed"; }
  grep -q 'Apparently everything went fine' "$RUN35/log_t$th.txt" || die "step-35 did not finish"
  tail -n 6 "$RUN35/log_t$th.txt" | head -n 1
done

# ---- 3. twinflow runs -------------------------------------------------------------------
DT_OURS=$(python3 -c "print(repr($DT35 / 10))")
T_OURS=$(python3 -c "print(repr($STEPS * $DT35 / 10))")
OURS=$WORK/twinflow
mkdir -p "$OURS"
for lvl in $OUR_LEVELS; do
  prm=$OURS/dfg_2d2_l$lvl.prm
  # Overrides on a copy of the scene (the lines must exist: checked below).
  sed -e "s/^\( *set Global refinements *=\).*/\1 $lvl/" \
      -e "s/^\( *set Time step *=\).*/\1 $DT_OURS/" \
      -e "s/^\( *set End time *=\).*/\1 $T_OURS/" \
      "$SCENE" >"$prm"
  grep -Eq "^ *set Global refinements *= $lvl\$" "$prm" &&
    grep -Eq "^ *set Time step *= $DT_OURS\$" "$prm" &&
    grep -Eq "^ *set End time *= $T_OURS\$" "$prm" || die "could not set level/dt/end time in $prm"
  for np in $RANKS; do
    out=$OURS/l${lvl}_np$np
    rm -rf "$out"
    log "twinflow: level $lvl, dt = $DT_OURS, $STEPS steps, $np MPI rank(s)"
    if [[ $np -eq 1 ]]; then
      launcher=()
    else
      launcher=(mpirun -np "$np")
    fi
    $NICE python3 "$WORK/timed_run.py" "$OURS/timing_l${lvl}_np$np.json" "$OURS/log_l${lvl}_np$np.txt" \
        '^FEM mesh' -- "${launcher[@]}" "$TWINFLOW" "$prm" -o "$out" \
      || { tail -20 "$OURS/log_l${lvl}_np$np.txt"; die "twinflow failed (level $lvl, $np ranks)"; }
    grep -E '^ *cost ' "$OURS/log_l${lvl}_np$np.txt" || true
  done
done

# ---- 4. table ---------------------------------------------------------------------------
LOAD_END=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)
log "results"
LOAD="$LOAD_START / $LOAD_END" python3 - "$WORK" "$STEPS" "$DT35" "$DT_OURS" "$S35_REFINES" "$OUR_LEVELS" "$S35_THREADS" "$RANKS" \
  "$RESULTS_MD" "$RESULTS_JSON" <<'PY'
import json, math, os, re, subprocess, sys, datetime
work, steps, dt35, dtours, r35, levels, threads, ranks, md_path, json_path = sys.argv[1:]
steps = int(steps); levels = levels.split(); threads = threads.split(); ranks = ranks.split()

def cpu_model():
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"

rows = []
# step-35
for th in threads:
    t = json.load(open(f"{work}/run/timing_t{th}.json"))
    log = open(f"{work}/run/log_t{th}.txt").read()
    cells = int(re.search(r"Number of active cells: (\d+)", log).group(1))
    nu = int(re.search(r"dim \(X_h\) = (\d+)", log).group(1))
    npr = int(re.search(r"dim \(M_h\) = (\d+)", log).group(1))
    n = len(re.findall(r"^Step = ", log, re.M))
    assert n == steps, f"step-35 did {n} steps, expected {steps}"
    setup = t["mark_s"]; loop = t["wall_s"] - setup
    rows.append(dict(code="step-35", par=f"serial, {th} thread{'s' if th != '1' else ''}",
                     ranks=1, threads=int(th), level=f"n_of_refines {r35}", cells=cells,
                     dofs=nu + npr, dofs_u=nu, dofs_p=npr, steps=n, process_s=t["wall_s"],
                     setup_s=setup, loop_s=loop, ms_step=1e3 * loop / n, sections={}))
# twinflow
for lvl in levels:
    for np_ in ranks:
        t = json.load(open(f"{work}/twinflow/timing_l{lvl}_np{np_}.json"))
        s = json.load(open(f"{work}/twinflow/l{lvl}_np{np_}/fem/summary.json"))
        n = s["time_stepping"]["steps"]
        assert n == steps, f"twinflow did {n} steps, expected {steps}"
        sec = s["cost"]["sections"]
        setup = sec.get("setup", {}).get("wall_time_s", 0.0)
        loop = s["cost"]["wall_time_s"] - setup
        rows.append(dict(code="twinflow", par=f"{np_} MPI rank{'s' if np_ != '1' else ''}",
                         ranks=int(np_), threads=1, level=f"level {lvl}", cells=s["size"]["cells"],
                         dofs=s["size"]["dofs_total"], dofs_u=s["size"]["dofs"]["velocity"],
                         dofs_p=s["size"]["dofs"]["pressure"], steps=n, process_s=t["wall_s"],
                         setup_s=setup, loop_s=loop, ms_step=1e3 * loop / n,
                         summary_wall_s=s["cost"]["wall_time_s"],
                         summary_ms_step=1e3 * s["cost"]["wall_time_per_step_s"],
                         sections={k: v["wall_time_s"] for k, v in sec.items()},
                         monitors=s["monitors"]))

ref = next(r for r in rows if r["code"] == "step-35" and r["threads"] == 1)
for r in rows:
    r["ratio"] = r["ms_step"] / ref["ms_step"]
    r["ns_step_dof"] = 1e6 * r["ms_step"] / r["dofs"]

def ours(lvl, np_):
    return next(r for r in rows if r["code"] == "twinflow" and r["level"] == f"level {lvl}" and r["ranks"] == int(np_))

# Our time per step interpolated to step-35's DoF count: power law through the two
# levels that bracket it (or the two nearest).
interp = {}
if len(levels) >= 2:
    lv = sorted(levels, key=lambda l: ours(l, ranks[0])["dofs"])
    below = [l for l in lv if ours(l, ranks[0])["dofs"] <= ref["dofs"]]
    above = [l for l in lv if ours(l, ranks[0])["dofs"] >= ref["dofs"]]
    a, b = (below[-1], above[0]) if below and above and below[-1] != above[0] else (lv[0], lv[1])
    for np_ in ranks:
        ra, rb = ours(a, np_), ours(b, np_)
        p = math.log(rb["ms_step"] / ra["ms_step"]) / math.log(rb["dofs"] / ra["dofs"])
        interp[np_] = dict(ms_step=ra["ms_step"] * (ref["dofs"] / ra["dofs"]) ** p, exponent=p,
                           levels=(a, b))
speedup = {}
if "1" in ranks and "2" in ranks:
    for lvl in levels:
        speedup[lvl] = ours(lvl, "1")["ms_step"] / ours(lvl, "2")["ms_step"]
    if interp:
        speedup["interpolated"] = interp["1"]["ms_step"] / interp["2"]["ms_step"]

hdr = ("| code | parallel | mesh | cells | DoFs (u + p) | steps | process wall [s] | setup [s] "
       "| loop [s] | ms/step | ns/(step·DoF) | ratio to step-35 (1 thread) |")
lines = [hdr, "|" + "---|" * 12]
for r in rows:
    lines.append(f"| {r['code']} | {r['par']} | {r['level']} | {r['cells']} | {r['dofs']} "
                 f"({r['dofs_u']} + {r['dofs_p']}) | {r['steps']} | {r['process_s']:.1f} | {r['setup_s']:.2f} "
                 f"| {r['loop_s']:.1f} | {r['ms_step']:.1f} | {r['ns_step_dof']:.0f} | {r['ratio']:.2f} |")
for np_, v in interp.items():
    lines.append(f"| twinflow | {np_} MPI rank{'s' if np_ != '1' else ''} | interpolated to step-35's DoFs "
                 f"(levels {v['levels'][0]}–{v['levels'][1]}, t ∝ N^{v['exponent']:.2f}) | | {ref['dofs']} | | | | "
                 f"| **{v['ms_step']:.1f}** | {1e6 * v['ms_step'] / ref['dofs']:.0f} | **{v['ms_step'] / ref['ms_step']:.2f}** |")
table = "\n".join(lines)

sec_lines = ["| run | " + " | ".join(["setup", "velocity assembly", "velocity solve", "pressure projection", "forces", "other (loop − sections)"]) + " |",
             "|" + "---|" * 7]
for r in rows:
    if r["code"] != "twinflow":
        continue
    sec = r["sections"]; n = r["steps"]
    named = ["velocity assembly", "velocity solve", "pressure projection", "forces"]
    other = r["loop_s"] - sum(sec.get(k, 0.0) for k in named)
    cells = [f"{sec.get('setup', 0.0):.2f} s"] + \
            [f"{1e3 * sec.get(k, 0.0) / n:.1f} ms ({100 * sec.get(k, 0.0) / r['summary_wall_s']:.0f} %)" for k in named] + \
            [f"{1e3 * other / n:.1f} ms ({100 * other / r['summary_wall_s']:.0f} %)"]
    sec_lines.append(f"| {r['level']}, {r['par']} | " + " | ".join(cells) + " |")
sections = "\n".join(sec_lines)

sp = ", ".join(f"level {k}: {v:.2f}x" if k != "interpolated" else f"interpolated to {ref['dofs']} DoFs: {v:.2f}x"
               for k, v in speedup.items())
md = f"""# twinflow vs deal.II step-35 on DFG 2D-2 (generated)

Generated by `benchmarks/step35/run_benchmark.sh` on {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')},
CPU: {cpu_model()}, {os.cpu_count()} cores (load average 1/5/15 min at start / end:
{os.environ.get('LOAD', 'unknown')}; anything well above 0 at the start means other work shared the cores).
{steps} time steps, step-35 dt = {dt35} (its units,
D = 1) = twinflow dt = {dtours} s (D = 0.1 m): the same CFL number. ms/step = loop / steps, where
loop = process time after setup (step-35: from the line "Step = 2" to exit; twinflow:
summary.json wall_time_s − sections.setup); process wall = launch to exit.

{table}

Speed-up of twinflow 1 → 2 MPI ranks (ms/step): {sp}.

Wall time of twinflow's timer sections (per step, and share of summary.json wall_time_s):

{sections}
"""
open(md_path, "w").write(md)
json.dump(dict(steps=steps, dt_step35=float(dt35), dt_twinflow=float(dtours), cpu=cpu_model(),
               rows=rows, interpolated=interp, speedup=speedup), open(json_path, "w"), indent=1)
print(md)
print(f"written: {md_path}, {json_path}")
PY
