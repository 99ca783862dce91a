#!/usr/bin/env bash
# tests/bench.sh SINEW — `sinew bench` end to end on a 36-vertex cloth (seconds): the CSV has every
# method x setting, errors fall with dt for the convergent methods at their order, a blown-up
# run is recorded as failed, a crashed one as crashed, --emit-jobs + --merge give the same
# errors as local runs, the stability and scaling modes, the charts are valid PNG files, and a
# fixed-step reference (BDF2) on a contact scene, where CVODE and IDA fail.
. "$(dirname "$0")/lib.sh"
scene=tests/data/bench_tiny.yaml
py=/usr/bin/python3

# The value of column NAME in the rows of CSV FILE whose first columns match PATTERN (awk regex
# on the whole line), one per line.
col() {
  awk -F, -v name="$2" -v pat="$3" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
    $0 ~ pat { print $c }' "$1"
}

# ---------------------------------------------------------------- work precision
wp=$tmp/wp
"$sinew" bench $scene --out "$wp" --methods backward-euler,bdf2,implicit-midpoint,symplectic-euler,cvode \
  --dts 0.02,0.01,0.005,0.0025 --rtols 1e-3,1e-5 --repeat 2 --max-halvings 0 >"$tmp/wp.out" 2>"$tmp/wp.err" ||
  fail "bench exit $?: $(tail -5 "$tmp/wp.err")"
csv=$wp/work_precision.csv
[ -f "$csv" ] || fail "no work_precision.csv"
# 4 fixed-step methods x 4 dts + cvode x 2 rtols, one row each (repeats merged)
[ "$(($(wc -l <"$csv") - 1))" -eq 18 ] || fail "work_precision.csv has $(($(wc -l <"$csv") - 1)) rows, expected 18"
for m in backward-euler bdf2 implicit-midpoint symplectic-euler; do
  for dt in 0.02 0.01 0.005 0.0025; do
    [ "$(col "$csv" method "^$m,fixed,dt,$dt,")" = "$m" ] || fail "no row $m dt $dt"
  done
done
for r in 0.001 1e-05; do
  [ "$(col "$csv" method "^cvode,adaptive,rtol,$r,")" = cvode ] || fail "no row cvode rtol $r"
done
grep -q 'confirmed' "$tmp/wp.out" || fail "no reference confirmation line"
[ "$(col "$wp/reference.csv" confirmed .)" = yes ] || fail "reference not confirmed: $(cat "$wp/reference.csv")"
[ "$(col "$csv" repeats '^backward-euler,fixed,dt,0.02,')" = 2 ] || fail "repeats of backward-euler"

# Errors fall with dt at the method's order: slope of log(error) over log(dt) between the two
# smallest steps within [order - 0.35, order + 0.6] (BDF2 and midpoint 2, backward Euler 1).
order_ok() { # method order
  local e1 e2
  e1=$(col "$csv" pos_err_max "^$1,fixed,dt,0.005,")
  e2=$(col "$csv" pos_err_max "^$1,fixed,dt,0.0025,")
  $py -c "import math,sys; s = math.log($e1 / $e2, 2); print('$1 order', s); sys.exit(not ($2 - 0.35 < s < $2 + 0.6))" ||
    fail "$1: error does not fall at order $2 ($e1 -> $e2)"
  for dt in 0.02 0.01 0.005 0.0025; do
    [ "$(col "$csv" status "^$1,fixed,dt,$dt,")" = ok ] || fail "$1 dt $dt not ok"
  done
  local prev=1e300 e
  for dt in 0.02 0.01 0.005 0.0025; do
    e=$(col "$csv" txy_max_l2 "^$1,fixed,dt,$dt,")
    $py -c "import sys; sys.exit(not ($e < $prev))" || fail "$1: tension XY error does not fall at dt $dt ($prev -> $e)"
    prev=$e
  done
}
order_ok backward-euler 1
order_ok bdf2 2
order_ok implicit-midpoint 2
# The observed order of orders.csv (the least-squares slope over the converged range) and the
# printed table: BDF2 and implicit midpoint 2, backward Euler 1.
order_csv() { # method lo hi
  local o
  o=$(col "$wp/orders.csv" order "^$1,dt,")
  $py -c "import sys; sys.exit(not ($2 <= float('${o:-nan}') <= $3))" || fail "$1: observed order '$o' not in [$2, $3]"
  grep -q "^  $1 *[0-9.]* *over dt" "$tmp/wp.out" || fail "$1: no observed order printed"
}
order_csv backward-euler 0.8 1.2
order_csv bdf2 1.75 2.3
order_csv implicit-midpoint 1.75 2.3
[ -z "$(col "$wp/orders.csv" order '^symplectic-euler,')" ] || fail "an order from one ok run"
# On a linear mass-spring chain the observed orders are the methods' own: BDF2 and implicit
# midpoint 2, backward Euler 1 (within 0.1).
os=$tmp/os
"$sinew" bench tests/data/order_springs.yaml --out "$os" --methods backward-euler,bdf2,implicit-midpoint \
  --repeat 1 --no-charts >"$tmp/os.out" 2>&1 || fail "bench order_springs: $(tail -3 "$tmp/os.out")"
for mo in backward-euler:0.9:1.1 bdf2:1.9:2.1 implicit-midpoint:1.9:2.1; do
  IFS=: read -r m lo hi <<<"$mo"
  o=$(col "$os/orders.csv" order "^$m,dt,")
  $py -c "import sys; sys.exit(not ($lo <= float('${o:-nan}') <= $hi))" || fail "order_springs: $m observed order '$o' not in [$lo, $hi]"
  [ "$(col "$os/orders.csv" range_points "^$m,dt,")" = 4 ] || fail "order_springs: $m: the converged range is not all 4 steps"
done
# Against a reference worse than the runs (CVODE at rtol 1e-3, confirmed by itself) the errors
# do not fall with dt: no order, and a warning naming the steps.
"$sinew" bench tests/data/order_springs.yaml --out "$tmp/os2" --methods bdf2 --dts 0.005,0.0025,0.00125 \
  --reference cvode:q2 --confirm cvode:q2 --reference-rtol 1e-3 --repeat 1 --no-charts >"$tmp/os2.out" 2>&1
[ -z "$(col "$tmp/os2/orders.csv" order '^bdf2,')" ] || fail "an order where errors do not fall"
grep -q 'warning: bdf2: the error does not fall with dt between dt 0.00125 and 0.0025' "$tmp/os2.out" ||
  fail "no warning when errors do not fall: $(grep -i warn "$tmp/os2.out")"
# ... with the hint to tighten Newton (the runs used the scene's tolerance); none when they did not
grep -q "(its runs stop Newton at the scene's tolerance, whose error can exceed a fine step's: --newton-tol 1e-06" "$tmp/os2.out" ||
  fail "no Newton tolerance hint under the warning: $(grep -A1 warning "$tmp/os2.out")"
sed -i 's/^newton_tol = .*/newton_tol = 1e-06/' "$tmp/os2/bench_work_precision.cfg"
"$sinew" bench --merge "$tmp/os2" --no-charts >"$tmp/os2m.out" 2>&1
grep -q 'warning: bdf2: the error does not fall' "$tmp/os2m.out" && grep -q "its runs stop Newton" "$tmp/os2m.out" &&
  fail "the Newton tolerance hint for runs at --newton-tol 1e-6"
# A run is failed when its tension error exceeds --tension-diverged (here, tiny: every run).
td=$tmp/td
cp -r "$wp" "$td"
sed -i 's/^tension_diverged = .*/tension_diverged = 1e-12/' "$td/bench_work_precision.cfg"
"$sinew" bench --merge "$td" --no-charts >"$tmp/td.out" 2>&1
[ "$(col "$td/work_precision.csv" status '^bdf2,fixed,dt,0.01,')" = failed ] || fail "a tension error above the bound is not failed"
col "$td/work_precision.csv" how '^bdf2,fixed,dt,0.01,' | grep -q 'tension XY max error' || fail "the tension failure does not say so"
grep -q 'tension error (XY max, XY mean, tendons) exceeds 1e-12' "$tmp/td.out" || fail "the thresholds are not stated"
e3=$(col "$csv" pos_err_max '^cvode,adaptive,rtol,0.001,')
e5=$(col "$csv" pos_err_max '^cvode,adaptive,rtol,1e-05,')
$py -c "import sys; sys.exit(not ($e5 < $e3))" || fail "cvode: error does not fall with rtol ($e3 -> $e5)"

# Symplectic Euler blows up at dt = 0.02 (above its stability limit): failed, not fatal.
[ "$(col "$csv" status '^symplectic-euler,fixed,dt,0.02,')" = failed ] || fail "symplectic-euler dt 0.02 not failed"
col "$csv" how '^symplectic-euler,fixed,dt,0.02,' | grep -q 'blew up' || fail "symplectic-euler failure is not a blow-up"
[ -z "$(col "$csv" pos_err_max '^symplectic-euler,fixed,dt,0.02,')" ] || fail "a failed run has an error value"

# Charts: valid PNG files (signature and IHDR; matplotlib reads them back).
for png in work_precision tension_series; do
  f=$wp/$png.png
  [ "$(head -c 8 "$f" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$png.png is not a PNG"
  [ "$(head -c 16 "$f" | tail -c 4)" = IHDR ] || fail "$png.png has no IHDR"
  $py -c "import matplotlib.image as m, sys; a = m.imread('$f'); sys.exit(not (a.shape[0] > 100 and a.shape[1] > 100))" ||
    fail "$png.png does not read back"
done

# CPU time beside wall time: in every row (a failed run's: to its failure), above 0 and at most
# the wall time x the cores (runs and their repeats, the reference; summary.json of each run).
cpu_ok() { # CSV [COLUMN SUFFIX ...]: every row's cpu_s > 0 and <= wall_s x cores
  $py - "$@" "$(nproc)" <<'PY' || fail "CPU time in $1: see above"
import csv, sys
path, cores = sys.argv[1], int(sys.argv[-1])
rows = list(csv.DictReader(open(path)))
bad = [r for r in rows for s in ("", "_min", "_max") if f"wall{s}_s" in r and r[f"wall{s}_s"] and
       not (r.get(f"cpu{s}_s") and 0 < float(r[f"cpu{s}_s"]) <= float(r[f"wall{s}_s"]) * cores)]
print("\n".join(f"{path}: cpu {r.get('cpu_s')} wall {r['wall_s']}" for r in bad))
sys.exit(not rows or bool(bad) or any(not r.get("cpu_s") for r in rows))
PY
}
cpu_ok "$csv"
cpu_ok "$wp/reference.csv"
for f in "$wp"/runs/*/summary.json; do
  $py -c "import json, sys; s = json.load(open('$f')); sys.exit(not (0 < s['cpu_time_s'] <= s['wall_time_s'] * $(nproc)))" ||
    fail "$f: cpu_time_s $(grep -o '"cpu_time_s": [^,]*' "$f"), wall $(grep -o '"wall_time_s": [^,]*' "$f")"
done
# --time: the table's first time column and the setting kept for --merge and the charts
grep -qx 'time = cpu' "$wp/bench_work_precision.cfg" || fail "the default --time is not cpu"
grep -q '^  method .* CPU  *wall$' "$tmp/wp.out" || fail "the table does not lead with CPU time: $(grep '^  method' "$tmp/wp.out")"
"$sinew" bench --merge "$wp" --time wall --no-charts >"$tmp/wall.out" 2>&1
grep -q '^  method .* wall  *CPU$' "$tmp/wall.out" || fail "--merge --time wall: $(grep '^  method' "$tmp/wall.out")"
"$sinew" bench --merge "$wp" --time gpu >/dev/null 2>&1 && fail "--time gpu accepted"
$py tools/bench_charts.py "$wp" --time wall >/dev/null || fail "bench_charts.py --time wall"

# ---------------------------------------------------------- a crash is recorded
# A run that died by a signal leaves no final summary: --merge records it as crashed.
id=wp_backward-euler_dt0.01_r1
echo "signal 11" >"$wp/logs/$id.exit"
rm -f "$wp/runs/$id/summary.json"
"$sinew" bench --merge "$wp" --no-charts >/dev/null 2>&1
[ "$(col "$csv" status '^backward-euler,fixed,dt,0.01,')" = crashed ] || fail "a killed run is not recorded as crashed"
col "$csv" how '^backward-euler,fixed,dt,0.01,' | grep -q 'signal 11' || fail "crash reason lacks the signal"

# A damaged run folder (garbage, truncation, empty files) is read without crashing: --merge
# exits normally and the damaged run is crashed or has no errors, never a made-up number.
id=wp_bdf2_dt0.01_r1
head -c 3000 /dev/urandom >"$wp/runs/$id/positions.bin"
printf '{\n  "status": "ok",\n  "message": "\\u12' >"$wp/runs/$id/summary.json"
printf 'time,txy_max,txy_mean\n0,1e999,x\n,,,,\n0.02' >"$wp/runs/$id/tension.csv"
: >"$wp/runs/$id/energy.csv"
id2=wp_bdf2_dt0.005_r1
truncate -s 20 "$wp/runs/$id2/positions.bin"
head -c 500 /dev/urandom >"$wp/runs/$id2/tension.csv"
"$sinew" bench --merge "$wp" --no-charts >"$tmp/dmg.out" 2>&1
rc=$?
[ $rc -le 2 ] || fail "--merge of damaged runs ended with $rc: $(tail -3 "$tmp/dmg.out")"
[ -z "$(col "$csv" pos_err_max '^bdf2,fixed,dt,0.01,')" ] || fail "random positions.bin gave an error value"
[ -z "$(col "$csv" pos_err_max '^bdf2,fixed,dt,0.005,')" ] || fail "truncated positions.bin gave an error value"

# --------------------------------------------------------- job list and merge
em=$tmp/em
"$sinew" bench $scene --out "$em" --methods backward-euler,cvode --dts 0.02,0.01 --rtols 1e-4 \
  --repeat 1 --emit-jobs "$tmp/jobs.txt" >"$tmp/em.out" 2>&1 || fail "--emit-jobs: $(cat "$tmp/em.out")"
# timings are the median of 3 repeats by default: 2 + 3 x 3 runs
"$sinew" bench $scene --out "$tmp/em3" --methods backward-euler,cvode --dts 0.02,0.01 --rtols 1e-4 \
  --emit-jobs "$tmp/jobs3.txt" >/dev/null 2>&1 || fail "--emit-jobs (default repeat)"
[ "$(wc -l <"$tmp/jobs3.txt")" -eq 11 ] || fail "default --repeat: $(wc -l <"$tmp/jobs3.txt") jobs, expected 11"
[ "$(wc -l <"$tmp/jobs.txt")" -eq 5 ] || fail "jobs.txt has $(wc -l <"$tmp/jobs.txt") lines, expected 5"
grep -q 'SBATCH --array=1-5' "$em/slurm.sh" || fail "slurm.sh array size"
[ -f "$em/work_precision.csv" ] && fail "--emit-jobs ran the jobs"
bash "$tmp/jobs.txt" || fail "the job list does not run"
"$sinew" bench --merge "$em" --no-charts >"$tmp/merge.out" 2>&1 || fail "--merge: $(cat "$tmp/merge.out")"
a=$(col "$em/work_precision.csv" pos_err_max '^backward-euler,fixed,dt,0.02,')
b=$(col "$csv" pos_err_max '^backward-euler,fixed,dt,0.02,')
[ -n "$a" ] && [ "$a" = "$b" ] || fail "merged job list error $a != local run error $b"
cpu_ok "$em/work_precision.csv"

# --------------------------------------------------------------- stability
st=$tmp/st
"$sinew" bench $scene --stability --out "$st" --methods backward-euler,symplectic-euler \
  --dts 0.02,0.005,0.00125 --scales 1,4 >"$tmp/st.out" 2>&1 || fail "--stability: $(tail -3 "$tmp/st.out")"
s=$st/stability.csv
[ "$(($(wc -l <"$s") - 1))" -eq 12 ] || fail "stability.csv has $(($(wc -l <"$s") - 1)) rows, expected 12"
[ "$(col "$s" status '^symplectic-euler,1,0.02,')" = failed ] || fail "symplectic-euler dt 0.02 not failed in the map"
[ "$(col "$s" status '^symplectic-euler,1,0.00125,')" = stable ] || fail "symplectic-euler dt 0.00125 not stable"
[ "$(col "$s" status '^backward-euler,1,0.02,')" = over-damped ] || fail "backward-euler dt 0.02 not over-damped ($(col "$s" energy_loss '^backward-euler,1,0.02,'))"
[ "$(col "$st/stability_limits.csv" largest_stable_dt '^symplectic-euler,1,')" = 0.00125 ] ||
  fail "largest stable dt of symplectic-euler"
head -c 8 "$st/stability.png" | od -An -tx1 | tr -d ' \n' | grep -q 89504e470d0a1a0a || fail "stability.png"
grep -q 'backward-euler *x1 *[0-9.e-]* *(none failed)' "$tmp/st.out" || fail "no 'none failed': $(grep backward "$tmp/st.out")"
# dt = 0.1 s on a 0.2 s run is 2 steps: short (too few steps to tell), not stable.
"$sinew" bench $scene --stability --out "$tmp/sh" --methods backward-euler --dts 0.1 --scales 1 \
  --no-charts >"$tmp/sh.out" 2>&1 || fail "--stability (short): $(tail -3 "$tmp/sh.out")"
[ "$(col "$tmp/sh/stability.csv" status '^backward-euler,1,0.1,')" = short ] || fail "2 steps are not short"
grep -q 'none stable' "$tmp/sh.out" || fail "no 'none stable'"

# ----------------------------------------------------------------- scaling
sc=$tmp/sc
"$sinew" bench $scene --scaling --out "$sc" --methods backward-euler --sizes 6,12,24 --steps 3 \
  >"$tmp/sc.out" 2>&1 || fail "--scaling: $(tail -3 "$tmp/sc.out")"
for n in 6 12 24; do
  row=$(awk -F, -v n=$n '$1 == "backward-euler" && $2 == n' "$sc/scaling.csv")
  [ "$(cut -d, -f3 <<<"$row")" = $((n * n)) ] || fail "scaling: grid $n has not $((n * n)) vertices: $row"
  $py -c "import sys; r = '$row'.split(','); sys.exit(not (float(r[5]) > 0 and 0 < float(r[9]) < 1 and float(r[10]) > 0))" ||
    fail "scaling row $row: step time, factor share or memory out of range"
done
head -c 8 "$sc/scaling.png" | od -An -tx1 | tr -d ' \n' | grep -q 89504e470d0a1a0a || fail "scaling.png"
cpu_ok "$sc/scaling.csv"

# ------------------------------------------------------ adaptive max orders
# --max-orders 2,5: each adaptive method once per order, its own line (cvode:q2, cvode:q5), the
# order passed to its runs; NAME:qN in --methods is the same; the reference is cvode:q5.
mo=$tmp/mo
"$sinew" bench $scene --out "$mo" --methods cvode,ida:q1,bdf2 --max-orders 2,5 --dts 0.02 \
  --rtols 1e-4 --no-charts >"$tmp/mo.out" 2>&1 || fail "--max-orders: $(tail -3 "$tmp/mo.out")"
[ "$(cut -d, -f1 "$mo/work_precision.csv" | tail -n +2 | tr '\n' ' ')" = "cvode:q2 cvode:q5 ida:q1 bdf2 " ] ||
  fail "--max-orders rows: $(cut -d, -f1 "$mo/work_precision.csv" | tr '\n' ' ')"
for q in 2 5; do
  grep -q "\"max_order\": $q," "$mo/runs/wp_cvode_q${q}_rtol0.0001_r1/summary.json" ||
    fail "cvode:q$q did not run at max_order $q"
done
grep -q '"max_order": 1,' "$mo/runs/wp_ida_q1_rtol0.0001_r1/summary.json" || fail "ida:q1 order"
grep -q '"max_order": 5,' "$mo/runs/wp_reference/summary.json" || fail "the reference is not at order 5"
[ "$(col "$mo/reference.csv" method .)" = cvode:q5 ] || fail "reference method $(col "$mo/reference.csv" method .)"
s2=$(col "$mo/work_precision.csv" steps '^cvode:q2,')
s5=$(col "$mo/work_precision.csv" steps '^cvode:q5,')
[ "$s2" -gt 0 ] && [ "$s5" -gt 0 ] && [ "$s2" -ne "$s5" ] || fail "cvode:q2 and q5 took $s2 and $s5 steps"
"$sinew" bench $scene --methods cvode --max-orders 6 >/dev/null 2>&1 && fail "--max-orders 6 accepted"
"$sinew" bench $scene --methods bdf2:q2 >/dev/null 2>&1 && fail "a fixed-step method with an order accepted"
"$sinew" bench $scene --methods cvode:q0 >/dev/null 2>&1 && fail "cvode:q0 accepted"

# ------------------------------------------- a fixed-step reference on a contact scene
# CVODE and IDA fail at the first contact (docs/contact.md): the reference is BDF2 at
# --reference-dt (default the finest dt / 8 = 1.25 ms), confirmed by BDF2 at half that step
# (--confirm-dt's default); they agree to ~2.4e-4 of the size (contact is not smooth), hence
# --confirm-tol 1e-3 here.
ct=$tmp/ct
"$sinew" bench tests/data/bench_contact.yaml --out "$ct" --methods backward-euler,bdf2,baraff-witkin \
  --dts 0.02,0.01 --reference bdf2 --confirm bdf2 --confirm-tol 1e-3 --no-charts >"$tmp/ct.out" 2>&1 ||
  fail "contact bench: $(tail -3 "$tmp/ct.out")"
for f in reference.csv work_precision.csv plan_work_precision.csv; do
  [ -f "$ct/$f" ] || fail "contact bench: no $f"
done
r=$ct/reference.csv
[ "$(col "$r" confirmed .)" = yes ] || fail "contact reference not confirmed: $(cat "$r")"
[ "$(col "$r" dt .),$(col "$r" confirm_dt .),$(col "$r" rtol .)" = "0.00125,0.000625," ] ||
  fail "contact reference dt, confirm_dt, rtol: $(cat "$r")"
grep -q 'reference: bdf2 dt 0.00125 s; bdf2 dt 0.000625 s agrees' "$tmp/ct.out" ||
  fail "the summary does not give the reference's dt: $(grep reference: "$tmp/ct.out")"
grep -q '"dt": 0.00125,' "$ct/runs/wp_reference/summary.json" || fail "the reference did not run at 1.25 ms"
c=$ct/work_precision.csv
agree=$(col "$r" pos_err .)
for m in bdf2 baraff-witkin; do
  e1=$(col "$c" pos_err_max "^$m,fixed,dt,0.02,")
  e2=$(col "$c" pos_err_max "^$m,fixed,dt,0.01,")
  t2=$(col "$c" txy_max_l2 "^$m,fixed,dt,0.01,")
  # errors fall with dt and stay above the reference's own (the confirm's agreement)
  $py -c "import sys; sys.exit(not ($agree < $e2 < $e1 and $t2 > 0))" ||
    fail "$m on contact: errors $e1 -> $e2 (reference agreement $agree, tension $t2)"
done
# The reference and confirm runs (and only they) get a strict Newton tolerance and halvings.
"$sinew" bench tests/data/bench_contact.yaml --out "$tmp/cj" --methods bdf2 --dts 0.02,0.01 \
  --reference bdf2 --confirm bdf2 --emit-jobs "$tmp/cj.txt" >/dev/null 2>&1 || fail "contact --emit-jobs"
[ "$(grep -c -- "--max-halvings' '4' '--newton-tol' '1e-05'" "$tmp/cj.txt")" = 2 ] ||
  fail "reference and confirm lines lack --newton-tol 1e-05 / --max-halvings 4: $(head -2 "$tmp/cj.txt")"
[ "$(grep -c -- "--newton-tol" "$tmp/cj.txt")" = 2 ] || fail "a sweep run got the reference's --newton-tol"
# --newton-tol: the sweep's fixed-step runs at it, the reference and confirm at theirs
"$sinew" bench tests/data/bench_contact.yaml --out "$tmp/cn" --methods bdf2 --dts 0.02,0.01 \
  --reference bdf2 --confirm bdf2 --repeat 1 --newton-tol 1e-7 --emit-jobs "$tmp/cn.txt" >/dev/null 2>&1 || fail "--newton-tol --emit-jobs"
[ "$(grep -c -- "'--newton-tol' '1e-07'" "$tmp/cn.txt")" = 2 ] && [ "$(grep -c -- "'--newton-tol' '1e-05'" "$tmp/cn.txt")" = 2 ] ||
  fail "--newton-tol 1e-7: $(cat "$tmp/cn.txt")"
grep -qx 'newton_tol = 1e-07' "$tmp/cn/bench_work_precision.cfg" || fail "newton_tol not in the settings file"
# A reference whose step is halved (backward Euler at 20 ms: Newton does not converge at the
# contact, the step is halved): its halved steps are counted, the samples still land on its
# grid, every error of the run is measured.
"$sinew" bench tests/data/bench_contact.yaml --out "$tmp/ch" --methods bdf2 --dts 0.02 \
  --reference backward-euler --reference-dt 0.02 --confirm bdf2 --confirm-dt 0.005 --confirm-tol 0.05 \
  --no-charts >"$tmp/ch.out" 2>&1 || fail "halved reference: $(tail -3 "$tmp/ch.out")"
[ "$(col "$tmp/ch/reference.csv" retries .)" -ge 1 ] || fail "the reference was not halved: $(cat "$tmp/ch/reference.csv")"
[ -n "$(col "$tmp/ch/work_precision.csv" pos_err_final '^bdf2,')" ] || fail "halved reference: no final error"
[ "$(col "$tmp/ch/reference.csv" confirmed .)" = yes ] || fail "halved reference not confirmed"
# bad input: a step that does not divide the finest dt, a step for an adaptive reference, static
"$sinew" bench tests/data/bench_contact.yaml --out "$tmp/cb" --dts 0.02,0.01 --reference bdf2 \
  --reference-dt 0.003 >/dev/null 2>"$tmp/cb.err" && fail "--reference-dt 0.003 accepted"
grep -q 'does not divide the finest dt' "$tmp/cb.err" || fail "message for --reference-dt: $(cat "$tmp/cb.err")"
"$sinew" bench $scene --out "$tmp/cb" --reference-dt 0.001 >/dev/null 2>"$tmp/cb.err" &&
  fail "--reference-dt with an adaptive reference accepted"
grep -q 'is for a fixed-step method' "$tmp/cb.err" || fail "message for --reference-dt with cvode"
"$sinew" bench $scene --reference static >/dev/null 2>&1 && fail "--reference static accepted"

# ------------------------------------------------------------- bad input
"$sinew" bench $scene --out "$tmp/bad" --dts 0.03,0.02 >/dev/null 2>"$tmp/bad.err" && fail "non-dividing dts accepted"
grep -q 'does not divide' "$tmp/bad.err" || fail "message for dts that do not divide the sample interval"
"$sinew" bench $scene --methods nope >/dev/null 2>&1 && fail "unknown method accepted"
"$sinew" bench --merge "$tmp" >/dev/null 2>&1 && fail "--merge of a folder without a bench"

[ $fails -eq 0 ] && echo "bench: all checks passed"
exit $((fails > 0))
