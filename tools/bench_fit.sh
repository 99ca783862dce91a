#!/usr/bin/env bash
# tools/bench_fit.sh [SINEW] — the fit stage as dynamics or as an optimisation (docs/garments.md,
# `fit.mode`, `fit.dt`), on the shipped garments with seams (scenes/garment_{skirt,tank,tshirt,
# skirt_dxf,tshirt_dxf}.yaml; the gather and the drawstring have none, so no fit), REPS times
# (default 1), the runs interleaved per garment and repetition.  RUNS lists them (default
# "dynamic optimize settle"): `dynamic`, `optimize` and `settle` are the fit modes, `dt=H` the
# dynamic fit with steps of H s, `tol=T` the dynamic fit with Newton's tolerance `fit.newton_tol`
# T m/s, and `+` joins them (`tol=1e-4+dt=0.005`); the reference, the dynamic fit at the scene's
# own fit step followed by a static solve (`--method static`, with the dynamic fit's compact
# bending matrix), is always run.  REFS lists accurate fits in the same notation (say "tol=1e-4
# tol=1e-5 tol=1e-4+dt=0.005"), each followed by the static solve like the reference: the table
# then measures every run against each of them and prints their spread among themselves (a
# garment whose rest state the fit's own accuracy does not decide to 1 mm).  Each is the fit alone
# (`--duration 0`, one BLAS thread, positions.bin at every step: its last record is the end);
# CPU time is the process's user time.  Writes docs/bench/fit/fit.csv (one row per run) and
# docs/bench/fit/fit.md (the table: CPU and Newton iterations of each fit, their ratios to the
# dynamic fit's, and each fit against the reference: RMS and largest distance of the final
# positions, relative change of tension XY's mean and 95th percentile, largest seam gap,
# self-intersections); OUT=DIR writes them elsewhere, KEEP=DIR keeps the final positions there
# (GARMENT-RUN-REP.bin, for tools/fit_table.py).  GARMENTS="skirt tank" runs some of them.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
reps=${REPS:-1}
out=${OUT:-docs/bench/fit}
work=$(mktemp -d)
pos=${KEEP:-$work/pos}
scenes=()
trap 'rm -rf "$work" "${scenes[@]}"' EXIT
mkdir -p "$out"
csv=$out/fit.csv
echo "garment,rep,run,status,cpu_s,fit_steps,fit_end_s,newton_iterations,static_iterations,retries,seam_gap_max_m,self_intersections,txy_mean,txy_p95,txy_max" >"$csv"
for r in $(seq "$reps"); do
  for g in ${GARMENTS:-skirt tank tshirt skirt_dxf tshirt_dxf}; do
    refs=()
    for x in ${REFS:-}; do refs+=("ref:$x"); done
    for run in ${RUNS:-dynamic optimize settle} static "${refs[@]}"; do
      # the scene beside the shipped one (its files are found from its folder)
      sc=scenes/.bench_fit_${g}_$run.yaml
      scenes+=("$sc")
      cp "scenes/garment_$g.yaml" "$sc"
      mode=dynamic extra=() opts=""
      # the reference's fit is the dynamic one's: with --method static the automatic bending
      # matrix would be the exact one for the fit too (docs/integrators.md, "The bending matrix")
      case $run in static | ref:*) extra=(--method static --bending-matrix compact) ;; esac
      IFS=+ read -ra parts <<<"${run#ref:}"
      for p in "${parts[@]}"; do
        case $p in
          optimize | settle) mode=$p ;;
          dt=*) opts+=", dt: ${p#dt=}" ;;
          tol=*) opts+=", newton_tol: ${p#tol=}" ;;
          dynamic | static) ;;
          *) echo "tools/bench_fit.sh: run '$run': unknown setting '$p' (dynamic, optimize, settle, dt=H, tol=T)" >&2
             exit 2 ;;
        esac
      done
      echo "fit: {mode: $mode$opts}" >>"$sc"
      d=$work/$g-$run-$r
      /usr/bin/time -f %U -o "$d.cpu" "$bin" run "$sc" --out "$d" --duration 0 --no-frames \
        --positions-every 1e-6 --threads 1 --quiet "${extra[@]}" >/dev/null 2>"$d.err" || true
      /usr/bin/python3 - "$d" "$g" "$r" "$run" >>"$csv" <<'PY'
import csv, json, sys
d, g, rep, run = sys.argv[1:5]
s = json.load(open(d + "/summary.json"))
cpu = float(open(d + ".cpu").read().split()[-1])
t = list(csv.DictReader(open(d + "/tension.csv")))[-1]
print(",".join(str(v) for v in (g, rep, run, s["status"], cpu, s["fit_steps"], s["fit_end_s"],
      s["newton_iterations"], s.get("static_iterations", 0), s.get("retries", 0),
      s["seam_gap_max"], s["self_intersections"], t["txy_mean"], t["txy_p95"], t["txy_max"])))
PY
      mkdir -p "$pos"
      cp "$d/positions.bin" "$pos/$g-$run-$r.bin" 2>/dev/null || true
      rm -rf "$d"
    done
  done
done
/usr/bin/python3 -B tools/fit_table.py "$csv" "$pos" >"$out/fit.md"
cat "$out/fit.md"
