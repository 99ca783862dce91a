#!/usr/bin/env bash
# tools/bench_contact_compare.sh OLD_SINEW [NEW_SINEW] — the contact terms of two builds on
# every shipped scene with the triangle-mesh contact term (scenes/fold_self.yaml,
# scenes/drape_sphere.yaml, scenes/drape_mesh.yaml and the garments scenes/garment_tank.yaml,
# garment_skirt.yaml, garment_tshirt.yaml), run interleaved (old, new, old, new ..., REPS
# times, default 1) so that both see the same machine load, one BLAS thread each.
# Durations: FOLD (default 0.3 s: its folds meet from 0.2 s on), DRAPE (1 s), MESH (1.5 s),
# GARMENT (0.5 s after the fit, as shipped); SCENES picks some of them (default all).
# Per run: status, steps, Newton iterations, the mesh_contact term's time (its evaluations:
# candidates, distances, blocks) and the self CCD's (line searches and steps' starts), both per
# Newton iteration, the factorisation's time, the contact terms over the factorisation, and the
# largest distance of the end positions from the old build's (positions.bin, m); and the
# process's CPU time with the contact terms' CPU time per iteration estimated from their share
# of the wall time.  With CPU_CLOCK=1 (the default) every run has tools/cpu_clock.c preloaded:
# the timers of summary.json then count CPU seconds, not wall seconds, so that neither the
# ratios nor the shares depend on how many other processes share the cores (CPU_CLOCK=0: wall
# time, as sinew reports it).  The build named `old` is the reference of the ratios.  Writes
# docs/bench/contact/compare.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: tools/bench_contact_compare.sh OLD_SINEW [NEW_SINEW]}
new=${2:-build/sinew}
reps=${REPS:-1}
out=${OUT:-docs/bench/contact}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
g=${GARMENT:-0.5}
declare -A dur=([fold_self]=${FOLD:-0.3} [drape_sphere]=${DRAPE:-1} [drape_mesh]=${MESH:-1.5}
  [garment_tank]=$g [garment_skirt]=$g [garment_tshirt]=$g)
pre=""
if [ "${CPU_CLOCK:-1}" = 1 ]; then
  cc -O2 -shared -fPIC tools/cpu_clock.c -o "$work/cpu_clock.so" -ldl
  pre=$work/cpu_clock.so
fi
csv="$out/compare.csv"
echo "scene,duration_s,build,rep,status,steps,newton_iterations,mesh_contact_s,self_ccd_s,factor_s,step_s,contact_ms_per_iteration,contact_over_factor,cpu_s,contact_cpu_ms_per_iteration,end_max_diff_m" >"$csv"
for r in $(seq "$reps"); do
  for s in ${SCENES:-fold_self drape_sphere drape_mesh garment_tank garment_skirt garment_tshirt}; do
    for b in old new; do
      bin=$old; [ "$b" = new ] && bin=$new
      d="$work/$s-$b-$r"
      LD_PRELOAD=$pre /usr/bin/time -f "%U %S" -o "$work/cpu" "$bin" run "scenes/$s.yaml" --duration "${dur[$s]}" \
        --out "$d" --no-frames --positions-every "${dur[$s]}" --quiet --threads 1 >/dev/null 2>&1 || true
      cpu=$(awk '{print $1 + $2}' "$work/cpu")
      diff=""
      [ "$b" = new ] && diff=$(/usr/bin/python3 tools/positions_diff.py "$work/$s-old-$r" "$d" \
        2>/dev/null | tail -1 | awk '{print $3}')
      /usr/bin/python3 - "$d/summary.json" "$s" "${dur[$s]}" "$b" "$r" "$cpu" "${diff:-}" >>"$csv" <<'PY'
import json, sys
f, scene, dur, build, rep, cpu, diff = sys.argv[1:]
s = json.load(open(f))
it = max(s["newton_iterations"], 1)
mc = s["time_terms_s"].get("mesh_contact", 0.0)
ccd = s.get("time_self_ccd_s", 0.0)
fac = s["time_factor_s"]
# CPU time of the contact terms: the process's CPU time times their share of the wall time
# (the machine may be shared: shares hold under load, wall times do not)
share = (mc + ccd) / s["wall_time_s"]
print(f"{scene},{dur},{build},{rep},{s['status']},{s['steps']},{it},{mc:.4g},{ccd:.4g},{fac:.4g},"
      f"{s['time_step_s']:.4g},{1e3 * (mc + ccd) / it:.4g},{(mc + ccd) / fac:.3f},{cpu},"
      f"{1e3 * float(cpu) * share / it:.4g},{diff}")
PY
    done
  done
done
cat "$csv"
