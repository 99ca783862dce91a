#!/bin/bash
# drape_mesh.sh — the drape coefficient of scenes/cusick_drape.yaml against the mesh: the disc
# remeshed with rings SPACING m apart (tools/make_disc.py), the scene's perturbation (1 mm,
# seed 1), one bending model; the mesh-refinement table of docs/drape.md.
# Usage: tools/drape_mesh.sh [BUILD_DIR [MODEL [SPACING...]]]
#        (default: build, quadratic, 0.01 0.0075 0.005 0.00375 0.0025). A spacing must divide
#        0.09 m and 0.15 m, so that the clamp's edge and the specimen's edge are rings.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
model=${2:-quadratic}
shift 2 || shift $#
spacings=("${@:-0.01}")
[ $# -gt 0 ] || spacings=(0.01 0.0075 0.005 0.00375 0.0025)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '| bending | ring spacing, cm | vertices | DC | nodes | Newton iterations | wall time, s |\n'
printf '| --- | --- | --- | --- | --- | --- | --- |\n'
for h in "${spacings[@]}"; do
  /usr/bin/python3 tools/make_disc.py --spacing "$h" "$tmp/disc.obj" >/dev/null
  sed -e "s|obj: meshes/cusick_disc.obj|obj: $tmp/disc.obj|" scenes/cusick_drape.yaml |
    awk -v b="  bending: {model: $model}" '{print} /^  fabric:/ {print b}' >"$tmp/scene.yaml"
  "$build/sinew" run "$tmp/scene.yaml" --out "$tmp/out" --frames-every 3 >/dev/null 2>&1
  PYTHONPATH=python /usr/bin/python3 -c "
import json, sys; from sinew.drape import coefficient
r = coefficient(sys.argv[1]); s = json.load(open(sys.argv[1] + '/summary.json'))
print('| %s | %g | %d | %.4f | %d | %d | %.1f |' % (sys.argv[2], 100 * float(sys.argv[3]),
      s['vertices'], r['dc'], r['nodes'], s['newton_iterations'], s['wall_time_s']))
" "$tmp/out" "$model" "$h"
done
