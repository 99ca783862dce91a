#!/usr/bin/env bash
# tools/bench_order.sh [SINEW] — the sparse Cholesky factorisation chosen by measurement
# (docs/performance.md, "Factorisation: ordering, kind and threads"): the hanging cloth
# (scenes/hanging_cloth.yaml, --grid N x N for N in $NS, default "40 80 160 320") and the
# shipped garments in $GARMENTS (default scenes/garment_tank.yaml, garment_tshirt_dxf.yaml, with
# the fit off and a short duration) under each fill-reducing ordering in $ORDERINGS (default "amd metis
# nesdis") x {simplicial, supernodal} x OpenBLAS threads {1, 2} (--ordering, --factorization,
# --threads), and the default (auto ordering and kind, one thread).  A simplicial factorisation makes no BLAS call, so it runs with one thread only;
# above N = $SIMPLICIAL_MAX (default 160) it is left out (8x slower than supernodal there).
#
# Every configuration of a scene runs once per repetition (REPS, default 3), the
# configurations interleaved, so a busy machine slows them alike.  Each run is paired with one
# of the same scene and configuration that stops at t = 0 (loading, pattern, analysis; the
# garments' too with the fit off): the per-step CPU time (user + system, every thread) is
# (cpu - cpu0) / steps, and so is the wall time.  Per run also the factor's nonzeros (CHOLMOD's
# lnz, summary.json factor_nnz), the ordering and kind the analysis used, Newton iterations,
# factorisations and cpu0 (what the analysis adds).  Writes $OUT (default
# docs/bench/order/factor_order.csv) and prints the table of tools/bench_order.py.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-build/sinew}")
ns=${NS:-40 80 160 320}
orderings=${ORDERINGS:-amd metis nesdis}
reps=${REPS:-3}
simplicial_max=${SIMPLICIAL_MAX:-160}
out=${OUT:-docs/bench/order/factor_order.csv}
mkdir -p "$(dirname "$out")"
work=$(mktemp -d)
garments=${GARMENTS-garment_tank garment_tshirt_dxf}
tmpscenes=()
cleanup() { rm -rf "$work"; rm -f "${tmpscenes[@]}"; }
trap cleanup EXIT
# The garments without their fit (its length depends on the solution, and a shortened one
# fails the run): beside the originals, whose meshes and patterns they name relatively.
for g in $garments; do
  s=scenes/.bench_order_$$_$g.yaml
  tmpscenes+=("$s")
  { cat "scenes/$g.yaml"; echo "fit: {enabled: false}"; } >"$s"
done
# field DIR KEY: a number or a string of DIR/summary.json
field() {
  sed -n "s/^ *\"$2\": \"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}$/\1/p" "$1/summary.json" | head -1
}
# scene, duration and extra arguments of case C (cloth N or a garment)
case_args() {
  case $1 in
    garment_tank) echo "scenes/.bench_order_$$_garment_tank.yaml 0.3" ;;
    garment_tshirt_dxf) echo "scenes/.bench_order_$$_garment_tshirt_dxf.yaml 0.1" ;;
    40) echo "scenes/hanging_cloth.yaml 0.5 --grid 40x40" ;;
    80) echo "scenes/hanging_cloth.yaml 0.2 --grid 80x80" ;;
    160) echo "scenes/hanging_cloth.yaml 0.02 --grid 160x160" ;;
    *) echo "scenes/hanging_cloth.yaml 0.01 --grid $1x$1" ;;
  esac
}
configs() { # ordering:kind:threads of case C; first the default (auto:auto, one thread)
  echo "auto:auto:1"
  for o in $orderings; do
    if [ "${1#garment}" != "$1" ] || [ "$1" -le "$simplicial_max" ]; then echo "$o:simplicial:1"; fi
    echo "$o:supernodal:1"
    echo "$o:supernodal:2"
  done
}
echo "case,dofs,ordering,factorization,threads,rep,status,steps,newton_iterations,factorizations,factor_nnz,ordering_used,factorization_used,cpu_s,wall_s,cpu0_s,wall0_s,cpu_step_s,wall_step_s" >"$out"
for rep in $(seq 1 "$reps"); do
  for c in $ns $garments; do
    read -r scene dur extra <<<"$(case_args "$c")"
    for cfg in $(configs "$c"); do
      IFS=: read -r o k t <<<"$cfg"
      args=(--no-frames --quiet --ordering "$o" --factorization "$k" --threads "$t")
      # shellcheck disable=SC2086
      "$bin" run "$scene" $extra --duration 0 --out "$work/zero" "${args[@]}" >/dev/null 2>&1 || true
      # shellcheck disable=SC2086
      "$bin" run "$scene" $extra --duration "$dur" --out "$work/run" "${args[@]}" >/dev/null 2>&1 || true
      d=$work/run z=$work/zero
      cpu=$(field "$d" cpu_time_s) wall=$(field "$d" wall_time_s) steps=$(field "$d" steps)
      cpu0=$(field "$z" cpu_time_s) wall0=$(field "$z" wall_time_s)
      line=$(printf '%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s' "$c" \
        "$(field "$d" free_dofs)" "$o" "$k" "$t" "$rep" "$(field "$d" status)" "$steps" \
        "$(field "$d" newton_iterations)" "$(field "$d" factorizations)" \
        "$(field "$d" factor_nnz)" "$(field "$d" ordering)" "$(field "$d" factorization)" \
        "$cpu" "$wall" "$cpu0" "$wall0")
      per=$(awk -v a="$cpu" -v b="$cpu0" -v w="$wall" -v w0="$wall0" -v s="$steps" \
        'BEGIN { if (s > 0) printf "%.6g,%.6g", (a - b) / s, (w - w0) / s; else printf "," }')
      echo "$line,$per" | tee -a "$out" >&2
    done
  done
done
/usr/bin/python3 tools/bench_order.py "$out"
