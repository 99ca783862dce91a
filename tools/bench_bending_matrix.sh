#!/usr/bin/env bash
# tools/bench_bending_matrix.sh [SINEW] — the bending's part of Newton's matrix, exact against
# compact (`--bending-matrix`, docs/integrators.md "The bending matrix"), on every shipped scene
# whose bending is quadratic or morley: the garments with seams their fit alone (`--duration
# 0`), the others as shipped (DURATION= to cap them).  One binary; the two modes alternate per
# scene and repetition (REPS=, default 1), one BLAS thread, CPU = the process's user time.
# Compared per scene: status, fit end, Newton iterations, factor nonzeros, the factorisation's
# and assembly's time, seam gap, intersections, tension XY p95 of the last state and the RMS
# and largest distance between the two modes' last frames' positions.  Writes
# docs/bench/bending_matrix/bending_matrix.csv (OUT= another folder) and prints a Markdown
# table (docs/performance.md, "The bending matrix").
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
out=${OUT:-docs/bench/bending_matrix}
work=$(mktemp -d /tmp/bench_bmatrix.XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
csv=$out/bending_matrix.csv
fits="garment_tank garment_tshirt garment_skirt garment_skirt_dxf garment_tshirt_dxf"
runs="garment_gather drape_sphere drape_mannequin drape_mesh skirt skirt_body fold_self cloth_drawstring"
echo "scene,rep,matrix,status,cpu_s,time_reached_s,fit_end_s,newton_iterations,factor_nnz,time_factor_s,time_assemble_s,seam_gap_max_m,self_intersections,obstacle_intersections,txy_p95,rms_vs_exact_m,max_vs_exact_m" >"$csv"
for rep in $(seq 1 "${REPS:-1}"); do
  for s in ${SCENES:-$fits $runs}; do
    dur=()
    case " $fits " in *" $s "*) dur=(--duration 0) ;; *) [ -n "${DURATION:-}" ] && dur=(--duration "$DURATION") ;; esac
    for mx in exact compact; do
      d=$work/$s-$mx
      rm -rf "$d"
      /usr/bin/time -f %U -o "$d.cpu" "$bin" run "scenes/$s.yaml" --out "$d" "${dur[@]}" \
        --bending-matrix "$mx" --frames-every 0 --frames-format binary --threads 1 --quiet \
        >/dev/null 2>&1 || true
    done
    PYTHONPATH=python /usr/bin/python3 - "$work/$s" "$s" "$rep" >>"$csv" <<'PY'
import csv, json, sys
import numpy as np
from sinew import frames
base, scene, rep = sys.argv[1:4]

def last_positions(d):  # the last frame's cloth (float64 frames)
    return frames.read(frames.index(d)[-1][1]["cloth"]).points

ref = last_positions(base + "-exact")
for mx in ("exact", "compact"):
    d = base + "-" + mx
    s = json.load(open(d + "/summary.json"))
    cpu = float(open(d + ".cpu").read().split()[-1])
    t = list(csv.DictReader(open(d + "/tension.csv")))[-1]
    dist = np.linalg.norm(last_positions(d) - ref, axis=1)
    print(",".join(str(v) for v in (scene, rep, mx, s["status"], cpu, s["time_reached"],
          s.get("fit_end_s", ""), s["newton_iterations"], s.get("factor_nnz", ""),
          s["time_factor_s"], s["time_assemble_s"], s.get("seam_gap_max", ""),
          s.get("self_intersections", ""), s.get("obstacle_intersections", ""), t["txy_p95"],
          float(np.sqrt(np.mean(dist ** 2))), float(dist.max()))))
PY
  done
done
/usr/bin/python3 - "$csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| scene | matrix | status | fit end, s | Newton it. | factor nnz | CPU s | CPU compact / exact | factorisation s | seam gap mm | self / obstacle crossings | tension XY p95 N/m | last positions vs exact: RMS / max mm |")
print("| --- | --- | --- | --: | --: | --: | --: | --: | --: | --: | --: | --: | --: |")
med = lambda rs, k: statistics.median(float(r[k]) for r in rs)
for sc in dict.fromkeys(r["scene"] for r in rows):
    ex = [r for r in rows if r["scene"] == sc and r["matrix"] == "exact"]
    for mx in ("exact", "compact"):
        rs = [r for r in rows if r["scene"] == sc and r["matrix"] == mx]
        f = lambda k, fmt: fmt % float(rs[0][k]) if rs[0][k] not in ("", None) else "-"
        gap = "%.3f" % (1e3 * float(rs[0]["seam_gap_max_m"])) if rs[0]["seam_gap_max_m"] else "-"
        print("| %s | %s | %s | %s | %.0f | %s | %.1f | %.2f | %.1f | %s | %s / %s | %s | %.2f / %.2f |" % (
            sc, mx, "/".join(sorted(set(r["status"] for r in rs))), f("fit_end_s", "%.2f"),
            med(rs, "newton_iterations"), f("factor_nnz", "%.0f"), med(rs, "cpu_s"),
            med(rs, "cpu_s") / med(ex, "cpu_s"), med(rs, "time_factor_s"), gap,
            rs[0]["self_intersections"], rs[0]["obstacle_intersections"], f("txy_p95", "%.2f"),
            1e3 * max(float(r["rms_vs_exact_m"]) for r in rs),
            1e3 * max(float(r["max_vs_exact_m"]) for r in rs)))
PY
