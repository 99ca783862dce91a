#!/bin/sh
# bench_dde_bending.sh — the cost of the measured fabrics' curvature-dependent bending (`bending:
# {model: dde}`, models/dde_bending.c) against the quadratic bending the presets use otherwise
# (docs/fabrics.md, "Bending by the data"): bench/bench_step's hanging cloth made of a preset
# (its dde membrane either way), backward Euler, STEPS steps (default 30) of 0.01 s on an N x N
# grid (default 60), the two models alternating REPEAT times (default 3) so that the machine's
# load falls on both alike.  Prints, per model, the median over the rounds of the process's CPU
# seconds per Newton iteration, the assembly's (wall) seconds per iteration and the Newton
# iterations, and the median over the rounds of each round's per-iteration CPU ratio to
# quadratic.
#
#   tools/bench_dde_bending.sh [build-dir [preset]]   (defaults: build, gray-interlock)
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
preset=${2:-gray-interlock}
ninja -C "$build" bench/bench_step >/dev/null
REPEAT=${REPEAT:-3} N=${N:-60} STEPS=${STEPS:-30} /usr/bin/python3 - "$build/bench/bench_step" "$preset" <<'PY'
import os, resource, statistics, subprocess, sys
exe, preset = sys.argv[1], sys.argv[2]
n, steps, repeat = os.environ["N"], os.environ["STEPS"], int(os.environ["REPEAT"])
runs = {"quadratic": [], "dde": []}
for r in range(repeat):
    for model in ("quadratic", "dde"):
        t0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        out = subprocess.run([exe, "--fabric=" + preset, "--bending=" + model, n, steps],
                             check=True, capture_output=True, text=True).stdout.split(",")
        t1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = t1.ru_utime - t0.ru_utime + t1.ru_stime - t0.ru_stime
        its = int(out[4])
        runs[model].append((cpu / its, float(out[13]), its))
print("| bending | Newton iterations | CPU s per iteration | assembly s per iteration | "
      "CPU per iteration / quadratic's |")
print("| --- | --- | --- | --- | --- |")
for model in ("quadratic", "dde"):
    rs = runs[model]
    ratio = statistics.median(a[0] / b[0] for a, b in zip(rs, runs["quadratic"]))
    print("| %s | %d | %.4f | %.4f | %.2f |" % (model, statistics.median(x[2] for x in rs),
          statistics.median(x[0] for x in rs), statistics.median(x[1] for x in rs), ratio))
PY
