#!/usr/bin/env bash
# tools/bench_contact.sh [SINEW] — what contact costs: scenes/drape_sphere.yaml (41 x 41 cloth
# dropped on a sphere, backward Euler, dt 10 ms, 2 s) as shipped, and the same scene without its
# obstacle and contact keys (the cloth falls freely), interleaved REPS times (default 2) so both
# see the same machine load.  Per run: steps, Newton iterations, factorisations, line-search
# cuts, step time, its assembly (every term, the contact term included), factorisation, solve
# and contact checks (time_contact_s: continuous collision detection, the settling test, each
# step's start), per step and per Newton iteration.  Writes docs/bench/contact/drape.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
reps=${REPS:-2}
out=${OUT:-docs/bench/contact}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
scene=scenes/drape_sphere.yaml
# the scene without contact: drop the obstacles and contact blocks (and their comments)
awk '/^obstacles:/ || /^contact:/ { skip = 1; next } skip && /^[^ #]/ { skip = 0 } !skip' \
  "$scene" >"$work/free.yaml"
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1/summary.json" | head -1; }
echo "case,rep,status,steps,newton_iterations,factorizations,linesearch_backtracks,time_step_s,time_assemble_s,time_factor_s,time_solve_s,time_contact_s,step_ms_per_step,step_ms_per_iteration,contact_share" >"$out/drape.csv"
for r in $(seq "$reps"); do
  for c in contact free; do
    s=$scene; [ "$c" = free ] && s=$work/free.yaml
    d="$work/$c$r"
    "$bin" run "$s" --out "$d" --no-frames --quiet --threads 1 >/dev/null 2>&1 || true
    st=$(sed -n 's/.*"status": "\([a-z]*\)".*/\1/p' "$d/summary.json")
    steps=$(field "$d" steps); it=$(field "$d" newton_iterations); fa=$(field "$d" factorizations)
    ls=$(field "$d" linesearch_backtracks); ts=$(field "$d" time_step_s)
    ta=$(field "$d" time_assemble_s); tf=$(field "$d" time_factor_s); tv=$(field "$d" time_solve_s)
    tc=$(field "$d" time_contact_s); tc=${tc:-0}
    awk -v c="$c" -v r="$r" -v st="$st" -v s="$steps" -v it="$it" -v fa="$fa" -v ls="$ls" \
      -v ts="$ts" -v ta="$ta" -v tf="$tf" -v tv="$tv" -v tc="$tc" 'BEGIN {
        printf "%s,%s,%s,%d,%d,%d,%d,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.3f\n", c, r, st, s, it, fa,
          ls, ts, ta, tf, tv, tc, 1e3 * ts / s, 1e3 * ts / it, tc / ts }' >>"$out/drape.csv"
  done
done
cat "$out/drape.csv"
