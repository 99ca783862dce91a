#!/bin/bash
# drape_presets.sh — scenes/cusick_drape.yaml (shipped mesh, 1 mm bump, seed 1) with its fabric
# replaced by each measured preset (docs/fabrics.md), for docs/drape.md's table of predicted
# drape coefficients: DC, nodes, Newton iterations and wall time of each run.
# Usage: tools/drape_presets.sh [BUILD_DIR [PRESET...]]   (default: build, all ten)
# BENDING=dde (or another model) puts `bending: {model: $BENDING}` beside the fabric (default:
# the preset's quadratic bending).
# MESHES="ARGS;ARGS;..." runs each preset on each disc that tools/make_disc.py makes from ARGS
# (as tools/drape_mesh.sh does; "shipped" for the shipped mesh), one table row per mesh, for
# the mesh convergence of each preset's coefficient.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
presets=("$@")
[ ${#presets[@]} -gt 0 ] || presets=(gray-interlock ivory-rib-knit navy-sparkle-sweat
  camel-ponte-roma white-swim-solid 11oz-black-denim royal-target tango-red-jet-set
  pink-ribbon-brown white-dots-on-blk)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
IFS=';' read -r -a meshes <<<"${MESHES:-shipped}"
printf '| preset | mesh | vertices | DC | nodes | shadow radius, cm | Newton iterations | wall time, s |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- |\n'
for p in "${presets[@]}"; do
  line="  fabric: {preset: $p}"
  [ -z "${BENDING:-}" ] || line="$line\n  bending: {model: $BENDING}"
  for mesh in "${meshes[@]}"; do
    disc=$PWD/scenes/meshes/cusick_disc.obj
    if [ "$mesh" != shipped ]; then
      disc=$tmp/disc.obj
      # shellcheck disable=SC2086  # the mesh's arguments are split on purpose
      /usr/bin/python3 tools/make_disc.py $mesh "$disc" >/dev/null
    fi
    sed -e "s|obj: meshes/cusick_disc.obj|obj: $disc|" -e "s|obj: meshes/|obj: $PWD/scenes/meshes/|" \
        -e "s|^  fabric: .*|$line|" scenes/cusick_drape.yaml >"$tmp/scene.yaml"
    if ! "$build/sinew" run "$tmp/scene.yaml" --out "$tmp/out" --frames-every 3 >"$tmp/log" 2>&1; then
      printf '| `%s` | %s | | failed: %s | | | | |\n' "$p" "$mesh" "$(tail -1 "$tmp/log")"
      continue
    fi
    PYTHONPATH=python /usr/bin/python3 -c "
import json, sys; from sinew.drape import coefficient
r = coefficient(sys.argv[1]); s = json.load(open(sys.argv[1] + '/summary.json'))
print('| \`%s\` | %s | %d | %.4f | %d | %.1f–%.1f | %d | %.1f |' % (sys.argv[2], sys.argv[3],
      s['vertices'], r['dc'], r['nodes'], 100 * r['radius_min'], 100 * r['radius_max'],
      s['newton_iterations'], s['wall_time_s']))
" "$tmp/out" "$p" "$mesh"
  done
done
