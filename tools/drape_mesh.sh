#!/bin/bash
# drape_mesh.sh — the drape coefficient of scenes/cusick_drape.yaml against the mesh: the disc
# remeshed by tools/make_disc.py with each MESH's arguments, the scene's perturbation (1 mm,
# seed 1), one bending model; the mesh tables of docs/drape.md.
# Usage: tools/drape_mesh.sh [BUILD_DIR [MODEL [MESH...]]]
#   MESH: make_disc.py's arguments as one word, e.g. "--spacing 0.005" or
#   "--ring 0.09 --refine 0.08 0.11 0.0025" (default: rings 1, 0.75, 0.5, 0.375 and 0.25 cm
#   apart, the disc refined away from the clamp's edge, then about it, coarse to fine). A
#   uniform spacing must divide 0.09 m and 0.15 m, so that the clamp's and the specimen's edges
#   are rings.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
model=${2:-quadratic}
shift 2 || shift $#
band1="--ring 0.09 --refine 0.08 0.11 0.0025 --refine 0.11 0.12 0.005"
meshes=("$@")
[ $# -gt 0 ] || meshes=("--spacing 0.01" "--spacing 0.0075" "--spacing 0.005" "--spacing 0.00375"
  "--spacing 0.0025" "--refine 0.11 0.12 0.005 --refine 0.12 0.15 0.0025"
  "$band1" "$band1 --refine 0.0875 0.0925 0.00125"
  "$band1 --refine 0.085 0.10 0.00125"
  "$band1 --refine 0.085 0.10 0.00125 --refine 0.0875 0.095 0.000625")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '| bending | mesh (make_disc.py arguments) | vertices | DC | nodes | Newton iterations | wall time, s |\n'
printf '| --- | --- | --- | --- | --- | --- | --- |\n'
for mesh in "${meshes[@]}"; do
  # shellcheck disable=SC2086  # the mesh's arguments are split on purpose
  /usr/bin/python3 tools/make_disc.py $mesh "$tmp/disc.obj" >/dev/null
  sed -e "s|obj: meshes/cusick_disc.obj|obj: $tmp/disc.obj|" scenes/cusick_drape.yaml |
    awk -v b="  bending: {model: $model}" '{print} /^  fabric:/ {print b}' >"$tmp/scene.yaml"
  "$build/sinew" run "$tmp/scene.yaml" --out "$tmp/out" --frames-every 3 >/dev/null 2>&1
  PYTHONPATH=python /usr/bin/python3 -c "
import json, sys; from sinew.drape import coefficient
r = coefficient(sys.argv[1]); s = json.load(open(sys.argv[1] + '/summary.json'))
print('| %s | \`%s\` | %d | %.4f | %d | %d | %.1f |' % (sys.argv[2], sys.argv[3], s['vertices'],
      r['dc'], r['nodes'], s['newton_iterations'], s['wall_time_s']))
" "$tmp/out" "$model" "$mesh"
done
