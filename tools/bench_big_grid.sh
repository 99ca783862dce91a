#!/usr/bin/env bash
# tools/bench_big_grid.sh [SINEW] — what a large flat cloth costs: an N x N grid (1 m square in
# the xy plane, bw98, quadratic bending, gravity) for each N in $SIZES (default "200 400 600"),
# one backward Euler step of 5 ms with one thread (`--threads 1`), with self-contact on and
# off ($SELF, default "true false").  Per run: the CPU time (user + system) and peak resident
# memory of the process, summary.json's factor_nnz, Newton iterations, the step's wall time
# and its parts (assembly, factorisations, solves, self-contact's collision detection, pattern
# growths), the rest of the run's wall time (loading, the start checks, the end-of-run counts:
# `load_s`), and the end-of-run self-intersection count.  Also `sinew check` alone (the load
# and the start checks): its CPU time and peak memory.  Writes docs/bench/contact/big_grid.csv.
# Sizes above 600 take minutes and gigabytes (docs/contact.md, "Cost"); keep them out of the
# test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-build/sinew}")
sizes=${SIZES:-200 400 600}
selfs=${SELF:-true false}
out=${OUT:-docs/bench/contact}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1/summary.json" | head -1; }
now() { date +%s.%N; }
calc() { awk "BEGIN { print $1 }"; }
echo "n,vertices,self,check_cpu_s,check_rss_mb,run_cpu_s,run_wall_s,max_rss_mb,factor_nnz,newton_iterations,step_s,assemble_s,factor_s,solve_s,self_ccd_s,pattern_s,load_s,self_intersections" >"$out/big_grid.csv"
for n in $sizes; do
  for self in $selfs; do
    cat >"$work/scene.yaml" <<YAML
name: flat grid $n x $n
dimension: 3
mesh:
  grid: {size: [1, 1], vertices: [$n, $n], plane: xy}
material:
  density: 0.1
  membrane: {model: bw98, k_u: 5000, k_v: 5000, k_shear: 100}
  bending: {model: quadratic, stiffness: 1e-5}
gravity: [0, 0, -9.81]
$( [ "$self" = true ] && echo "contact: {self: true}" )
integrator:
  method: backward-euler
  dt: 0.005
duration: 0.005
YAML
    d="$work/run"
    rm -rf "$d"
    /usr/bin/time -f "%U %S %M" -o "$work/time" "$bin" check "$work/scene.yaml" >/dev/null 2>&1 || true
    read -r cu cs ck <"$work/time"
    t0=$(now)
    /usr/bin/time -f "%U %S %M" -o "$work/time" "$bin" run "$work/scene.yaml" --out "$d" \
      --no-frames --quiet --threads 1 >/dev/null 2>&1 || true
    rw=$(calc "$(now) - $t0")
    read -r ru rs rk <"$work/time"
    sw=$(field "$d" wall_time_s)
    printf '%s,%s,%s,%.2f,%.1f,%.2f,%.2f,%.1f,%s,%s,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%s\n' "$n" \
      "$((n * n))" "$self" "$(calc "$cu + $cs")" "$(calc "$ck / 1024")" "$(calc "$ru + $rs")" "$rw" \
      "$(calc "$rk / 1024")" "$(field "$d" factor_nnz)" "$(field "$d" newton_iterations)" \
      "$(field "$d" time_step_s)" "$(field "$d" time_assemble_s)" "$(field "$d" time_factor_s)" \
      "$(field "$d" time_solve_s)" "$(field "$d" time_self_ccd_s)" "$(field "$d" time_pattern_s)" \
      "$(calc "$rw - $sw")" "$(field "$d" self_intersections)" | tee -a "$out/big_grid.csv"
  done
done
