#!/usr/bin/env bash
# tools/bench_builds.sh BUILD_DIR... — the shipped garments run by several builds of sinew
# (each a build folder holding `sinew`, e.g. ones configured with
# `meson setup ../b16 -Dc_args=-DSW_MC_RENEW=16`), interleaved: for each repetition (REPS,
# default 2), garment (GARMENTS, default "skirt tank tshirt") and stiffness scale (SCALES,
# default "1"; e.g. "1 1.000000000001 0.999999999999" for round-off variants) every build in
# turn, `--threads 1`, this checkout's scene files.  One CSV line per run: CPU s (user +
# system), Newton iterations, line-search halvings, Newton iterations with friction's bound,
# candidate listings made and renewed, the self-contact CCD and broad-phase wall time, the
# contact term's evaluation time, the step time, status and intersections (summary.json).
# OUT=file (default /tmp/bench_builds.csv).  docs/contact.md, "Renewed listings" and
# "Friction's matrix"; docs/performance.md, "On another machine, with round-off variants".
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { echo "usage: tools/bench_builds.sh BUILD_DIR..." >&2; exit 2; }
reps=${REPS:-2}
garments=${GARMENTS:-"skirt tank tshirt"}
scales=${SCALES:-1}
out=${OUT:-/tmp/bench_builds.csv}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "garment,build,scale,rep,cpu_s,newton,halvings,bound_iterations,listings,renewals,ccd_s,broadphase_s,contact_term_s,step_s,status,self_intersections,obstacle_intersections" > "$work/out.csv"
for r in $(seq "$reps"); do
  for g in $garments; do
    for sc in $scales; do
      for b in "$@"; do
        run=$work/run
        rm -rf "$run"
        /usr/bin/time -f "%U %S" -o "$run.cpu" "$b/sinew" run "scenes/garment_$g.yaml" --out "$run" \
          --quiet --threads 1 --stiffness-scale "$sc" >/dev/null 2>&1 || true
        /usr/bin/python3 - "$run" "$g" "$b" "$sc" "$r" >> "$work/out.csv" <<'PY'
import json, sys
run, g, b, sc, r = sys.argv[1:]
u, s = map(float, open(run + ".cpu").read().split()[-2:])
try:
    j = json.load(open(run + "/summary.json"))
except (OSError, ValueError):
    j = {}
terms = j.get("time_terms_s", {})
cols = [j.get(k, "") for k in ["newton_iterations", "linesearch_backtracks",
                               "newton_bound_iterations", "candidate_listings",
                               "candidate_renewals", "time_self_ccd_s",
                               "time_self_broadphase_s"]]
cols += [terms.get("mesh_contact", ""), j.get("time_step_s", ""), j.get("status", ""),
         j.get("self_intersections", ""), j.get("obstacle_intersections", "")]
print(",".join([g, b, sc, r, "%.2f" % (u + s)] + [str(c) for c in cols]))
PY
        tail -1 "$work/out.csv"
      done
    done
  done
done
cp "$work/out.csv" "$out"
echo "wrote $out"
