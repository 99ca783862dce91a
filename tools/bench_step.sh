#!/bin/sh
# bench_step.sh — per-step time of backward Euler on the N x N hanging cloth (N = 20 ... 160),
# split into assembly, factorisation, solve and the rest, with each run's peak memory.
#
#   tools/bench_step.sh [build-dir]          (default build dir: build-bench)
#
# Each N runs in its own process (so peak RSS is per run).  Steps per N come from STEPS_20,
# STEPS_40, STEPS_80, STEPS_160 (defaults 20, 20, 10, 5); NS overrides the list of N, METHOD the
# integrator.  Writes docs/bench/step_times.csv and prints a Markdown table on stdout.
# OPENBLAS_NUM_THREADS is passed through (unset: bench_step uses 1 thread, as sinew does), and
# so are OMP_* and OPENBLAS_CORETYPE (see docs/performance.md); OUT=file writes elsewhere.
set -eu
cd "$(dirname "$0")/.."
build=${1:-build-bench}
if [ ! -d "$build" ]; then meson setup "$build" >/dev/null; fi
ninja -C "$build" bench/bench_step >/dev/null
exe=$build/bench/bench_step
NS=${NS:-"20 40 80 160"}
METHOD=${METHOD:-backward-euler}
out=${OUT:-docs/bench/step_times.csv}
mkdir -p "$(dirname "$out")"
tmp=$(mktemp)   # not beside $out, so a half-written table is never picked up
trap 'rm -f "$tmp"' EXIT
"$exe" --header > "$tmp"
for n in $NS; do
  eval "steps=\${STEPS_$n:-}"
  if [ -z "$steps" ]; then
    case $n in 160) steps=5 ;; 80) steps=10 ;; *) steps=20 ;; esac
  fi
  echo "bench_step $n $steps $METHOD" >&2
  "$exe" "$n" "$steps" "$METHOD" >> "$tmp"
done
cp "$tmp" "$out"
# Markdown: times in ms per step, shares of the step in %.
awk -F, 'NR == 1 {
  print "| N | DOFs | nnz | steps | Newton it. | factorisations | step ms | assembly ms | factor ms | solve ms | rest ms | not factor+solve | peak RSS MiB | assembly ms/it | factor ms/it |"
  print "|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
  next
}
{ printf "| %d | %d | %d | %d | %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f%% | %.1f | %.3f | %.3f |\n",
    $1, $2, $3, $4, $5, $6, 1e3*$7, 1e3*$8, 1e3*$9, 1e3*$10, 1e3*$11, 100*$12, $13, 1e3*$14, 1e3*$15 }' "$out"
