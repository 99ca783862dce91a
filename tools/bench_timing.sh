#!/usr/bin/env bash
# tools/bench_timing.sh [SINEW] — which time `sinew bench` should chart on a shared machine, the
# measurement behind its `--time cpu` default.  One small bench (the shipped hanging cloth, 0.25 s,
# backward Euler, BDF2 and implicit midpoint at 10 and 5 ms, a BDF2 reference, 3 repeats, one
# run at a time) four times, interleaved: A, the machine as it is; B, the same while two
# `yes > /dev/null` compete for the cores; A; B.  For each run, the median over A's and over B's
# of its wall time and of its CPU time (user + system), and their ratio B / A: the measure whose
# ratio stays near 1 is the one another program's load does not move.  The load average before
# and after each bench is printed.  Writes docs/bench/timing/timing.csv and prints a table.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
out=${OUT:-docs/bench/timing}
work=$(mktemp -d)
pids=()
trap 'kill "${pids[@]}" 2>/dev/null; rm -rf "$work"' EXIT
mkdir -p "$out"
for round in 1 2; do
  for cond in A B; do
    pids=()
    if [ $cond = B ]; then
      yes >/dev/null & pids+=($!)
      yes >/dev/null & pids+=($!)
    fi
    l0=$(cut -d' ' -f1 /proc/loadavg)
    "$bin" bench scenes/hanging_cloth.yaml --duration 0.25 \
      --methods backward-euler,bdf2,implicit-midpoint --dts 0.01,0.005 --reference bdf2 \
      --confirm bdf2 --confirm-tol 1 --repeat 3 --jobs 1 --no-charts --out "$work/$cond$round" \
      >"$work/$cond$round.txt" 2>&1
    ((${#pids[@]})) && kill "${pids[@]}" && wait "${pids[@]}" 2>/dev/null || true
    pids=()
    echo "bench $cond$round: load average $l0 before, $(cut -d' ' -f1 /proc/loadavg) after"
  done
done
/usr/bin/python3 - "$work" "$out/timing.csv" <<'PY'
import csv, statistics as st, sys
work, path = sys.argv[1], sys.argv[2]
def rows(tag):
    return {(r["method"], r["value"]): r for r in csv.DictReader(open(f"{work}/{tag}/work_precision.csv"))
            if r["status"] == "ok"}
R = {t: rows(t) for t in ("A1", "A2", "B1", "B2")}
keys = sorted(set.intersection(*(set(v) for v in R.values())))
def med(col, cond, k):
    return st.median(float(R[t][k][col]) for t in R if t[0] == cond)
out = csv.writer(open(path, "w", newline=""))
out.writerow(["method", "dt", "wall_a_s", "wall_b_s", "wall_ratio", "cpu_a_s", "cpu_b_s", "cpu_ratio"])
print("| method | dt (ms) | wall A (s) | wall B (s) | B / A | CPU A (s) | CPU B (s) | B / A |")
print("| --- | --: | --: | --: | --: | --: | --: | --: |")
rw, rc = [], []
for k in keys:
    wa, wb, ca, cb = med("wall_s", "A", k), med("wall_s", "B", k), med("cpu_s", "A", k), med("cpu_s", "B", k)
    rw.append(wb / wa), rc.append(cb / ca)
    out.writerow([k[0], k[1], f"{wa:.4g}", f"{wb:.4g}", f"{wb / wa:.3f}", f"{ca:.4g}", f"{cb:.4g}", f"{cb / ca:.3f}"])
    print(f"| {k[0]} | {float(k[1]) * 1e3:g} | {wa:.3g} | {wb:.3g} | {wb / wa:.2f} | {ca:.3g} | {cb:.3g} | {cb / ca:.2f} |")
print(f"| median | | | | {st.median(rw):.2f} | | | {st.median(rc):.2f} |")
for t in R:
    sw = [float(r["wall_max_s"]) / float(r["wall_min_s"]) for r in R[t].values()]
    sc = [float(r["cpu_max_s"]) / float(r["cpu_min_s"]) for r in R[t].values()]
    print(f"bench {t}: max / min over the 3 repeats, median over the runs: wall {st.median(sw):.2f}, CPU {st.median(sc):.2f}")
PY
