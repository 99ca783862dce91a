#!/bin/sh
# bench_bending.sh — the cost of morley bending against quadratic (docs/models.md, "morley",
# "Cost"): bench/bench_step's hanging cloth (backward Euler, 10 steps of 0.01 s, bw98, bending
# 1e-4 N m) on the 80 x 80 grid and on gmsh's unstructured mesh of the same square with about as
# many vertices (tools/bending_study.py --square), the two models run alternately REPEAT times
# (default 3) so that the machine's load falls on both alike.  Prints the pattern's nonzeros
# (lower triangle) and the median seconds per step and per Newton iteration's assembly.
#
#   tools/bench_bending.sh [build-dir]        (default build dir: build)
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
ninja -C "$build" bench/bench_step >/dev/null
exe=$build/bench/bench_step
REPEAT=${REPEAT:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 tools/bending_study.py --square "$tmp/square.obj" 80 >&2
for r in $(seq "$REPEAT"); do
  for mesh in grid gmsh; do
    obj=""
    [ "$mesh" = gmsh ] && obj="--obj=$tmp/square.obj"
    for b in quadratic morley; do
      # shellcheck disable=SC2086
      printf '%s,%s,%s\n' "$mesh" "$b" "$("$exe" --bending=$b $obj 80 10 2>/dev/null)" >> "$tmp/runs.csv"
    done
  done
done
/usr/bin/python3 - "$tmp/runs.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.reader(open(sys.argv[1])))
# columns after mesh, model: N,dofs,nnz,steps,newton_iterations,factorizations,step_s,assembly_s,...
print("| mesh | model | dofs | nonzeros | Newton its | s per step | assembly s per iteration |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for mesh in ("grid", "gmsh"):
    for model in ("quadratic", "morley"):
        rs = [r for r in rows if r[0] == mesh and r[1] == model]
        step = statistics.median(float(r[8]) for r in rs)
        asm = statistics.median(float(r[15]) for r in rs)
        print("| %s | %s | %s | %s | %s | %.3f | %.4f |" % (mesh, model, rs[0][3], rs[0][4],
                                                           rs[0][6], step, asm))
PY
