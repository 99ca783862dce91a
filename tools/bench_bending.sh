#!/bin/sh
# bench_bending.sh — the cost of morley bending against dihedral and quadratic (docs/models.md, "morley",
# "Cost"): bench/bench_step's hanging cloth (backward Euler, 10 steps of 0.01 s, bw98, bending
# 1e-4 N m) on the 80 x 80 grid and on gmsh's unstructured mesh of the same square with about as
# many vertices (tools/bending_study.py --square), the three models run in turn REPEAT times
# (default 3) so that the machine's load falls on all alike.  Prints the pattern's nonzeros
# (lower triangle), the median seconds per step, per Newton iteration and per iteration's
# assembly, and the median per-iteration ratio to quadratic over the rounds (each round's runs
# taken one after the other).
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
    for b in dihedral quadratic morley; do
      # shellcheck disable=SC2086
      printf '%s,%s,%s,%s\n' "$r" "$mesh" "$b" "$("$exe" --bending=$b $obj 80 10 2>/dev/null)" >> "$tmp/runs.csv"
    done
  done
done
/usr/bin/python3 - "$tmp/runs.csv" <<'PY'
import csv, statistics, sys
rows = [r[1:] for r in csv.reader(open(sys.argv[1]))]
rounds = [r[0] for r in csv.reader(open(sys.argv[1]))]
# columns after mesh, model: N,dofs,nnz,steps,newton_iterations,factorizations,step_s,assembly_s,...
def per_it(r):  # wall s per Newton iteration
    return float(r[8]) * float(r[5]) / float(r[6])
print("| mesh | model | dofs | nonzeros | Newton its | s per step | s per Newton iteration | "
      "assembly s per iteration | per iteration / quadratic's |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for mesh in ("grid", "gmsh"):
    for model in ("dihedral", "quadratic", "morley"):
        rs = [r for r in rows if r[0] == mesh and r[1] == model]
        base = {k: per_it(r) for k, r in zip(rounds, rows) if r[0] == mesh and r[1] == "quadratic"}
        ratio = statistics.median(per_it(r) / base[k] for k, r in zip(rounds, rows)
                                  if r[0] == mesh and r[1] == model)
        step = statistics.median(float(r[8]) for r in rs)
        it = statistics.median(per_it(r) for r in rs)
        asm = statistics.median(float(r[15]) for r in rs)
        print("| %s | %s | %s | %s | %s | %.3f | %.4f | %.4f | %.2f |" % (
            mesh, model, rs[0][3], rs[0][4], rs[0][6], step, it, asm, ratio))
PY
