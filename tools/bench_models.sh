#!/bin/sh
# bench_models.sh — per-step cost of each cloth model on the same N x N hanging cloth (default
# N = 80), relative to bw98, measured in one run (docs/models.md, "Cost per model").
#
#   tools/bench_models.sh [build-dir]        (default build dir: build-bench)
#
# Runs bench/bench_step once per model (each in its own process, one after the other) with
# STEPS (default 10) backward-Euler steps of 0.01 s; N overrides the grid size.  Writes
# docs/bench/models_80.csv (OUT= elsewhere) and prints a Markdown table with the ratios to bw98:
# per step, and per Newton iteration of assembly (the term's own cost) and factorisation.
set -eu
cd "$(dirname "$0")/.."
build=${1:-build-bench}
if [ ! -d "$build" ]; then meson setup "$build" >/dev/null; fi
ninja -C "$build" bench/bench_step >/dev/null
exe=$build/bench/bench_step
N=${N:-80}
STEPS=${STEPS:-10}
out=${OUT:-docs/bench/models_$N.csv}
mkdir -p "$(dirname "$out")"
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
printf 'model,%s\n' "$("$exe" --header)" > "$tmp"
for cfg in bw98 stvk corotated springs bw98+dihedral bw98+quadratic; do
  model=${cfg%%+*}
  bend=""
  case $cfg in *+*) bend="--bending=${cfg#*+}" ;; esac
  echo "bench_step --model=$model $bend $N $STEPS" >&2
  # shellcheck disable=SC2086
  printf '%s,%s\n' "$cfg" "$("$exe" --model="$model" $bend "$N" "$STEPS")" >> "$tmp"
done
mv "$tmp" "$out"
trap - EXIT
/usr/bin/python3 - "$out" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
base = rows[0]
print("| model | Newton its | step s | step / bw98 | assembly per it / bw98 | factor per it / bw98 |")
print("| --- | --- | --- | --- | --- | --- |")
for r in rows:
    f = lambda k: float(r[k]) / float(base[k])
    print(f"| {r['model']} | {r['newton_iterations']} | {float(r['step_s']):.3g} | {f('step_s'):.2f} |"
          f" {f('assembly_per_iter_s'):.2f} | {f('factor_per_iter_s'):.2f} |")
PY
