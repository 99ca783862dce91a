#!/bin/sh
# bench_assembly.sh — the assembly of Newton's matrix in two builds, interleaved: CPU ms per
# assembly of the terms' blocks (eval) and of their scatter (fill), the memory of blocks, slot
# map and values, and peak RSS, per scene; then the ratios new / old of the medians.
#
#   tools/bench_assembly.sh OLD_BUILD NEW_BUILD [rounds]     (default 3 rounds)
#
# Both builds need bench/bench_assembly (ninja -C DIR bench/bench_assembly; for a build of an
# older commit, copy bench/bench_assembly.c and its meson.build lines there).  SCENES overrides
# the list, REPS the assemblies per run (default 30).  One BLAS thread.  Output: CSV of every run
# on stdout, then a Markdown table of the medians and ratios.
set -eu
cd "$(dirname "$0")/.."
old=$1/bench/bench_assembly new=$2/bench/bench_assembly rounds=${3:-3}
SCENES=${SCENES:-"scenes/hanging_cloth.yaml scenes/hanging_cloth_80.yaml scenes/drape_sphere.yaml scenes/garment_tank.yaml scenes/garment_tshirt_dxf.yaml"}
REPS=${REPS:-30}
export OPENBLAS_NUM_THREADS=1
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
echo "build,round,$("$new" --header)" 
r=1
while [ "$r" -le "$rounds" ]; do
  for s in $SCENES; do
    for b in old new; do
      eval "exe=\$$b"
      line=$("$exe" "$s" "$REPS")
      echo "$b,$r,$line" | tee -a "$tmp"
    done
  done
  r=$((r + 1))
done
/usr/bin/python3 - "$tmp" <<'PY'
import csv, statistics, sys
rows = list(csv.reader(open(sys.argv[1])))
med = {}
for b, r, scene, dofs, nnz, nb, mib, ev, fi, rss, *into in rows:
    med.setdefault((scene, b), []).append((float(ev), float(fi), float(mib), float(rss), int(dofs)))
print("\n| scene | DOFs | blocks+map+values MiB old / new | peak RSS of this program (no factor) KiB/DOF old / new | eval ms old / new | fill ms old / new | eval ratio | fill ratio | eval+fill ratio |")
print("|---|--:|--:|--:|--:|--:|--:|--:|--:|")
for scene in dict.fromkeys(s for s, _ in med):
    o, n = med[(scene, "old")], med[(scene, "new")]
    m = lambda v, k: statistics.median(x[k] for x in v)
    dofs = o[0][4]
    print(f"| {scene} | {dofs} | {m(o,2):.1f} / {m(n,2):.1f} | {1024*m(o,3)/dofs:.2f} / {1024*m(n,3)/dofs:.2f} | "
          f"{m(o,0):.2f} / {m(n,0):.2f} | {m(o,1):.2f} / {m(n,1):.2f} | {m(n,0)/m(o,0):.2f} | "
          f"{m(n,1)/m(o,1):.2f} | {(m(n,0)+m(n,1))/(m(o,0)+m(o,1)):.2f} |")
PY
