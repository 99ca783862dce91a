#!/bin/bash
# drape_sensitivity.sh — the drape coefficient and node count of scenes/cusick_drape.yaml
# against the mesh (rings 1 cm and 0.75 cm apart) and the perturbation (seeds and amplitudes),
# for one or more bending models; the tables of docs/drape.md, with each run's wall time.
# Usage: tools/drape_sensitivity.sh [BUILD_DIR [MODEL...]]   (default: build, the scene's model)
# MODEL is a bending model (quadratic, morley, dihedral) written beside the scene's fabric.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
models=("${@:-scene}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 tools/make_disc.py --spacing 0.0075 "$tmp/disc_fine.obj" >/dev/null
cp scenes/meshes/cusick_disc.obj "$tmp/disc.obj"
printf '| bending | mesh | perturbation | DC | nodes | Newton iterations | wall time, s |\n'
printf '| --- | --- | --- | --- | --- | --- | --- |\n'
run() {  # model, mesh file, amplitude, seed
  local bend=""
  [ "$1" = scene ] || bend="  bending: {model: $1}"
  sed -e "s|obj: meshes/cusick_disc.obj|obj: $2|" \
      -e "s|perturb: {amplitude: 0.001, seed: 1}|perturb: {amplitude: $3, seed: $4}|" \
      scenes/cusick_drape.yaml | awk -v b="$bend" '{print} /^  fabric:/ && b != "" {print b}' \
      >"$tmp/scene.yaml"
  "$build/sinew" run "$tmp/scene.yaml" --out "$tmp/out" --frames-every 3 >/dev/null 2>&1
  PYTHONPATH=python /usr/bin/python3 -c "
import json, sys; from sinew.drape import coefficient
r = coefficient(sys.argv[1]); s = json.load(open(sys.argv[1] + '/summary.json'))
print('| %s | %s | %s m, seed %s | %.4f | %d | %d | %.2f |' % (sys.argv[2], sys.argv[3], sys.argv[4],
      sys.argv[5], r['dc'], r['nodes'], s['newton_iterations'], s['wall_time_s']))
" "$tmp/out" "$1" "$(basename "$2" .obj)" "$3" "$4"
}
for b in "${models[@]}"; do
  for m in "$tmp/disc.obj" "$tmp/disc_fine.obj"; do
    for ps in "0.001 1" "0.001 2" "0.001 3" "0.003 1"; do run "$b" "$m" $ps; done
  done
done
