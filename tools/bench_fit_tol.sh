#!/usr/bin/env bash
# tools/bench_fit_tol.sh OLD_SINEW NEW_SINEW — two builds' fits of the shipped garments with
# seams (scenes/garment_{tank,tshirt,skirt,skirt_dxf,tshirt_dxf}.yaml, GARMENTS= to choose),
# each as shipped and with every stiffness scaled by 1 + 1e-12 and 1 - 1e-12
# (`--stiffness-scale`, SCALES= to choose): a change of round-off only, which moves a fit's end
# where it is decided by noise.  The runs are interleaved (old, new per garment and scale), the
# fit alone (`--duration 0`, one BLAS thread); CPU time is the process's user time.  Writes
# docs/bench/fit/fit_tol.csv (OUT= another folder) and prints per garment and build the fit's
# end, Newton iterations and CPU time over the scales (docs/performance.md, "The fit's end").
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: bench_fit_tol.sh OLD_SINEW NEW_SINEW}
new=${2:?usage: bench_fit_tol.sh OLD_SINEW NEW_SINEW}
out=${OUT:-docs/bench/fit}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
csv=$out/fit_tol.csv
echo "garment,scale,build,status,cpu_s,fit_end_s,fit_steps,newton_iterations,seam_gap_max_m,self_intersections,obstacle_intersections,txy_p95" >"$csv"
for g in ${GARMENTS:-tank tshirt skirt skirt_dxf tshirt_dxf}; do
  for sc in ${SCALES:-1 1.000000000001 0.999999999999}; do
    for b in old new; do
      bin=$old
      [ "$b" = new ] && bin=$new
      d=$work/$g-$sc-$b
      /usr/bin/time -f %U -o "$d.cpu" "$bin" run "scenes/garment_$g.yaml" --out "$d" \
        --duration 0 --no-frames --threads 1 --quiet --stiffness-scale "$sc" >/dev/null 2>&1 || true
      /usr/bin/python3 - "$d" "$g" "$sc" "$b" >>"$csv" <<'PY'
import csv, json, sys
d, g, sc, b = sys.argv[1:5]
s = json.load(open(d + "/summary.json"))
cpu = float(open(d + ".cpu").read().split()[-1])
t = list(csv.DictReader(open(d + "/tension.csv")))[-1]
print(",".join(str(v) for v in (g, sc, b, s["status"], cpu, s["fit_end_s"], s["fit_steps"],
      s["newton_iterations"], s["seam_gap_max"], s["self_intersections"],
      s["obstacle_intersections"], t["txy_p95"])))
PY
      rm -rf "$d"
    done
  done
done
/usr/bin/python3 - "$csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| garment | build | status | fit ends at, s | Newton iterations | CPU, s | seam gap max, mm | tension XY p95, N/m |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
for g in dict.fromkeys(r["garment"] for r in rows):
    for b in ("old", "new"):
        rs = [r for r in rows if r["garment"] == g and r["build"] == b]
        col = lambda k, f: " / ".join(f % float(r[k]) for r in rs)
        st = "/".join(sorted(set(r["status"] for r in rs)))
        print("| %s | %s | %s | %s | %s | %s | %s | %s |" % (g, b, st, col("fit_end_s", "%.2f"),
              col("newton_iterations", "%.0f"), col("cpu_s", "%.1f"),
              " / ".join("%.3f" % (1e3 * float(r["seam_gap_max_m"])) for r in rs),
              col("txy_p95", "%.2f")))
PY
