#!/usr/bin/env bash
# tools/bench_newton.sh BASE_SINEW [NEW_SINEW] — Newton's cost and accuracy on the shipped
# hanging cloth (backward Euler, dt 10 ms, 2 s), the build of an earlier commit against this one,
# interleaved (base, new, base, new, ...) so both see the same machine load.  Writes
# docs/bench/newton/runs.csv (one line per run) and prints it.  Also: positions at t = 0.5 s
# against a strict reference (--newton-tol 1e-9, 1000 iterations, no halving) and against the
# same at dt/2 (the time-discretisation error Newton's must stay well below).  With SIZES set
# (e.g. SIZES="40 80 120 160"), tools/bench_newton_sizes.sh runs instead: the grids of those
# sizes, every fixed-step Newton method, with and without Newton-Krylov, and Baraff-Witkin.
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:?usage: tools/bench_newton.sh BASE_SINEW [NEW_SINEW]}
new=${2:-build/sinew}
if [ -n "${SIZES:-}" ]; then exec tools/bench_newton_sizes.sh "$base" "$new"; fi
reps=${REPS:-2}
out=${OUT:-docs/bench/newton}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
scene=scenes/hanging_cloth.yaml
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1/summary.json" | head -1; }
median_its() { awk -F, 'NR > 1 { print $9 }' "$1/energy.csv" | sort -n |
  awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
echo "build,rep,status,steps,newton_iterations,factorizations,retries,median_newton_per_step,factorizations_per_iteration,time_step_s" >"$out/runs.csv"
for r in $(seq "$reps"); do
  for b in base new; do
    bin=$base; [ "$b" = new ] && bin=$new
    d="$work/$b$r"
    "$bin" run "$scene" --out "$d" --no-frames --quiet >/dev/null 2>&1 || true
    st=$(sed -n 's/.*"status": "\([a-z]*\)".*/\1/p' "$d/summary.json")
    it=$(field "$d" newton_iterations); fa=$(field "$d" factorizations)
    echo "$b,$r,$st,$(field "$d" steps),$it,$fa,$(field "$d" retries),$(median_its "$d"),$(awk -v f="$fa" -v i="$it" 'BEGIN { printf "%.3f", f / i }'),$(field "$d" time_step_s)" >>"$out/runs.csv"
  done
done
# accuracy at t = 0.5 s
sed 's/max_iterations: 50/max_iterations: 1000/' "$scene" >"$work/strict.yaml"
for v in strict:0.01 half:0.005; do
  "$new" run "$work/strict.yaml" --out "$work/${v%%:*}" --dt "${v#*:}" --duration 0.5 --positions-every 0.1 \
    --no-frames --quiet --newton-tol 1e-9 --max-halvings 0 >/dev/null 2>&1 || true
done
"$base" run "$scene" --out "$work/base05" --duration 0.5 --positions-every 0.1 --no-frames --quiet >/dev/null 2>&1 || true
"$new" run "$scene" --out "$work/new05" --duration 0.5 --positions-every 0.1 --no-frames --quiet >/dev/null 2>&1 || true
{
  echo "comparison,rms_m_at_0.5s"
  for c in "new_vs_strict:new05" "base_vs_strict:base05" "dt_half_vs_strict:half"; do
    echo "${c%%:*},$(/usr/bin/python3 tools/positions_diff.py "$work/strict" "$work/${c#*:}" 0.5 | awk '{ print $2 }')"
  done
} >"$out/accuracy.csv"
cat "$out/runs.csv" "$out/accuracy.csv"
