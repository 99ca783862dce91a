#!/usr/bin/env bash
# tools/bench_newton_sizes.sh BASE_SINEW [NEW_SINEW] — the linear algebra of Newton's method by
# size: scenes/hanging_cloth.yaml on N x N grids (--grid), each fixed-step Newton method, the
# build of an earlier commit against this one interleaved (base, new, new with
# --newton-reuse REUSE (default on), base, ...), over the first STEPS steps of 10 ms.  The cost is the CPU time
# (user + system, /usr/bin/time) of the whole run, so that a machine shared with other work
# slows both builds alike.  Writes docs/bench/newton/sizes.csv: one line per run with its
# steps, Newton iterations, factorisations, CG iterations, CPU s per step, and the RMS
# distance of its positions at t = STEPS x 10 ms from the base build's of the same method
# (m; Newton's tolerance is 1e-2 m/s x 10 ms = 1e-4 m).  Then Baraff-Witkin against backward
# Euler (this build, with --newton-reuse BW_REUSE when set) at each N and at BW_SIZES
# (512: one step), docs/bench/newton/bw.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:?usage: tools/bench_newton_sizes.sh BASE_SINEW [NEW_SINEW]}
new=${2:-build/sinew}
sizes=${SIZES:-40 80 120 160}
methods=${METHODS:-backward-euler bdf2 implicit-midpoint newmark}
reps=${REPS:-2}
reuse=${REUSE:-on}
bw_reuse=${BW_REUSE:-}
steps=${STEPS:-10}
bw_sizes=${BW_SIZES-40 80 120 160 512}
out=${OUT:-docs/bench/newton}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
scene=scenes/hanging_cloth.yaml
dur=$(awk -v s="$steps" 'BEGIN { printf "%.6g", s * 0.01 }')
field() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "$1/summary.json" | head -1; }
# run BIN DIR N METHOD DURATION [ARGS]: one run; prints its CPU seconds
run() {
  local bin=$1 d=$2 n=$3 meth=$4 du=$5
  shift 5
  /usr/bin/time -f "%U %S" -o "$d.time" "$bin" run "$scene" --grid "${n}x$n" --method "$meth" \
    --duration "$du" --positions-every "$du" --out "$d" --no-frames --quiet "$@" >/dev/null 2>&1 || true
  awk '{ print $1 + $2 }' "$d.time"
}
row() { # row LABEL N METHOD REP DIR CPU
  local d=$5 st
  st=$(field "$d" steps)
  echo "$1,$2,$3,$4,$(sed -n 's/.*"status": "\([a-z]*\)".*/\1/p' "$d/summary.json"),$st,$(field "$d" newton_iterations),$(field "$d" factorizations),$(field "$d" cg_iterations),$(awk -v c="$6" -v s="$st" 'BEGIN { printf "%.5f", c / s }'),$7"
}
echo "build,n,method,rep,status,steps,newton_iterations,factorizations,cg_iterations,cpu_s_per_step,rms_vs_base_m" >"$out/sizes.csv"
for n in $sizes; do
  for meth in $methods; do
    for r in $(seq "$reps"); do
      cb=$(run "$base" "$work/b" "$n" "$meth" "$dur")
      cn=$(run "$new" "$work/n" "$n" "$meth" "$dur")
      co=$(run "$new" "$work/o" "$n" "$meth" "$dur" --newton-reuse "$reuse")
      dn=$(/usr/bin/python3 tools/positions_diff.py "$work/b" "$work/n" "$dur" | awk '{ print $2 }')
      do_=$(/usr/bin/python3 tools/positions_diff.py "$work/b" "$work/o" "$dur" | awk '{ print $2 }')
      { row base "$n" "$meth" "$r" "$work/b" "$cb" 0
        row new "$n" "$meth" "$r" "$work/n" "$cn" "$dn"
        row "new_reuse_$reuse" "$n" "$meth" "$r" "$work/o" "$co" "$do_"; } | sed 's/,,/,0,/' >>"$out/sizes.csv"
      tail -3 "$out/sizes.csv"
    done
  done
done
echo "n,method,rep,steps,newton_iterations,factorizations,cpu_s_per_step" >"$out/bw.csv"
for n in $bw_sizes; do
  st=$steps; [ "$n" -ge 512 ] && st=1
  du=$(awk -v s="$st" 'BEGIN { printf "%.6g", s * 0.01 }')
  for r in $(seq "$reps"); do
    for meth in baraff-witkin backward-euler; do
      extra=()
      [ "$meth" = backward-euler ] && [ -n "$bw_reuse" ] && extra=(--newton-reuse "$bw_reuse")
      c=$(run "$new" "$work/w" "$n" "$meth" "$du" "${extra[@]}")
      s=$(field "$work/w" steps)
      echo "$n,$meth,$r,$s,$(field "$work/w" newton_iterations),$(field "$work/w" factorizations),$(awk -v c="$c" -v s="$s" 'BEGIN { printf "%.5f", c / s }')" | tee -a "$out/bw.csv"
    done
  done
done
