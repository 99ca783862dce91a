#!/usr/bin/env bash
# tools/fabric_garments.sh [SINEW [OUT]] — the shipped tank top and T-shirt
# (scenes/garment_tank.yaml, scenes/garment_tshirt.yaml) fitted and run as shipped in their
# assumed woven (bw98) and with their material replaced by three measured fabrics
# (`fabric: {preset: NAME}`, docs/fabrics.md): the T-shirt jersey gray-interlock, the denim
# 11oz-black-denim and the stiff woven royal-target (PRESETS= to choose).  One run at a time,
# one BLAS thread.  Writes OUT/fabric_garments.csv (default docs/bench/fabric) with status, fit
# end, Newton iterations, CPU, seam gap, intersections and tension XY percentiles of the last
# frame per run, its table as fabric_garments.md, and per garment the presets' tension maps side
# by side at one colour scale (`sinew render --compare`) as docs/images/fabric_GARMENT.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/sinew}
out=${2:-docs/bench/fabric}
presets=${PRESETS:-gray-interlock 11oz-black-denim royal-target}
if [ -n "${KEEP:-}" ]; then  # KEEP=DIR keeps the run folders there
  work=$KEEP && mkdir -p "$work"
else
  work=$(mktemp -d) && trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$out"
csv=$out/fabric_garments.csv
echo "garment,material,status,cpu_s,fit_end_s,steps,newton_iterations,seam_gap_max_m,seam_stiffness,self_intersections,obstacle_intersections,txy_mean,txy_p95,txy_max" >"$csv"
for g in tank tshirt; do
  runs=()
  for p in shipped $presets; do
    sc=$work/$g-$p.yaml
    sed -e "s| meshes/| $PWD/scenes/meshes/|g" "scenes/garment_$g.yaml" >"$sc"
    if [ "$p" != shipped ]; then
      awk -v p="$p" '/^  density:|^  bending:/ {next}
        /^  membrane:/ {print "  fabric: {preset: " p "}"; next} {print}' "$sc" >"$sc.tmp"
      mv "$sc.tmp" "$sc"
    fi
    d=$work/$g-$p
    "$bin" run "$sc" --out "$d" --threads 1 --quiet >/dev/null 2>"$d.err" || true
    /usr/bin/python3 - "$d" "$g" "$p" >>"$csv" <<'PY'
import csv, json, sys
import numpy as np
d, g, p = sys.argv[1:4]
s = json.load(open(d + "/summary.json"))
rows = list(csv.DictReader(open(d + "/tension.csv")))
t = rows[-1]
mat = "bw98 (shipped)" if p == "shipped" else p
status = s["status"] if s["status"] == "ok" else "%s: %s" % (s["status"], s.get("message", ""))
print(",".join(str(v) for v in (g, mat, '"%s"' % status.replace('"', "'"), s["cpu_time_s"],
      s["fit_end_s"], s["steps"], s["newton_iterations"], s["seam_gap_max"],
      s.get("seam_stiffness", ""), s["self_intersections"], s["obstacle_intersections"],
      t["txy_mean"], t["txy_p95"], t["txy_max"])))
PY
    [ "$p" = shipped ] || runs+=("$d")
  done
  "$bin" render "${runs[@]}" --compare \
    "docs/images/fabric_$g.png" --titles "$(echo $presets | tr ' ' ,)" --smooth --quiet
done
/usr/bin/python3 - "$csv" >"$out/fabric_garments.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| garment | material | status | fit ends at, s | steps | Newton iterations | CPU, s | seam gap max, mm | seam stiffness, N/m² | self / obstacle intersections | tension XY mean / p95 / max, N/m |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for r in rows:
    print("| %s | %s | %s | %.2f | %s | %s | %.1f | %.3f | %.3g | %s / %s | %s |" % (
        r["garment"], r["material"], r["status"], float(r["fit_end_s"]), r["steps"],
        r["newton_iterations"], float(r["cpu_s"]), 1e3 * float(r["seam_gap_max_m"]),
        float(r["seam_stiffness"] or 0), r["self_intersections"], r["obstacle_intersections"],
        " / ".join("%.1f" % float(r[k]) for k in ("txy_mean", "txy_p95", "txy_max"))))
PY
cat "$out/fabric_garments.md"
