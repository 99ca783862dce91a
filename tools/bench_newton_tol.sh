#!/usr/bin/env bash
# tools/bench_newton_tol.sh [SINEW] — how Newton's stopping rule (integrator.newton.norm and
# .tol) trades iterations for accuracy, the measurement behind their defaults.  For each norm
# (rms, max) and tolerance (1e-2, 3e-3, 1e-3 m/s): the shipped hanging cloth (backward Euler,
# dt 10 ms, 2 s, no step halving): Newton iterations, median per step, step time; its positions
# at t = 0.5 s against a strict reference (max norm, tol 1e-9 m/s, 1000 iterations); and the
# gathered garment (scenes/garment_drawstring.yaml, 1.5 s, no halving): status and iterations.
# The time-discretisation error (the strict solution at dt/2 against the one at dt) is the
# scale Newton's error must stay well below.  Writes docs/bench/newton/tolerance.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
out=${OUT:-docs/bench/newton}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
hc=scenes/hanging_cloth.yaml
garment=scenes/garment_drawstring.yaml
field() { sed -n "s/.*\"$2\": \"*\([-0-9.e+a-z]*\)\"*.*/\1/p" "$1/summary.json" | head -1; }
median_its() { awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "newton_iterations") c = i }
  NR > 2 { print $c }' "$1/energy.csv" | sort -n |
  awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
run() { "$bin" run "$@" --no-frames --quiet --max-halvings 0 >/dev/null 2>&1 || true; }
# the strict reference and the time-discretisation scale, both at t = 0.5 s
sed 's/max_iterations: 50/max_iterations: 1000/' "$hc" >"$work/strict.yaml"
for v in strict:0.01 half:0.005; do
  run "$work/strict.yaml" --out "$work/${v%%:*}" --dt "${v#*:}" --duration 0.5 \
    --positions-every 0.1 --newton-tol 1e-9 --newton-norm max
done
half=$(/usr/bin/python3 tools/positions_diff.py "$work/strict" "$work/half" 0.5 | awk '{ print $2 }')
echo "norm,tol_m_per_s,status,newton_iterations,median_per_step,time_step_s,rms_m_at_0.5s,time_error_rms_m,garment_status,garment_t_reached_s,garment_newton_iterations" >"$out/tolerance.csv"
for norm in rms max; do
  for tol in 1e-2 3e-3 1e-3; do
    a=(--newton-norm "$norm" --newton-tol "$tol")
    run "$hc" --out "$work/hc" "${a[@]}"
    run "$hc" --out "$work/acc" --duration 0.5 --positions-every 0.1 "${a[@]}"
    run "$garment" --out "$work/g" "${a[@]}"
    err=$(/usr/bin/python3 tools/positions_diff.py "$work/strict" "$work/acc" 0.5 | awk '{ print $2 }')
    echo "$norm,$tol,$(field "$work/hc" status),$(field "$work/hc" newton_iterations),$(median_its "$work/hc"),$(field "$work/hc" time_step_s),$err,$half,$(field "$work/g" status),$(field "$work/g" time_reached),$(field "$work/g" newton_iterations)" >>"$out/tolerance.csv"
  done
done
cat "$out/tolerance.csv"
