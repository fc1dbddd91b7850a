#!/usr/bin/env bash
# Instructions per particle-step of the fast DEM, counted by valgrind's cachegrind: a measure
# that does not move with the machine's load. Wall-clock comparisons on a shared 2-core VM
# scatter by 10–25 % between identical runs (docs/performance.md), which hides
# any change of a few per cent; the instruction count of the same run is the same to < 0.01 %
# every time. It is a proxy: it does not see cache misses, and says nothing about threads.
# Valgrind does not run AVX-512, so under it the pair loop takes the AVX kernel even where the
# processor would take the AVX-512 one (fast/src/dem/pair_lanes_avx512.rs): the counts are the
# AVX path's.
# Wall-clock speed stays measured by `cargo bench --bench dem_settle` and the LIGGGHTS side by
# side (benches/peers/liggghts_settle/run.sh).
#
# usage: benches/instructions.sh [CASE.toml] [BIN ...]
#   CASE  default cases/bench/settle_box_10k.toml (1000 sub-steps of 10⁴ spheres)
#   BIN   one or more spillage binaries to compare on the same case, 1 thread each
#         (default target/release/spillage, or under $CARGO_TARGET_DIR; build with
#         cargo build --release). Copy a binary aside before rebuilding to compare two builds.
#   TOP   functions listed per binary (default 12; 0: none)
#   CACHE a simulated last-level cache of this many bytes (a power of two, e.g. 4194304, the
#         size of a core's L2 on the 2-core VMs): adds its misses per particle-step (slower)
# Skips cleanly (exit 0) when valgrind is absent (apt-get install valgrind).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
case_file=${1:-$root/cases/bench/settle_box_10k.toml}
shift || true
if [ ! -f "$case_file" ]; then
  echo "instructions.sh: no case file $case_file" >&2
  exit 2
fi
if ! command -v valgrind >/dev/null; then
  echo "instructions.sh: valgrind not found (apt-get install valgrind); skipped"
  exit 0
fi
bins=("$@")
if [ ${#bins[@]} -eq 0 ]; then
  bins=("${CARGO_TARGET_DIR:-$root/target}/release/spillage")
fi
for bin in "${bins[@]}"; do
  if [ ! -x "$bin" ]; then
    echo "instructions.sh: no spillage binary $bin (cargo build --release)" >&2
    exit 2
  fi
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sim=(--cache-sim=no)
header=""
if [ -n "${CACHE:-}" ]; then
  sim=(--cache-sim=yes "--LL=$CACHE,16,64")
  header="misses/particle-step"
fi
printf '%-40s %18s %14s %22s %20s\n' binary instructions particle-steps instructions/particle-step "$header"
for i in "${!bins[@]}"; do
  bin=${bins[$i]}
  out="$work/run$i"
  valgrind --tool=cachegrind "${sim[@]}" --cachegrind-out-file="$work/cg$i.out" \
    "$bin" run "$case_file" --out "$out" --threads 1 >"$work/log$i" 2>&1 || {
    echo "instructions.sh: $bin failed on $case_file; its output:" >&2
    tail -5 "$work/log$i" >&2
    exit 1
  }
  total=$(grep -E 'I +refs:' "$work/log$i" | tail -1 | sed 's/.*refs: *//; s/,//g')
  # particle-steps: Σ over the outer steps of particles × sub-steps (series.csv)
  steps=$(awk -F, 'NR == 1 { for (c = 1; c <= NF; c++) { if ($c == "substeps") s = c; if ($c == "particles") p = c } next }
                   { n += $s * $p } END { printf "%.0f", n }' "$out/series.csv")
  per=$(awk -v t="$total" -v n="$steps" 'BEGIN { if (n > 0) printf "%.1f", t / n; else print "n/a" }')
  misses=""
  if [ -n "${CACHE:-}" ]; then
    ll=$(grep -E 'LL misses:' "$work/log$i" | tail -1 | sed 's/.*misses: *//; s/ .*//; s/,//g')
    misses=$(awk -v m="$ll" -v n="$steps" 'BEGIN { if (n > 0) printf "%.3f", m / n; else print "n/a" }')
  fi
  printf '%-40s %18s %14s %22s %20s\n' "$(basename "$bin")" "$total" "$steps" "$per" "$misses"
done
if [ "${TOP:-12}" -gt 0 ]; then
  events=Ir
  if [ -n "${CACHE:-}" ]; then events=Ir,DLmr,DLmw; fi
  for i in "${!bins[@]}"; do
    echo
    echo "== $(basename "${bins[$i]}"): functions by instructions${CACHE:+, then the simulated cache read and write misses} (inlined code counted where it is written)"
    cg_annotate --show="$events" "$work/cg$i.out" 2>/dev/null | awk '/file:function/ { on = 1; getline; next } on && NF == 0 { exit } on' | head -n "${TOP:-12}" | cut -c1-160
  done
fi
