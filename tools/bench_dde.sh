#!/bin/bash
# bench_dde.sh — what the data-driven membrane (models/dde.c) costs a garment against bw98:
# scenes/garment_tshirt.yaml as shipped (bw98 2000 / 1500 / 50 N/m, bending 1e-5 N m) and with
# its material replaced by a measured preset (dde membrane, the preset's bending), run in turns
# (bw98, preset, bw98, preset, ...) so that both see the same machine; per run: Newton
# iterations, steps, CPU time and CPU time per Newton iteration (docs/bench/dde.md).
# Usage: tools/bench_dde.sh [BUILD_DIR [PRESET [ROUNDS [SCENE [DURATION]]]]]
#   (default: build gray-interlock 2 scenes/garment_tshirt.yaml, the scene's duration)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
preset=${2:-gray-interlock}
rounds=${3:-2}
scene=${4:-scenes/garment_tshirt.yaml}
dur=${5:+--duration $5}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed -e "s| meshes/| $PWD/scenes/meshes/|g" "$scene" >"$tmp/bw98.yaml"
awk -v p="$preset" '/^  density:|^  bending:/ {next}
  /^  membrane:/ {print "  fabric: {preset: " p "}"; next} {print}' "$tmp/bw98.yaml" >"$tmp/dde.yaml"
printf '| run | material | status | steps | Newton iterations | CPU, s | CPU per iteration, ms | membrane term per iteration, ms | all terms per iteration, ms |\n'
printf '| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n'
for r in $(seq "$rounds"); do
  for k in bw98 dde; do
    rm -rf "$tmp/out"
    # shellcheck disable=SC2086  # --duration and its value, split on purpose
    "$build/sinew" run "$tmp/$k.yaml" --out "$tmp/out" --no-frames $dur >/dev/null 2>&1 || true
    PYTHONPATH=python /usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1] + '/summary.json'))
n = max(s['newton_iterations'], 1)
t = s['time_terms_s']
memb = t.get('dde', t.get('bw98', 0.0))
status = s['status'] if s['status'] == 'ok' else '%s: %s' % (s['status'], s.get('message', ''))
print('| %s | %s | %s | %d | %d | %.2f | %.3f | %.4f | %.3f |' % (sys.argv[2], sys.argv[3],
      status, s['steps'], s['newton_iterations'], s['cpu_time_s'], 1e3 * s['cpu_time_s'] / n,
      1e3 * memb / n, 1e3 * sum(t.values()) / n))
" "$tmp/out" "$r" "$([ $k = bw98 ] && echo 'bw98 (shipped)' || echo "$preset")"
  done
done
