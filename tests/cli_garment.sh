#!/usr/bin/env bash
# tests/cli_garment.sh SINEW — garment input refused by `sinew run` (docs/garments.md): a seam
# naming an unknown panel, a vertex not on its panel's boundary, two seams claiming one boundary
# segment, curves whose lengths differ past the ease limit, an arrangement inside or across
# the body: each a file:line:column error naming the seam or the piece, exit 1, nothing
# written.  The run folder of a sewn tube: seams.csv, seams.json, seam_gap_max.  And the
# shipped garments (skirt, tank top) load with nothing crossing and every seam paired, their
# OBJ is what the command on its first line writes, and their seams are the ones it prints.
# A tube run stopped by SIGTERM during its fit (exit 143, summary "interrupted", fit_end_s 0)
# or killed with SIGKILL there, then `sinew run --resume`, writes the logs of a straight run
# bit for bit (but the step_wall_s column) and its fit_steps.  The shipped tank's fit ends at
# its rest whatever the round-off (within 0.1 s of the earliest end, under stiffnesses scaled
# by 1 +- 1e-12).  The shipped grid skirt's fit ends at its equilibrium.
. "$(dirname "$0")/lib.sh"
cp tests/data/tube_pieces.obj tests/data/cylinder.obj "$tmp/"
good=tests/data/tube_seams.yaml

# bad NAME LINE:COL WHAT SED: the tube scene edited by SED is refused at LINE:COL, naming WHAT
bad() {
  local name=$1 where=$2 what=$3
  sed -e "$4" -e "s|^integrator:|output: {dir: $tmp/out_$name}\nintegrator:|" "$good" \
    >"$tmp/$name.yaml"
  if "$sinew" run "$tmp/$name.yaml" --quiet 2>"$tmp/err" >/dev/null; then
    fail "$name: accepted"
  else
    [ $? -eq 1 ] || fail "$name: exit code is not 1"
  fi
  grep -q "$name.yaml:$where: .*$what" "$tmp/err" || fail "$name: message: $(cat "$tmp/err")"
  [ -e "$tmp/out_$name" ] && fail "$name: wrote its output folder"
}
bad panel 18:29 "seam 'left' panel is 'frnt'" 's/a: {panel: front, from: 6/a: {panel: frnt, from: 6/'
bad vertex 18:42 "seam 'left' a from is vertex 11, which is not on the boundary of panel front" \
  's/from: 6, to: 34/from: 11, to: 34/'
bad claim 19:5 "seam 'right' claims the boundary edge (35, 42), which seam 'left'" \
  's/a: {panel: back, from: 41, to: 69}/a: {panel: back, from: 35, to: 63}/'
bad ease 18:5 "seam 'left': its curves are 0.2 m (a) and 0.15 m (b) long" \
  's/b: {panel: back, from: 35, to: 63}/b: {panel: back, from: 35, to: 38}/'
bad inside 15:3 "arrange front: the piece lies inside obstacles\[0\]" \
  's/angle: 270, top: 0.1, radius: 0.11/angle: 270, top: 0.1, radius: 0.07/'
bad across 16:3 "arrange back: the piece crosses obstacles\[0\]" \
  's/back: {cylinder: {angle: 90, top: 0.1, radius: 0.11}}/back: {rigid: {rotate: [90, 0, 0], translate: [0, 0, 0.1]}}/'

# the good scene: the fit closes the seams (summary, seams.csv per seam, seams.json's pairs)
"$sinew" run "$good" --out "$tmp/run" --quiet 2>"$tmp/err" || fail "tube run: $(cat "$tmp/err")"
gap=$(sed -n 's/.*"seam_gap_max": \([0-9.e+-]*\).*/\1/p' "$tmp/run/summary.json")
awk -v g="$gap" 'BEGIN { exit !(g != "" && g + 0 < 1e-3) }' || fail "seam_gap_max = '$gap'"
head -1 "$tmp/run/seams.csv" | grep -q '^time,seam,gap_max,gap_mean,force,length_ratio$' ||
  fail "seams.csv header"
tail -2 "$tmp/run/seams.csv" | cut -d, -f2 | tr '\n' ' ' | grep -q '^left right $' ||
  fail "seams.csv: a line per seam"
/usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))['seams']
assert [x['name'] for x in s] == ['left', 'right'] and s[0]['panels'] == ['front', 'back']
assert s[0]['curves'][0] == list(range(6, 35, 7)) and len(s[0]['pairs']) == 10
" "$tmp/run/seams.json" || fail "seams.json"

# the shipped garments: `sinew check` (no fit, no run) and the generator's output
for g in skirt tank tshirt; do
  scene=scenes/garment_$g.yaml obj=scenes/meshes/garment_$g.obj
  "$sinew" check "$scene" >"$tmp/check_$g" 2>&1 || fail "check $g: $(cat "$tmp/check_$g")"
  grep -q '^crossings   0 face pairs intersect at the start$' "$tmp/check_$g" ||
    fail "$g: crossings at the start"
  nseam=4; [ $g = tshirt ] && nseam=10
  [ "$(grep -c '^seam ' "$tmp/check_$g")" -eq $nseam ] || fail "$g: not $nseam seams"
  cmd=$(head -1 "$obj" | sed 's/^# [^:]*: //')
  # shellcheck disable=SC2086
  /usr/bin/python3 $cmd -o "$tmp/$g.obj" >"$tmp/seams_$g" || fail "$g: $cmd"
  cmp -s "$obj" "$tmp/$g.obj" || fail "$g: $obj is not what '$cmd' writes"
  grep '^  - {name:' "$tmp/seams_$g" | while IFS= read -r line; do
    grep -qxF "$line" "$scene" || echo "$line"
  done >"$tmp/missing_$g"
  [ -s "$tmp/missing_$g" ] && fail "$g: seams the generator prints, not in $scene: $(cat "$tmp/missing_$g")"
done

# a fit interrupted (SIGTERM) or killed (SIGKILL) part-way, resumed: the straight run's logs
# wait_lines FILE N: until FILE has N lines (at most 60 s)
wait_lines() {
  local i
  for i in $(seq 3000); do
    [ -f "$1" ] && [ "$(wc -l <"$1")" -ge "$2" ] && return 0
    sleep 0.02
  done
  return 1
}
nowall() { # energy.csv without its step_wall_s column
  awk -F, -v OFS=, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "step_wall_s") c = i } { $c = ""; print }' "$1"
}
summary() { sed -n "s/.*\"$2\": \([0-9.e+-]*\).*/\1/p" "$1/summary.json"; }
# fit dt 2 ms: about 1550 fit steps, then 0.3 s of dynamics
sed -e 's/^duration: 0$/duration: 0.3\nfit: {dt: 0.002}/' "$good" >"$tmp/fit.yaml"
rf() { "$sinew" run "$tmp/fit.yaml" --frames-every 0.1 --quiet "$@"; }
rf --out "$tmp/straight" 2>"$tmp/err" || fail "fit straight run: $(cat "$tmp/err")"
for sig in TERM KILL; do
  d=$tmp/fit$sig
  "$sinew" run "$tmp/fit.yaml" --frames-every 0.1 --quiet --out "$d" 2>/dev/null &
  pid=$!
  wait_lines "$d/tension.csv.part" 200 || fail "SIG$sig: the fit did not get going"
  kill -$sig $pid
  wait $pid
  code=$?
  if [ $sig = TERM ]; then
    [ $code = 143 ] || fail "SIGTERM in the fit: exit $code, expected 143"
    grep -q '"status": "interrupted"' "$d/summary.json" || fail "SIGTERM in the fit: not interrupted"
    [ "$(summary "$d" fit_end_s)" = 0 ] || fail "SIGTERM came after the fit (fit_end_s $(summary "$d" fit_end_s))"
  fi
  "$sinew" run --resume "$d" 2>"$tmp/err" >/dev/null || fail "SIG$sig in the fit: resume: $(cat "$tmp/err")"
  grep -q "to t = the fit's end + " "$tmp/err" ||
    fail "SIG$sig in the fit: the resume message does not count the duration from the fit's end: $(head -1 "$tmp/err")"
  grep -q '"status": "ok"' "$d/summary.json" || fail "SIG$sig in the fit: resumed run not ok"
  for f in tension contact seams; do
    cmp -s "$tmp/straight/$f.csv" "$d/$f.csv" || fail "SIG$sig in the fit: $f.csv differs from the straight run's"
  done
  cmp -s <(nowall "$tmp/straight/energy.csv") <(nowall "$d/energy.csv") ||
    fail "SIG$sig in the fit: energy.csv differs from the straight run's"
  [ "$(summary "$d" fit_steps)" = "$(summary "$tmp/straight" fit_steps)" ] ||
    fail "SIG$sig in the fit: fit_steps $(summary "$d" fit_steps), the straight run's $(summary "$tmp/straight" fit_steps)"
done

# The fit's end is the garment's rest, not Newton's error: the shipped tank, as shipped and with
# every stiffness scaled by 1 +- 1e-12 (round-off only), ends its fit within 0.2 s of the
# earliest end possible (2 s, twice the ramp; 2.07 to 2.13 s with the compact bending matrix).  With the fit's Newton tolerance 1e-2 m/s after
# the ramps (ten times the speed threshold) two of the three ended at 3.56 and 3.59 s.
for sc in 1 1.000000000001 0.999999999999; do
  d=$tmp/tank_$sc
  "$sinew" run scenes/garment_tank.yaml --out "$d" --duration 0 --no-frames --quiet \
    --stiffness-scale $sc 2>"$tmp/err" >/dev/null || fail "tank x $sc: $(cat "$tmp/err")"
  end=$(summary "$d" fit_end_s)
  awk -v e="$end" 'BEGIN { exit !(e >= 2 && e <= 2.2) }' ||
    fail "tank x $sc: the fit ended at $end s, expected 2 to 2.2 s"
done

# The shipped grid skirt's fit ends at rest: the static solve started from its end (with the
# dynamic fit's compact bending matrix) moves it by under 0.1 mm RMS (0.02 mm measured; a fit
# stopped at the ramps' end, `fit: {speed: 1}`, lies 1.7 mm from that equilibrium, and
# `fit: {mode: settle}` 1.07 mm), every seam closed to 1 mm, nothing crossing.
d=$tmp/skirt
"$sinew" run scenes/garment_skirt.yaml --out "$d" --duration 0 --no-frames --quiet \
  --method static --bending-matrix compact --positions-every 1e-6 2>"$tmp/err" >/dev/null ||
  fail "skirt, fit and static solve: $(cat "$tmp/err")"
awk -v g="$(summary "$d" seam_gap_max)" -v x="$(summary "$d" self_intersections)" \
  'BEGIN { exit !(g < 1e-3 && x == 0) }' ||
  fail "skirt: seam gap $(summary "$d" seam_gap_max) m, $(summary "$d" self_intersections) crossings"
# positions.bin's last two records: the fit's end and the static solve's answer, at one time
moved=$(/usr/bin/python3 -B -c '
import sys
import numpy as np
sys.path.insert(0, "tools")
from positions_diff import records
t, x = records(sys.argv[1])
assert t[-2] == t[-1], "the last two records are at %g and %g s" % (t[-2], t[-1])
print("%.3e" % np.sqrt(np.mean(np.sum((x[-1] - x[-2]) ** 2, axis=1))))' "$d/positions.bin") || fail "skirt: positions.bin unread"
awk -v e="$moved" 'BEGIN { exit !(e < 1e-4) }' ||
  fail "skirt: the static solve moved the fitted skirt by $moved m RMS, expected under 1e-4"

[ $fails -eq 0 ] && echo "cli_garment: all passed"
exit $((fails > 0))
