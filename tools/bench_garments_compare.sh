#!/usr/bin/env bash
# tools/bench_garments_compare.sh OLD_DIR [NEW_DIR] — every shipped garment
# (scenes/garment_*.yaml, fit and dynamics as shipped) run by two builds, interleaved (old,
# new, old, new ..., REPS rounds, default 2) so that both see the same machine load; each
# build runs its own checkout's scene files, `--threads 1`.  OLD_DIR and NEW_DIR are checkouts
# with a build in build/ (NEW_DIR default: this one), e.g. `git worktree add ../base REV &&
# meson setup ../base/build && ninja -C ../base/build`.  Per run: CPU seconds (user + system,
# /usr/bin/time), status, the fit's end, steps, Newton iterations, the largest seam gap, self
# and obstacle intersections (summary.json).  GARMENTS="tank skirt" picks some (default all
# seven); OUT=file writes the CSV elsewhere (default /tmp/bench_garments_compare.csv).
# docs/performance.md, "Every shipped garment against the build of December 6".
set -euo pipefail
cd "$(dirname "$0")/.."
old=$(cd "${1:?usage: tools/bench_garments_compare.sh OLD_DIR [NEW_DIR]}" && pwd)
new=$(cd "${2:-.}" && pwd)
reps=${REPS:-2}
out=${OUT:-/tmp/bench_garments_compare.csv}
garments=${GARMENTS:-"skirt tank tshirt skirt_dxf tshirt_dxf gather drawstring"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "garment,build,rep,cpu_s,status,fit_end_s,steps,newton_iterations,seam_gap_max_m,self_intersections,obstacle_intersections" > "$work/out.csv"
for r in $(seq "$reps"); do
  for g in $garments; do
    for b in old new; do
      dir=$old; [ "$b" = new ] && dir=$new
      run=$work/${g}_${b}_$r
      ( cd "$dir" && /usr/bin/time -f "%U %S" -o "$run.cpu" build/sinew run "scenes/garment_$g.yaml" \
          --out "$run" --quiet --threads 1 >/dev/null 2>&1 ) || true
      /usr/bin/python3 - "$run" "$g" "$b" "$r" >> "$work/out.csv" <<'PY'
import json, sys
run, g, b, r = sys.argv[1:]
u, s = map(float, open(run + ".cpu").read().split()[-2:])
try:
    j = json.load(open(run + "/summary.json"))
except (OSError, ValueError):
    j = {}
keys = ["status", "fit_end_s", "steps", "newton_iterations", "seam_gap_max",
        "self_intersections", "obstacle_intersections"]
print(",".join([g, b, r, "%.2f" % (u + s)] + [str(j.get(k, "")) for k in keys]))
PY
      tail -1 "$work/out.csv"
    done
  done
done
cp "$work/out.csv" "$out"
echo "wrote $out"
