#!/usr/bin/env bash
# tools/bench_orders.sh — regenerate docs/bench/adaptive_order/: CVODE and IDA at every largest
# BDF order, and the work-precision charts of their old and new defaults (docs/integrators.md,
# "Which BDF order").
#
#   tools/bench_orders.sh [NAME ...]   NAME: sweep_hanging_cloth sweep_drawstring sweep_skirt
#                                            before after compare (default: all)
#   SINEW=PATH the sinew executable (default build/sinew); OUT=DIR the run folders
#   (default out/bench_orders; they are not copied)
#
# sweep_*: `sinew bench --max-orders 1,2,3,4,5` at rtol 1e-3 ... 1e-8 on a shipped scene, runs
# over 45 s killed (recorded as timed out); then tools/order_table.py gathers the three (their
# run folders: it reads each run's summary.json) into order_sweep.csv and order_sweep.md.  before / after: the default scene over 0.3 s, CVODE and IDA at rtol 1e-3 ...
# 1e-6 with the defaults before this change (max_order 5, CVODE setup_every 20: a copy of the
# scene with `setup_every: 20`) and after it (max_order auto, setup_every 200), each bench a few
# minutes; compare: one chart of both (the rows of before renamed "... before").  One run at a
# time: about 80 minutes on a 2-core machine, most of it in the sweeps.
set -euo pipefail
cd "$(dirname "$0")/.."
sinew=${SINEW:-build/sinew}
out=${OUT:-out/bench_orders}
doc=docs/bench/adaptive_order
mkdir -p "$out" "$doc"
rtols=1e-3,1e-4,1e-5,1e-6,1e-7,1e-8

# keep NAME: the bench's tables, charts and printed table into docs/bench/adaptive_order/NAME
keep() {
  mkdir -p "$doc/$1"
  rm -f "$doc/$1"/*.csv "$doc/$1"/*.png
  cp "$out/$1"/*.csv "$doc/$1/"
  cp "$out/$1"/*.png "$doc/$1/" 2>/dev/null || true
  cp "$out/$1.txt" "$doc/$1/bench.txt"
}

# sweep NAME SCENE DURATION [ARGS...]
sweep() {
  local name=$1 scene=$2 dur=$3
  shift 3
  rm -rf "${out:?}/$name"
  "$sinew" bench "$scene" --out "$out/$name" --methods cvode,ida --max-orders 1,2,3,4,5 \
    --rtols $rtols --dts 0.01 --duration "$dur" --timeout 45 --no-charts "$@" |
    tee "$out/$name.txt" || true
  keep "$name"
}

wp() { # NAME SCENE METHODS
  rm -rf "${out:?}/$1"
  "$sinew" bench "$2" --out "$out/$1" --methods "$3" --rtols 1e-3,3e-4,1e-4,1e-5,1e-6 \
    --dts 0.01 --duration 0.3 --repeat 1 --timeout 600 | tee "$out/$1.txt" || true
  keep "$1"
}

run_one() {
  case $1 in
    sweep_hanging_cloth) sweep "$1" scenes/hanging_cloth.yaml 0.3 ;;
    sweep_drawstring) sweep "$1" scenes/cloth_drawstring.yaml 0.5 --max-halvings 8 ;;
    sweep_skirt) sweep "$1" scenes/skirt.yaml 0.2 --max-halvings 8 ;;
    before)
      sed 's/^integrator:$/integrator:\n  setup_every: 20/' scenes/hanging_cloth.yaml \
        >"$out/hanging_cloth_before.yaml"
      grep -q 'setup_every: 20' "$out/hanging_cloth_before.yaml"
      wp before "$out/hanging_cloth_before.yaml" cvode:q5,ida:q5 ;;
    after) wp after scenes/hanging_cloth.yaml cvode,ida,cvode:q5 ;;
    compare)
      rm -rf "${out:?}/compare"
      mkdir -p "$out/compare/runs" "$doc/compare"
      cp "$out/after/reference.csv" "$out/compare/"
      for r in "$out/after/runs"/*; do ln -s "../../after/runs/${r##*/}" "$out/compare/runs/"; done
      for r in "$out/before/runs"/*; do
        ln -s "../../before/runs/${r##*/}" "$out/compare/runs/before_${r##*/}"
      done
      { cat "$out/after/work_precision.csv"
        tail -n +2 "$out/before/work_precision.csv" |
          sed -e 's/^\([^,]*\),/\1 before,/' -e 's/,runs\/\([^,]*\)$/,runs\/before_\1/'
      } >"$out/compare/work_precision.csv"
      /usr/bin/python3 tools/bench_charts.py "$out/compare" \
        --title "default scene, 0.3 s: old defaults (before) and new" >/dev/null
      cp "$out/compare"/*.csv "$out/compare"/*.png "$doc/compare/" ;;
    *) echo "tools/bench_orders.sh: unknown name $1" >&2; exit 2 ;;
  esac
}

names=("$@")
[ ${#names[@]} -gt 0 ] || names=(sweep_hanging_cloth sweep_drawstring sweep_skirt before after compare)
for n in "${names[@]}"; do run_one "$n"; done
args=()
for n in hanging_cloth:sweep_hanging_cloth drawstring:sweep_drawstring skirt:sweep_skirt; do
  [ -f "$out/${n#*:}/work_precision.csv" ] && args+=("${n%%:*}=$out/${n#*:}")
done
if [ ${#args[@]} -gt 0 ]; then
  /usr/bin/python3 tools/order_table.py "$doc/order_sweep.csv" "${args[@]}" >"$doc/order_sweep.md"
fi
