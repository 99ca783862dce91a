#!/usr/bin/env bash
# tools/bench_docs.sh — regenerate every chart and table of docs/benchmarks.md: `sinew bench` on
# the shipped scenes, the CSV files, PNG charts and printed tables copied to docs/bench/NAME/.
#
#   tools/bench_docs.sh [NAME ...]      NAME: hanging_cloth drawstring membrane_2d
#                                              membrane_2d_forcing membrane_crush_2d
#                                              stiff stiff_stability
#                                              drape_sphere drape_sphere_fold scaling
#                                              (default: all)
#   JOBS=N  runs N at a time (default 2, both cores: the runs then share the machine, which
#           moves their CPU times, charted by default, much less than their wall times
#           (docs/benchmarks.md, "Timing on a shared machine"); the scaling sweep, which charts
#           wall time per step, always runs alone)
#   OUT=DIR where the run folders go (default out/bench_docs; they are not copied)
#   SINEW=PATH the sinew executable (default build/sinew)
#
# Takes about an hour on a 2-core machine, most of it in the references (CVODE at rtol 1e-10)
# and in the 512 x 512 grid of the scaling sweep.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh >/dev/null
sinew=${SINEW:-build/sinew}
out=${OUT:-out/bench_docs}
jobs=${JOBS:-2}
mkdir -p "$out"

# bench NAME JOBS ARGS...: run, print, keep the CSV, PNG and the printed table in docs/bench/NAME
bench() {
  local name=$1 j=$2
  shift 2
  echo "== $name: sinew bench $*"
  rm -rf "${out:?}/$name"
  "$sinew" bench "$@" --out "$out/$name" --jobs "$j" | tee "$out/$name.txt" || true
  mkdir -p "docs/bench/$name"
  rm -f "docs/bench/$name"/*.csv "docs/bench/$name"/*.png
  cp "$out/$name"/*.csv "$out/$name"/*.png "docs/bench/$name/"
  cp "$out/$name.txt" "docs/bench/$name/bench.txt"
}

run_one() {
  case $1 in
    hanging_cloth) # the default scene, first second (a swing), scene dt 10 ms and halvings
      bench hanging_cloth "$jobs" scenes/hanging_cloth.yaml --duration 0.5 --repeat 2 \
        --timeout 1800 ;;
    drawstring) # a cloth gathered by a hem cable (tendon + gathered, compressed cloth), to
      # 0.12 s: before its buckling amplifies every error to the same size (docs/benchmarks.md)
      bench drawstring "$jobs" scenes/cloth_drawstring.yaml --duration 0.12 \
        --dts 0.01,0.005,0.0025,0.00125 --rtols 1e-3,1e-4,1e-5 --max-halvings 8 --timeout 1800 ;;
    membrane_2d) # three pretensioned cables contracting in turn on a 2D membrane, smooth
      # throughout: the fixed-step methods' orders over the whole run
      bench membrane_2d "$jobs" scenes/tendon_membrane_2d.yaml --repeat 2 --max-halvings 8 \
        --timeout 1800 ;;
    membrane_2d_forcing) # the same scene without each of its three smoothing choices in turn
      # (docs/benchmarks.md, "What a slope jump does"): linear keyframes; no pretension (the
      # waiting cables go slack and snap taut); no stiffness damping
      local s=scenes/tendon_membrane_2d.yaml
      sed 's/interpolation: smooth/interpolation: linear/' $s >"$out/membrane_2d_linear.yaml"
      sed -e 's/\[\[0, 1.0\], \[0.5, 0.98\], \[1.5, 0.98\], \[2.5, 0.95\]\]/[[1.5, 1.0], [2.5, 0.95]]/' \
        -e 's/\[\[0, 1.0\], \[0.5, 0.98\], \[2.5, 0.98\], \[3.5, 0.95\]\]/[[2.5, 1.0], [3.5, 0.95]]/' \
        -e 's/\[\[0, 1.0\], \[0.5, 0.98\], \[1.5, 0.95\]\]/[[0.5, 1.0], [1.5, 0.95]]/' \
        $s >"$out/membrane_2d_slack.yaml"
      sed 's/damping: {mass: 2.0, stiffness: 0.001}/damping: {mass: 2.0}/' $s \
        >"$out/membrane_2d_undamped.yaml"
      # each sed must have done all its work: what it removes is gone from the variant
      local -A gone=([linear]='interpolation: smooth' [slack]='0\.98' [undamped]='stiffness: 0\.001')
      for v in linear slack undamped; do
        grep -q "${gone[$v]}" "$out/membrane_2d_$v.yaml" &&
          { echo "bench_docs: membrane_2d_$v still has '${gone[$v]}'" >&2; exit 2; }
        bench membrane_2d_$v "$jobs" "$out/membrane_2d_$v.yaml" --methods backward-euler,bdf2 \
          --max-halvings 8 --timeout 1800
      done ;;
    membrane_crush_2d) # the membrane as it first shipped: 80 % contractions that crush faces
      bench membrane_crush_2d "$jobs" scenes/bench/membrane_crush_2d.yaml --repeat 2 \
        --max-halvings 8 --timeout 1800 ;;
    stiff) # 50 kN/m fabric: symplectic Euler fails at every implicit-sized step
      bench stiff "$jobs" scenes/bench/stiff_cloth.yaml --repeat 2 --timeout 1800 ;;
    stiff_stability) # where each fixed-step method fails, stiffness x 1, 10, 100
      bench stiff_stability "$jobs" scenes/bench/stiff_cloth.yaml --stability --duration 0.2 \
        --dts 0.02,0.01,0.005,0.002,0.0005,0.0002 --scales 1,10,100 --timeout 1800 ;;
    drape_sphere) # contact: the cloth touches the sphere at ~0.05 s; CVODE and IDA fail at
      # the first contact, so the reference is BDF2 at 2.5 ms / 8, confirmed by BDF2 at half
      # that step; to 0.12 s, before the folds amplify every difference (drape_sphere_fold)
      bench drape_sphere 1 scenes/drape_sphere.yaml --duration 0.12 \
        --methods backward-euler,bdf2,baraff-witkin --dts 0.01,0.005,0.0025 \
        --reference bdf2 --confirm bdf2 --confirm-tol 1e-3 --timeout 1800 ;;
    drape_sphere_fold) # the same to 0.3 s, through the folding: the reference is not confirmed
      bench drape_sphere_fold 1 scenes/drape_sphere.yaml --duration 0.3 \
        --methods backward-euler,bdf2,baraff-witkin --dts 0.01,0.005,0.0025 \
        --reference bdf2 --confirm bdf2 --confirm-tol 1e-3 --timeout 1800 ;;
    scaling) # per-step time and memory up to 512 x 512 = 262k vertices, one run at a time
      bench scaling 1 scenes/bench/scaling_cloth.yaml --scaling --sizes 32,64,128,256,512 \
        --steps 3 --methods backward-euler,bdf2,implicit-midpoint ;;
    *) echo "bench_docs: unknown name '$1'" >&2; exit 2 ;;
  esac
}

names=("$@")
((${#names[@]})) || names=(hanging_cloth drawstring membrane_2d membrane_2d_forcing membrane_crush_2d stiff stiff_stability
                             drape_sphere drape_sphere_fold scaling)
for n in "${names[@]}"; do run_one "$n"; done
echo "bench_docs: charts in docs/bench/*/ (docs/benchmarks.md)"
