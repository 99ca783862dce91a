#!/bin/sh
# newton_certificate.sh — measure whether a cheaper test than Newton's last iteration could
# certify convergence (docs/performance.md, "Newton's last iteration").
#
#   tools/newton_certificate.sh [scene ...]     (default: hanging_cloth hanging_cloth_80
#                                                drape_sphere garment_tank)
#
# Builds sinew with -DSW_NEWTON_PROBE in build-probe/ (a diagnostic build: it prints one line
# per Newton iteration and allocates in the loop, so it is never the shipped one), runs each
# scene for DURATION s of simulated time (default 0.5) and prints the table of
# tools/newton_certificate.py.  The logs stay in ${OUT:-/tmp/newton_certificate}.
set -eu
cd "$(dirname "$0")/.."
build=build-probe
if [ ! -d "$build" ]; then
  meson setup "$build" -Dtests=false -Dc_args=-DSW_NEWTON_PROBE >/dev/null
fi
ninja -C "$build" sinew >/dev/null
out=${OUT:-/tmp/newton_certificate}
mkdir -p "$out"
scenes=${*:-"hanging_cloth hanging_cloth_80 drape_sphere garment_tank"}
logs=""
for s in $scenes; do
  echo "newton_certificate: $s" >&2
  "$build/sinew" run "scenes/$s.yaml" --out "$out/$s" --quiet --duration "${DURATION:-0.5}" \
    2> "$out/$s.log"
  logs="$logs $out/$s.log"
done
/usr/bin/python3 tools/newton_certificate.py $logs
