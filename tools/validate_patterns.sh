#!/bin/bash
# validate_patterns.sh — real Gerber pattern files through `sinew garment` (the automatic path
# only: import, automatic sewing, arrangement, fit at the defaults, 2 cm edges), where the
# folder of real files exists (../shared/patterns beside the checkout, or $PATTERNS).  Goal per
# garment: status ok, seam_gap_max < 1 mm, 0 self and 0 obstacle intersections, <= 60 s CPU.
#   tools/validate_patterns.sh [SINEW] [OUT]   (default build/sinew, /tmp/validate_patterns)
# docs/garments.md, "Real patterns", records what it reached.
set -u
cd "$(dirname "$0")/.."
SINEW=${1:-build/sinew}
OUT=${2:-/tmp/validate_patterns}
PATTERNS=${PATTERNS:-../shared/patterns}
if [ ! -d "$PATTERNS" ]; then
  echo "validate_patterns.sh: no $PATTERNS here; nothing to validate" >&2
  exit 0
fi
mkdir -p "$OUT"
fail=0
run() {  # NAME FILE [sinew garment options]
  local name=$1 file=$2
  shift 2
  echo "== $name: sinew garment $file $*"
  if ! "$SINEW" garment "$PATTERNS/$file" --out "$OUT/$name" --edge 0.02 "$@"; then
    fail=1
    return
  fi
  /usr/bin/python3 - "$OUT/$name/run/summary.json" <<'PY' || fail=1
import json, sys
s = json.load(open(sys.argv[1]))
ok = {"status ok": s["status"] == "ok", "seam gap < 1 mm": s["seam_gap_max"] < 1e-3,
      "no self intersection": s["self_intersections"] == 0,
      "no obstacle intersection": s["obstacle_intersections"] == 0,
      "<= 60 s CPU": s["cpu_time_s"] <= 60}
print("   ", "; ".join("%s: %s" % (k, "yes" if v else "NO") for k, v in ok.items()),
      "(cpu %.1f s)" % s["cpu_time_s"])
sys.exit(0 if all(ok.values()) else 1)
PY
}
run tank WM_LOOSE_SHAPE_TANK.DXF
run tee GMX1006S18-1.DXF --pieces GMX1006S18FR,GMX1006S18BK,GMX1006S18SS
run polo GMX1016S18_AAMA.DXF --pieces GMX1016S18FR,GMX1016S18BK,GMX1016S18SS
exit $fail
