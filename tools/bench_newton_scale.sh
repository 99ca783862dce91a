#!/usr/bin/env bash
# tools/bench_newton_scale.sh [SINEW] — what a backward-Euler step costs on large cloths, in
# units of its own linear algebra: scenes/bench/scaling_cloth.yaml (bw98, two corners pinned)
# at 160 x 160 vertices (dt 10 ms, the first 0.2 s, as the shipped hanging cloth) and at
# 512 x 512 (dt 1 ms, three steps), under backward Euler and Baraff-Witkin (one Newton step per
# time step).  Per run: steps, Newton iterations, factorisations, step time per step, and one
# factorisation + solve (time_factor_s / factorizations + time_solve_s / newton_iterations);
# the ratio of the two is what a step costs in factorisations.  One BLAS thread.
# Writes docs/bench/newton/scale.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
out=${OUT:-docs/bench/newton}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
field() { sed -n "s/.*\"$2\": \"*\([-0-9.e+a-z]*\)\"*.*/\1/p" "$1/summary.json" | head -1; }
echo "grid,method,dt_s,status,steps,newton_iterations,factorizations,step_s_per_step,factor_solve_s,step_over_factor_solve" >"$out/scale.csv"
for cfg in 160:0.01:0.2 512:0.001:0.003; do
  IFS=: read -r n dt dur <<<"$cfg"
  for method in backward-euler baraff-witkin; do
    d="$work/$n-$method"
    "$bin" run scenes/bench/scaling_cloth.yaml --grid "${n}x$n" --method "$method" --dt "$dt" \
      --duration "$dur" --no-frames --quiet --threads 1 --max-halvings 0 --out "$d" >/dev/null 2>&1 || true
    st=$(field "$d" status); steps=$(field "$d" steps); it=$(field "$d" newton_iterations)
    fa=$(field "$d" factorizations); ts=$(field "$d" time_step_s)
    tf=$(field "$d" time_factor_s); tv=$(field "$d" time_solve_s)
    awk -v n="$n" -v m="$method" -v dt="$dt" -v st="$st" -v s="$steps" -v it="$it" -v fa="$fa" \
      -v ts="$ts" -v tf="$tf" -v tv="$tv" 'BEGIN {
        fs = tf / fa + tv / it; per = ts / s
        printf "%sx%s,%s,%s,%s,%d,%d,%d,%.4g,%.4g,%.3f\n", n, n, m, dt, st, s, it, fa, per, fs, per / fs }' \
      >>"$out/scale.csv"
  done
done
cat "$out/scale.csv"
