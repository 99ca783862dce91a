#!/bin/bash
# drape_sensitivity.sh — the drape coefficient and node count of scenes/cusick_drape.yaml
# against the perturbation (seeds and amplitudes), on the shipped mesh, for one or more bending
# models; a table of docs/drape.md, with each run's wall time (the mesh: tools/drape_mesh.sh).
# Usage: tools/drape_sensitivity.sh [BUILD_DIR [MODEL...]]   (default: build, the scene's model)
# MODEL is a bending model (quadratic, morley, dihedral) written beside the scene's fabric.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
models=("${@:-scene}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '| bending | perturbation | DC | nodes | Newton iterations | wall time, s |\n'
printf '| --- | --- | --- | --- | --- | --- |\n'
run() {  # model, amplitude, seed
  local bend=""
  [ "$1" = scene ] || bend="  bending: {model: $1}"
  sed -e "s|obj: meshes/|obj: $PWD/scenes/meshes/|" \
      -e "s|perturb: {amplitude: 0.001, seed: 1}|perturb: {amplitude: $2, seed: $3}|" \
      scenes/cusick_drape.yaml | awk -v b="$bend" '{print} /^  fabric:/ && b != "" {print b}' \
      >"$tmp/scene.yaml"
  "$build/sinew" run "$tmp/scene.yaml" --out "$tmp/out" --frames-every 3 >/dev/null 2>&1
  PYTHONPATH=python /usr/bin/python3 -c "
import json, sys; from sinew.drape import coefficient
r = coefficient(sys.argv[1]); s = json.load(open(sys.argv[1] + '/summary.json'))
print('| %s | %s m, seed %s | %.4f | %d | %d | %.1f |' % (sys.argv[2], sys.argv[3], sys.argv[4],
      r['dc'], r['nodes'], s['newton_iterations'], s['wall_time_s']))
" "$tmp/out" "$1" "$2" "$3"
}
for b in "${models[@]}"; do
  for ps in "0.001 1" "0.001 2" "0.001 3" "0.003 1"; do
    # shellcheck disable=SC2086  # amplitude and seed, split on purpose
    run "$b" $ps
  done
done
