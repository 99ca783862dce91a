#!/bin/sh
# bench_step_compare.sh — bench/bench_step of two builds on the N x N hanging cloth,
# interleaved (old, new, old, new, ... per N and round) so that both see the same machine
# load; then, per build and N, the median and minimum of the step, assembly and factorisation
# times (ms per step) and the peak RSS (MiB, KiB per DOF).
#
#   tools/bench_step_compare.sh OLD_BUILD [NEW_BUILD]     (NEW_BUILD default: build)
#
# Both builds need bench/bench_step.  NS (default "80 120"), ROUNDS (default 9), STEPS (default
# 5) and ARGS (extra bench_step options for both, e.g. --hessian=auto) change the runs.  One
# BLAS thread (bench_step's default).  Output: every run's CSV line, then a Markdown table.
# docs/performance.md, "The Hessian straight into the system".
set -eu
cd "$(dirname "$0")/.."
old=${1:?usage: tools/bench_step_compare.sh OLD_BUILD [NEW_BUILD]}/bench/bench_step
new=${2:-build}/bench/bench_step
NS=${NS:-"80 120"}
ROUNDS=${ROUNDS:-9}
STEPS=${STEPS:-5}
ARGS=${ARGS:-}
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
r=1
while [ "$r" -le "$ROUNDS" ]; do
  for n in $NS; do
    for b in old new; do
      eval "exe=\$$b"
      # shellcheck disable=SC2086
      line=$("$exe" $ARGS "$n" "$STEPS" 2>/dev/null | tail -1)
      echo "$b,$r,$line" | tee -a "$tmp"
    done
  done
  r=$((r + 1))
done
/usr/bin/python3 - "$tmp" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    f = line.strip().split(",")
    b, n, dofs = f[0], int(f[2]), int(f[3])
    runs.setdefault((n, b), []).append((float(f[8]), float(f[9]), float(f[10]), float(f[14]), dofs))
print("\n| N | build | step ms, median (min) | assembly ms | factorisation ms | peak RSS MiB | KiB per DOF |")
print("|--:|---|--:|--:|--:|--:|--:|")
for (n, b) in sorted(runs, key=lambda k: (k[0], k[1] != "old")):
    v = runs[(n, b)]
    c = lambda k: "%.1f (%.1f)" % (1e3 * statistics.median(x[k] for x in v), 1e3 * min(x[k] for x in v))
    rss = statistics.median(x[3] for x in v)
    print(f"| {n} | {b} | {c(0)} | {c(1)} | {c(2)} | {rss:.1f} | {1024 * rss / v[0][4]:.2f} |")
PY
