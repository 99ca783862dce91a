#!/usr/bin/env bash
# tools/bench_garment.sh [SINEW] — the shipped garments (scenes/garment_skirt.yaml: four flat
# panels, 756 cloth vertices; scenes/garment_tank.yaml: front and back, 566 vertices; each on
# the 962-vertex mannequin; scenes/garment_tshirt.yaml: front, back and sleeves, 800 vertices,
# on the 1254-vertex mannequin with arms; scenes/garment_skirt_dxf.yaml: the skirt's panels read
# from a DXF pattern (sinew pattern import), 1670 vertices, Morley bending;
# scenes/garment_tshirt_dxf.yaml: the T-shirt's pieces from its DXF pattern, 1557 vertices;
# self-contact on) from their
# arrangement to rest and on through their dynamics, REPS times (default 1): wall and CPU time of
# the whole run, wall time of the fit stage, steps and Newton iterations of each, the cost per step and per
# Newton iteration, and the share of the step time of each term's evaluations, of self-contact's
# continuous collision detection, of the factorisations and of the solves; then the fit check
# (tools/garment_check.py: seam_gap_max < 1 mm, no intersection, tension XY higher on the hip
# line, or the tank's bust line, than at the hem; the tank's top at least 1.40 m high, on the
# shoulders, whose ridge is at 1.42-1.43 m; the T-shirt's likewise).  Writes
# docs/bench/garment/GARMENT.csv and prints each as a table.  GARMENTS="skirt" runs one of them;
# KEEP=DIR keeps each run folder as DIR/GARMENT_REP (for `sinew render`).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
reps=${REPS:-1}
out=${OUT:-docs/bench/garment}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
[ -n "${KEEP:-}" ] && mkdir -p "$KEEP"
mkdir -p "$out"
status=0
# the height of each garment's tight line on the mannequin: the hips, the bust
declare -A line_z=([skirt]=0.85 [skirt_dxf]=0.85 [tank]=1.224 [tshirt]=1.224 [tshirt_dxf]=1.224) \
  top_z=([skirt]=0 [skirt_dxf]=0 [tank]=1.40 [tshirt]=1.40 [tshirt_dxf]=1.40)
for g in ${GARMENTS:-skirt tank tshirt skirt_dxf tshirt_dxf}; do
  csv=$out/$g.csv
  for r in $(seq "$reps"); do
    d=$work/$g$r
    /usr/bin/time -f %U -o "$d.cpu" "$bin" run "scenes/garment_$g.yaml" --out "$d" --quiet \
      --threads 1 >/dev/null 2>&1 || status=1
    /usr/bin/python3 tools/garment_check.py "$d" --line-z "${line_z[$g]}" --top-z "${top_z[$g]}" |
      sed "s/^/$g rep $r: /" || status=1
    /usr/bin/python3 - "$d/summary.json" "$r" "$csv" "$d.cpu" <<'PY'
import json, os, sys
s, rep, csv = json.load(open(sys.argv[1])), sys.argv[2], sys.argv[3]
cpu = float(open(sys.argv[4]).read().split()[-1])
ts, it, st = s["time_step_s"], s["newton_iterations"], s["steps"]
row = {"rep": rep, "status": s["status"], "wall_s": s["wall_time_s"], "cpu_s": cpu,
       "fit_wall_s": s["fit_wall_s"],
       "fit_end_s": s["fit_end_s"], "fit_steps": s["fit_steps"], "steps": st,
       "newton_iterations": it, "step_ms_per_step": 1e3 * ts / st,
       "step_ms_per_iteration": 1e3 * ts / it, "seam_gap_max_m": s["seam_gap_max"]}
for k, v in s["time_terms_s"].items():
    row["share_" + k] = v / ts
for k in ("time_self_ccd_s", "time_factor_s", "time_solve_s", "time_pattern_s"):
    row["share_" + k[5:-2]] = s.get(k, 0.0) / ts
new = not os.path.exists(csv) or rep == "1"
with open(csv, "w" if new else "a") as f:
    if new:
        f.write(",".join(row) + "\n")
    f.write(",".join("%.4g" % v if isinstance(v, float) else str(v) for v in row.values()) + "\n")
PY
    if [ -n "${KEEP:-}" ]; then rm -rf "${KEEP:?}/${g}_$r"; cp -r "$d" "$KEEP/${g}_$r"; fi
  done
  echo "$g:"
  column -s, -t <"$csv"
done
exit $status
