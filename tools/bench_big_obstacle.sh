#!/usr/bin/env bash
# tools/bench_big_obstacle.sh [SINEW [PREVIOUS]] — what a large mesh obstacle costs: a 5 x 5
# cloth (0.2 m) 1 cm above a flat square mesh obstacle of N triangles (4 m, written by
# tools/make_big_obstacle.py) for each N in $TRIANGLES (default "200000 2000000").  Per build
# and N, interleaved REPS times (default 1):
#  - `sinew check`: wall and CPU time (user + system) and peak resident memory;
#  - `sinew run` of two steps (dt 10 ms): total wall time, the steps' own (summary.json's
#    wall_time_s), so the load (the rest: reading the OBJ, the model, the start checks, the
#    end-of-run intersection count), and max_rss_mb;
#  - signal latency: SIGTERM sent 1 s after the start (while loading) and 0.5 s after the first
#    step is logged (while stepping; a run of 10 s), the time until the process has exited.
# PREVIOUS (another build's sinew) runs only for N <= $PREV_MAX (default 200000): the previous
# broad phase takes minutes per step at 2 million triangles.  The mesh's own size in memory,
# 24 bytes per vertex and 12 per triangle (doubles and ints), is written beside the memory
# measured.  Writes docs/bench/contact/big_obstacle.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-build/sinew}")
prev=${2:+$(realpath "$2")}
reps=${REPS:-1}
sizes=${TRIANGLES:-200000 2000000}
prev_max=${PREV_MAX:-200000}
out=${OUT:-docs/bench/contact}
py=/usr/bin/python3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
cat >"$work/scene.yaml" <<'YAML'
name: cloth above a large mesh obstacle
dimension: 3
mesh:
  grid: {size: [0.2, 0.2], vertices: [5, 5], plane: xy}
material:
  density: 0.1
  membrane: {model: bw98, k_u: 5000, k_v: 5000, k_shear: 100}
  bending: {model: quadratic, stiffness: 1e-5}
gravity: [0, 0, -9.81]
obstacles:
  - {mesh: big.obj, translate: [0.1, 0.1, -0.01]}
contact:
  distance: 2e-3
integrator:
  method: backward-euler
  dt: 0.01
duration: 0.02
YAML
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1/summary.json" | head -1; }
now() { date +%s.%N; }
calc() { awk "BEGIN { print $1 }"; }
# seconds from sending SIGTERM to the exit of a run of 10 s, the signal sent after $2 seconds
# or, with $2 = step, 0.5 s after the first step is logged
latency() {
  local b=$1 when=$2 d="$work/sig" pid t0
  rm -rf "$d"
  "$b" run "$work/scene.yaml" --out "$d" --duration 10 --no-frames --quiet >/dev/null 2>&1 &
  pid=$!
  if [ "$when" = step ]; then
    until [ -s "$d/energy.csv" ] && [ "$(wc -l <"$d/energy.csv")" -ge 2 ]; do
      kill -0 "$pid" 2>/dev/null || { echo nan; return; }
      sleep 0.05
    done
    sleep 0.5
  else
    sleep "$when"
  fi
  t0=$(now)
  kill -TERM "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  calc "$(now) - $t0"
}
echo "build,triangles,rep,mesh_mb,check_wall_s,check_cpu_s,check_rss_mb,run_status,steps,run_wall_s,steps_wall_s,load_s,step_s,max_rss_mb,sigterm_loading_s,sigterm_stepping_s" >"$out/big_obstacle.csv"
for n in $sizes; do
  $py tools/make_big_obstacle.py --triangles "$n" -o "$work/big.obj"
  nv=$(grep -c '^v ' "$work/big.obj"); nf=$(grep -c '^f ' "$work/big.obj")
  mesh_mb=$(calc "($nv * 24 + $nf * 12) / 1048576")
  for r in $(seq "$reps"); do
    for which in current previous; do
      b=$bin; [ "$which" = previous ] && b=$prev
      [ -n "$b" ] || continue
      [ "$which" = previous ] && [ "$n" -gt "$prev_max" ] && continue
      d="$work/run"
      rm -rf "$d"
      /usr/bin/time -f "%e %U %S %M" -o "$work/time" "$b" check "$work/scene.yaml" >/dev/null 2>&1 || true
      read -r cw cu cs ck <"$work/time"
      t0=$(now)
      "$b" run "$work/scene.yaml" --out "$d" --no-frames --quiet >/dev/null 2>&1 || true
      rw=$(calc "$(now) - $t0")
      st=$(sed -n 's/.*"status": "\([a-z]*\)".*/\1/p' "$d/summary.json")
      steps=$(field "$d" steps); sw=$(field "$d" wall_time_s); rss=$(field "$d" max_rss_mb)
      load=$(calc "$rw - $sw"); per=$(calc "$sw / $steps")
      sl=$(latency "$b" 1); ss=$(latency "$b" step)
      printf '%s,%s,%s,%.1f,%.2f,%.2f,%.1f,%s,%s,%.2f,%.3f,%.2f,%.3f,%.1f,%.3f,%.3f\n' "$which" "$n" "$r" \
        "$mesh_mb" "$cw" "$(calc "$cu + $cs")" "$(calc "$ck / 1024")" "$st" "$steps" \
        "$rw" "$sw" "$load" "$per" "$rss" "$sl" "$ss" | tee -a "$out/big_obstacle.csv"
    done
  done
done
