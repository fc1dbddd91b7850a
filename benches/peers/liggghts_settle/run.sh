#!/usr/bin/env bash
# Side by side with LIGGGHTS 3.8 (issue 19, benchmarks): the DEM-only settling bed
# cases/bench/settle_box_10k.toml (or _100k) in both codes with the same setup, every number of
# the LIGGGHTS input read from the case file by case_params.py: the same spheres at the same
# lattice sites (a data file written with spillage's placement formula), density, Hertz normal
# and Mindlin tangential springs with history (`pair_style gran model hertz tangential history`:
# the same E*, G*, damping law from e and Coulomb friction), e, μ, E = E/softening, ν, gravity,
# the box's six faces as frictional planes (`fix wall/gran ... primitive`), the same fixed DEM
# time step and number of sub-steps, velocity Verlet (`fix nve/sphere`). Neighbour skin 0.1 d.
#
# Runs LIGGGHTS on 1 process and (with mpirun) 2, then, if the spillage binary exists,
# `spillage run` with --solver fast on 1 and 2 threads and --solver reference on 1, and prints
# particle-steps per second side by side with the ratios, and the end state of each run (kinetic
# energy, contacts, mean height, particles kept) to show both codes ran the same physics.
# Skips cleanly (exit 0) without LIGGGHTS or python3 ≥ 3.11. What differs between the two
# contact models is listed in README.md.
#
# usage: benches/peers/liggghts_settle/run.sh [10k|100k|CASE.toml] [WORKDIR]
#   WORKDIR keeps every run (default: a temporary directory removed at exit).
#   LIGGGHTS_PROCS   process counts for LIGGGHTS (default "1 2"; 2 only with mpirun)
#   SPILLAGE_BIN     the spillage binary (default target/release/spillage, or under
#                    $CARGO_TARGET_DIR); absent: LIGGGHTS only (build with cargo build --release)
#   SPILLAGE_RUNS    spillage runs as solver:threads (default "fast:1 fast:2 reference:1")
#   STEPS            outer steps of every run, both codes (default the case's): fewer for a quick
#                    look; the contacts are still closing early on, so a short run's
#                    particle-steps/s are higher than a full run's (compare equal lengths only)
#   ROUNDS           repeat every run this many times, the codes taking turns (LIGGGHTS first
#                    in odd rounds, spillage in even ones; default 1), and give each ratio's
#                    median over the rounds, each round's ratio taken within the round: the
#                    machine's speed drifts by more than the ratios' differences between runs
#                    made minutes apart
# Before every run the two threads' hand-off of a cache line is timed with
# `target/release/examples/core_to_core` when it has been built (cargo build --release --example
# core_to_core): a 2-thread run's speed follows it (docs/performance.md, "A gang or one thread, by the
# clock"), and the table gives the 1 → 2 ratios of the fast and the slow periods apart.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
case "${1:-10k}" in
  10k | 100k) case_file="$root/cases/bench/settle_box_${1:-10k}.toml" ;;
  *) case_file=$1 ;;
esac
if [ ! -f "$case_file" ]; then
  echo "run.sh: no case file $case_file (give 10k, 100k or a settle-box case file)" >&2
  exit 2
fi
case_file=$(cd "$(dirname "$case_file")" && pwd)/$(basename "$case_file")

liggghts=""
for name in ${LIGGGHTS_BIN:-} liggghts lmp_auto lmp_serial; do
  if command -v "$name" >/dev/null 2>&1; then liggghts=$(command -v "$name"); break; fi
done
if [ -z "$liggghts" ]; then
  echo "LIGGGHTS (liggghts) not found: skipping the settling-bed comparison (apt-get install liggghts)"
  exit 0
fi
if ! python3 -c 'import tomllib' >/dev/null 2>&1; then
  echo "python3 with tomllib (Python >= 3.11) not found: skipping the settling-bed comparison"
  exit 0
fi

if [ $# -ge 2 ]; then
  work=$(mkdir -p "$2" && cd "$2" && pwd)
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
results="$work/results.jsonl"
: > "$results"

# every number of the LIGGGHTS input comes from the case file
python3 "$here/case_params.py" "$case_file" "$work/lattice.data" > "$work/params.sh"
eval "$(cat "$work/params.sh")"
if [ -n "${STEPS:-}" ]; then
  outer_steps=$STEPS
  total_substeps=$(( STEPS * substeps_per_step ))
fi
echo "$case_name: $n_particles spheres, $total_substeps sub-steps of $substep s (from $case_file)"

# thermo ten times a run (its computes cost ~1 % of a step at that rate)
thermo_every=$(( total_substeps >= 10 ? total_substeps / 10 : 1 ))
skin=$(python3 -c "print(0.1 * $diameter)")
cat > "$work/in.settle" <<EOT
# written by benches/peers/liggghts_settle/run.sh from $case_file
atom_style granular
atom_modify map array
# fixed boundaries: an atom leaving the domain is lost (counted below, never expected)
boundary f f f
newton off
communicate single vel yes
units si
# split the domain across processes in x and y only: the bed fills the lower part of the box
processors * * 1
read_data lattice.data

neighbor $skin bin
neigh_modify delay 0

fix m1 all property/global youngsModulus peratomtype $youngs
fix m2 all property/global poissonsRatio peratomtype $poisson
fix m3 all property/global coefficientRestitution peratomtypepair 1 $restitution
fix m4 all property/global coefficientFriction peratomtypepair 1 $friction

# Hertz normal spring, Mindlin tangential spring with history, damping from e (Tsuji/
# Antypov–Elliott form), Coulomb limit; no cohesion, no rolling friction
pair_style gran model hertz tangential history
pair_coeff * *

timestep $substep

fix wx0 all wall/gran model hertz tangential history primitive type 1 xplane $bx0
fix wx1 all wall/gran model hertz tangential history primitive type 1 xplane $bx1
fix wy0 all wall/gran model hertz tangential history primitive type 1 yplane $by0
fix wy1 all wall/gran model hertz tangential history primitive type 1 yplane $by1
fix wz0 all wall/gran model hertz tangential history primitive type 1 zplane $bz0
fix wz1 all wall/gran model hertz tangential history primitive type 1 zplane $bz1

fix gravi all gravity $g_norm vector $gx $gy $gz
fix integr all nve/sphere

compute ket all ke
compute rke all erotate/sphere
compute cc all contact/atom
compute csum all reduce sum c_cc
compute zmean all reduce ave z
thermo_style custom step atoms c_ket c_rke c_csum c_zmean
thermo_modify norm no lost warn
thermo $thermo_every

run $total_substeps
write_dump all custom final.dump id x y z modify format "%d %.17g %.17g %.17g"
EOT

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
bin=${SPILLAGE_BIN:-${CARGO_TARGET_DIR:-$root/target}/release/spillage}
case "$bin" in /*) ;; *) bin="$root/$bin" ;; esac
rounds=${ROUNDS:-1}
if ! [[ "$rounds" =~ ^[1-9][0-9]*$ ]]; then
  echo "run.sh: ROUNDS=$rounds: expected a whole number ≥ 1" >&2
  exit 2
fi
# the case with frames on (the first and the last only; written outside the timed steps) so
# the end state can be read, and STEPS if given
spillage_case="$work/$(basename "$case_file")"
sed -E -e 's/^paraview = false/paraview = true/' \
  -e "s/^steps = [0-9]+/steps = $outer_steps/" "$case_file" > "$spillage_case"
if [ ! -x "$bin" ]; then
  echo "spillage binary $bin not found: LIGGGHTS only (cargo build --release, or set SPILLAGE_BIN)"
fi
if ! command -v mpirun >/dev/null 2>&1; then
  echo "mpirun not found: LIGGGHTS on more than one process skipped"
fi

# the two threads' hand-off in ns, into HANDOFF_NS for report.py (empty without the example)
handoff_bin="${CARGO_TARGET_DIR:-$root/target}/release/examples/core_to_core"
time_handoff() {
  export HANDOFF_NS=""
  if [ -x "$handoff_bin" ]; then
    HANDOFF_NS=$("$handoff_bin" 3 | awk '{print $1}')
  fi
}

# LIGGGHTS' runs of round $ROUND (directories suffixed $suffix)
run_liggghts() {
  for procs in ${LIGGGHTS_PROCS:-1 2}; do
    local dir="$work/liggghts_np$procs$suffix"
    if [ "$procs" = 1 ]; then
      launch=("$liggghts")
    elif command -v mpirun >/dev/null 2>&1; then
      # unbound, as spillage's threads: with other work on the machine a rank pinned to a busy
      # core cannot move to the idle one
      launch=(mpirun -np "$procs" --bind-to none "$liggghts")
    else
      continue
    fi
    mkdir -p "$dir"
    cp "$work/in.settle" "$work/lattice.data" "$dir/"
    echo "LIGGGHTS on $procs process(es) in $dir"
    time_handoff
    (cd "$dir" && "${launch[@]}" -in in.settle -log log.liggghts > stdout.txt 2>&1) \
      || { echo "LIGGGHTS failed: tail of $dir/stdout.txt:"; tail -20 "$dir/stdout.txt"; exit 1; }
    python3 "$here/report.py" liggghts "$dir/log.liggghts" "$dir/final.dump" "$work/params.sh" >> "$results"
  done
}

# spillage's runs of round $ROUND
run_spillage() {
  [ -x "$bin" ] || return 0
  for run in ${SPILLAGE_RUNS:-fast:1 fast:2 reference:1}; do
    local solver=${run%%:*} threads=${run##*:}
    local out="$work/spillage_${solver}_t$threads$suffix"
    echo "spillage --solver $solver --threads $threads in $out"
    time_handoff
    "$bin" run "$spillage_case" --solver "$solver" --threads "$threads" --out "$out" --force > "$out.log" 2>&1 \
      || { echo "spillage failed: tail of $out.log:"; tail -20 "$out.log"; exit 1; }
    grep -h '^note:' "$out.log" | sort -u || true
    python3 "$here/report.py" spillage "$out" "$work/params.sh" "$solver" >> "$results"
  done
}

# the codes take turns, and change who goes first every round, so that a drift of the
# machine's speed within a round favours neither
for round in $(seq "$rounds"); do
  export ROUND=$round
  suffix=$([ "$rounds" = 1 ] || echo "_r$round")
  if [ $((round % 2)) = 1 ]; then
    run_liggghts
    run_spillage
  else
    run_spillage
    run_liggghts
  fi
done

echo
python3 "$here/report.py" table "$results"
