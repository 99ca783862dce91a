#!/bin/bash
# drape_sensitivity.sh — the drape coefficient and node count of scenes/cusick_drape.yaml
# against the mesh (rings 1 cm and 0.75 cm apart) and the perturbation (seeds and amplitudes);
# the table of docs/drape.md.  Usage: tools/drape_sensitivity.sh [BUILD_DIR]   (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 tools/make_disc.py --spacing 0.0075 "$tmp/disc_fine.obj" >/dev/null
cp scenes/meshes/cusick_disc.obj "$tmp/disc.obj"
printf '| mesh | perturbation | DC | nodes |\n| --- | --- | --- | --- |\n'
run() {  # mesh file, amplitude, seed
  sed -e "s|obj: meshes/cusick_disc.obj|obj: $1|" \
      -e "s|perturb: {amplitude: 0.001, seed: 1}|perturb: {amplitude: $2, seed: $3}|" \
      scenes/cusick_drape.yaml >"$tmp/scene.yaml"
  "$build/sinew" run "$tmp/scene.yaml" --out "$tmp/out" --frames-every 3 >/dev/null 2>&1
  PYTHONPATH=python /usr/bin/python3 -c "
import sys; from sinew.drape import coefficient
r = coefficient(sys.argv[1]); print('| %s | %s m, seed %s | %.4f | %d |' % (sys.argv[2], sys.argv[3], sys.argv[4], r['dc'], r['nodes']))
" "$tmp/out" "$(basename "$1" .obj)" "$2" "$3"
}
for m in "$tmp/disc.obj" "$tmp/disc_fine.obj"; do
  for ps in "0.001 1" "0.001 2" "0.001 3" "0.003 1"; do run "$m" $ps; done
done
