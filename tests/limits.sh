#!/usr/bin/env bash
# tests/limits.sh SINEW — hostile inputs that must not hang, exhaust memory or destroy a file
# (docs/reliability.md, "Limits"): sampling intervals far below the step, oversized and endless
# input files, counts beyond the memory budget, `inverse --out` naming an input, damaged run
# folders in `bench --merge`, and the messages of values out of range.  Each case is bounded by
# `timeout` so that a regression fails instead of hanging the suite.
. "$(dirname "$0")/lib.sh"
sinew=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
pid=
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$tmp"' EXIT
GRID='mesh: {grid: {size: [1, 1], vertices: [3, 3]}}'
MAT='material: {density: 0.1}'

# expect_error WHAT PATTERN CMD...: CMD exits non-zero within 60 s (a sanitizer build on a loaded
# machine is slow; the cases that must be quick have their own bound) and its stderr matches PATTERN.
expect_error() {
  local what=$1 pat=$2
  shift 2
  timeout 60 "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [ $rc -eq 124 ] && { fail "$what: still running after 60 s"; return; }
  [ $rc -ne 0 ] || fail "$what: accepted (exit 0)"
  grep -Eq -- "$pat" "$tmp/err" || fail "$what: message '$(head -c 400 "$tmp/err")', expected /$pat/"
}

# 1. A sampling interval far below dt (and below half an ulp of t) samples every step, at once.
for every in 1e-300 1e-12; do
  for opt in --frames-every --positions-every; do
    rm -rf "$tmp/tiny"
    timeout 20 "$sinew" run scenes/hanging_cloth.yaml --duration 0.05 "$opt" "$every" \
      --out "$tmp/tiny" --quiet 2>"$tmp/err"
    rc=$?
    [ $rc -eq 0 ] || { fail "$opt $every: exit $rc $(cat "$tmp/err")"; continue; }
    if [ "$opt" = --frames-every ]; then
      n=$(grep -c '<DataSet ' "$tmp/tiny/frames.pvd")
      [ "$n" -eq 6 ] || fail "$opt $every: $n frames, expected 6 (every step)"
    else # 6 records of 8 + 1600 x 3 x 8 bytes after the 16-byte header
      n=$(stat -c %s "$tmp/tiny/positions.bin")
      [ "$n" -eq $((16 + 6 * 38408)) ] || fail "$opt $every: positions.bin $n bytes, expected 6 records"
    fi
  done
  printf '%s\n%s\nintegrator: {dt: 0.01}\nduration: 0.05\noutput: {frames_every: %s, positions_every: %s}\n' \
    "$GRID" "$MAT" "$every" "$every" >"$tmp/tiny.yaml"
  timeout 20 "$sinew" run "$tmp/tiny.yaml" --out "$tmp/tiny_scene" --quiet 2>"$tmp/err" ||
    fail "scene frames_every $every: $(cat "$tmp/err")"
  [ "$(grep -c '<DataSet ' "$tmp/tiny_scene/frames.pvd" 2>/dev/null)" = 6 ] ||
    fail "scene frames_every $every: expected 6 frames"
done

# 2. Byte limits and memory budgets, each refused at once with the file, the position and the
# limit: 30 million pin indices (60 MB, under the 64 MB scene limit), 2.1 million values in
# block style, /dev/zero and a 300 MB (sparse) file as OBJ and as targets, a 5000-byte CSV
# line, /etc/passwd as OBJ (not quoted: "not an OBJ file").
/usr/bin/python3 - "$tmp" <<'PY' || fail "python3 could not write the large scenes"
import sys
d = sys.argv[1]
head = 'mesh: {grid: {size: [1, 1], vertices: [3, 3]}}\nmaterial: {density: 0.1}\n'
with open(d + '/pins30m.yaml', 'w') as f:
    f.write(head + 'pins: [{select: {vertices: [' + '0,' * 29999999 + '0]}}]\n')
with open(d + '/pins2m.yaml', 'w') as f:
    f.write(head + 'pins:\n  - select:\n      vertices:\n' + '        - 0\n' * 2100000)
PY
start=$(date +%s)
expect_error "30 million pin indices" \
  'pins30m.yaml:3:4000024: more than 2000000 YAML values .*expected a smaller scene' \
  "$sinew" check "$tmp/pins30m.yaml"
[ $(($(date +%s) - start)) -le 5 ] || fail "30 million pin indices took more than 5 s to refuse"
expect_error "2.1 million values, block style" \
  'pins2m.yaml:1999982:11: more than 2000000 YAML values' "$sinew" check "$tmp/pins2m.yaml"
rm -f "$tmp/pins30m.yaml" "$tmp/pins2m.yaml"
ln -s /dev/zero "$tmp/zero.obj"
truncate -s 300M "$tmp/big.obj"
cp /etc/passwd "$tmp/passwd.obj"
for obj in zero big passwd; do
  printf 'mesh: {obj: %s.obj}\n%s\n' "$obj" "$MAT" >"$tmp/obj_$obj.yaml"
done
expect_error "/dev/zero as OBJ" 'obj_zero.yaml:1:13: in mesh obj: .*zero.obj:1:1: found a NUL byte' \
  "$sinew" check "$tmp/obj_zero.yaml"
expect_error "a 300 MB OBJ" 'big.obj: larger than 268435456 bytes, expected an OBJ file of at most 256 MB' \
  "$sinew" check "$tmp/obj_big.yaml"
expect_error "/etc/passwd as OBJ" 'passwd.obj:1:1: not an OBJ file: the first statement is not an OBJ keyword' \
  "$sinew" check "$tmp/obj_passwd.yaml"
grep -q root "$tmp/err" && fail "/etc/passwd as OBJ: the message quotes the file"
{ printf 'v 0 0 0\n'; printf 'x%.0s' $(seq 1 100); echo; } >"$tmp/longword.obj"
printf 'mesh: {obj: longword.obj}\n%s\n' "$MAT" >"$tmp/obj_longword.yaml"
expect_error "a 100-byte unknown statement" "longword.obj:2:1: found unknown statement '$(printf 'x%.0s' $(seq 1 40))\\.\\.\\.'," \
  "$sinew" check "$tmp/obj_longword.yaml"
expect_error "/dev/zero as targets" '^sinew: /dev/zero:1:1: a NUL byte; expected text' \
  "$sinew" inverse scenes/tendon_inverse_2d.yaml --targets /dev/zero --out "$tmp/inv.yaml"
truncate -s 100M "$tmp/big.csv"
expect_error "a 100 MB targets file" 'big.csv: 104857600 bytes; expected a targets file of at most 64 MB' \
  "$sinew" inverse scenes/tendon_inverse_2d.yaml --targets "$tmp/big.csv" --out "$tmp/inv.yaml"
{ echo vertex,fx,fy; printf '1,%05000d,0\n' 0; } >"$tmp/long.csv"
expect_error "a 5000-byte targets line" 'long.csv:2:4097: a line longer than 4096 bytes' \
  "$sinew" inverse scenes/tendon_inverse_2d.yaml --targets "$tmp/long.csv" --out "$tmp/inv.yaml"
{ yes 'v 0 0 0' | head -n 4000001; } >"$tmp/many.obj"
printf 'mesh: {obj: many.obj}\n%s\n' "$MAT" >"$tmp/obj_many.yaml"
expect_error "4000001 OBJ positions" 'many.obj:4000001:1: found more than 4000000 positions, expected fewer' \
  "$sinew" check "$tmp/obj_many.yaml"
rm -f "$tmp/big.obj" "$tmp/big.csv" "$tmp/many.obj"
[ -e "$tmp/inv.yaml" ] && fail "inverse wrote its output after refusing its targets"

# 3. `inverse --out` naming an input (also by a symlink or another path) is refused before
# anything is written: both inputs stay byte for byte as they were.
cp scenes/tendon_inverse_2d.yaml "$tmp/inv_scene.yaml"
cp scenes/tendon_inverse_2d_targets.csv "$tmp/inv_targets.csv"
ln -s inv_scene.yaml "$tmp/inv_link.yaml"
sums=$(cat "$tmp/inv_scene.yaml" "$tmp/inv_targets.csv" | cksum)
for out in "$tmp/inv_scene.yaml" "$tmp/inv_link.yaml" "$tmp/../$(basename "$tmp")/inv_scene.yaml"; do
  expect_error "inverse --out $out" "--out .* is the scene .*inv_scene.yaml; expected another file" \
    "$sinew" inverse "$tmp/inv_scene.yaml" --targets "$tmp/inv_targets.csv" --out "$out"
done
expect_error "inverse --out the targets" "--out .* is the targets file .*inv_targets.csv" \
  "$sinew" inverse "$tmp/inv_scene.yaml" --targets "$tmp/inv_targets.csv" --out "$tmp/inv_targets.csv"
[ "$(cat "$tmp/inv_scene.yaml" "$tmp/inv_targets.csv" | cksum)" = "$sums" ] ||
  fail "inverse --out changed an input"
[ -L "$tmp/inv_link.yaml" ] || fail "inverse --out replaced the symlink"

# 4. `bench --merge` of damaged run folders: NaN positions and a log line cut to 2 fields make
# the run "damaged" with the file and line, and no error value; the intact run keeps its value.
b=$tmp/bench
"$sinew" bench tests/data/bench_tiny.yaml --out "$b" --methods backward-euler --dts 0.02,0.01 \
  --no-charts >"$tmp/bench.out" 2>&1 || fail "bench: $(tail -3 "$tmp/bench.out")"
r1=$b/runs/wp_backward-euler_dt0.02_r1 r2=$b/runs/wp_backward-euler_dt0.01_r1
cp -r "$b" "$tmp/bench0" # the folder as the bench left it, for the cases of 4b
# record 2 (t = 0.02 s) of the 36-vertex 3D file: 8 + 36 x 3 x 8 = 872 bytes each; its 4th value
printf '\x00\x00\x00\x00\x00\x00\xf8\x7f' | dd of="$r1/positions.bin" bs=1 seek=$((16 + 872 + 32)) \
  conv=notrunc status=none
sed -i '4s/^\([^,]*,[^,]*\),.*/\1/' "$r2/tension.csv"
"$sinew" bench --merge "$b" --no-charts >"$tmp/merge.out" 2>&1
csv=$b/work_precision.csv
row1=$(grep '^backward-euler,fixed,dt,0.02,' "$csv") row2=$(grep '^backward-euler,fixed,dt,0.01,' "$csv")
grep -q ',damaged,damaged data,runs/wp_backward-euler_dt0.02_r1/positions.bin:2: record 2 (t = 0.02 s): a position is not finite,' <<<"$row1" ||
  fail "NaN positions not damaged: $row1"
grep -q ',damaged,damaged data,runs/wp_backward-euler_dt0.01_r1/tension.csv:4: 2 fields; expected 7' <<<"$row2" ||
  fail "a cut row not damaged: $row2"
# a FIFO in place of a log does not block the merge; a run folder replaced by a symbolic link to
# another run is refused, not read as that run
for f in tension.csv energy.csv; do rm -f "$r1/$f"; done
cp -r "$r2" "$tmp/r2_copy"
sed -i '4s/^\([^,]*,[^,]*\),.*/\1/' "$tmp/r2_copy/tension.csv"
mkfifo "$r1/tension.csv" && cp "$tmp/r2_copy/energy.csv" "$r1/energy.csv"
rm -rf "$r2" && ln -s "$tmp/r2_copy" "$r2"
timeout 20 "$sinew" bench --merge "$b" --no-charts >"$tmp/merge.out" 2>&1
[ $? -eq 124 ] && fail "bench --merge: blocked on a FIFO"
row1=$(grep '^backward-euler,fixed,dt,0.02,' "$csv") row2=$(grep '^backward-euler,fixed,dt,0.01,' "$csv")
grep -q ',damaged,damaged data,runs/wp_backward-euler_dt0.02_r1/tension.csv: not a regular file (a FIFO  device  folder or symbolic link); expected the log the run wrote' <<<"$row1" ||
  fail "a FIFO log not damaged: $row1"
grep -q ',damaged,damaged data,runs/wp_backward-euler_dt0.01_r1: a symbolic link; expected the run.s own folder' <<<"$row2" ||
  fail "a symlinked run folder not refused: $row2"
mkdir "$tmp/bigplan" && cp "$b/bench_work_precision.cfg" "$tmp/bigplan/"
{ head -1 "$b/plan_work_precision.csv"; yes 'x,run,bdf2,0,0.01,0,0,1,0,1' | head -n 1000001; } \
  >"$tmp/bigplan/plan_work_precision.csv"
expect_error "a plan of 1000001 runs" 'plan_work_precision.csv:1000002: more than 1000000 runs in the plan' \
  "$sinew" bench --merge "$tmp/bigplan" --no-charts
rm -rf "$tmp/bigplan"
for row in "$row1" "$row2"; do
  [ -z "$(cut -d, -f18-23 <<<"$row" | tr -d ,)" ] || fail "a damaged run has error values: $row"
done

# 4b. `bench --merge` checks what it reads against the plan: each case on a fresh copy of the
# bench folder; the damaged run has no error value, the reference that did not finish is said so.
c=$tmp/bench1 ids=wp_backward-euler
fresh() { rm -rf "$c" && cp -r "$tmp/bench0" "$c"; }
merged_row() { # DT PATTERN WHAT: merge, then the row of dt DT matches PATTERN and has no errors
  "$sinew" bench --merge "$c" --no-charts >"$tmp/merge.out" 2>&1
  local row
  row=$(grep "^backward-euler,fixed,dt,$1," "$c/work_precision.csv")
  grep -Eq -- ",damaged,damaged data,$2" <<<"$row" || fail "$3: $row"
  [ -z "$(cut -d, -f9,12,15-26 <<<"$row" | tr -d ,)" ] || fail "$3: numbers of a damaged run: $row"
}
fresh; rm -rf "$c/runs/${ids}_dt0.01_r1" && cp -r "$c/runs/${ids}_dt0.02_r1" "$c/runs/${ids}_dt0.01_r1"
merged_row 0.01 "runs/${ids}_dt0.01_r1/summary.json:[0-9]+: dt is 0.02; the plan says 0.01 for this run" \
  "a run folder holding another run's summary"
fresh; sed -i 4d "$c/runs/${ids}_dt0.02_r1/tension.csv"; sed -i 4d "$c/runs/${ids}_dt0.02_r2/tension.csv"
merged_row 0.02 "runs/${ids}_dt0.02_r1/tension.csv: no line at the sample time t = 0.04 s; expected one at every 0.02 s and at the end" \
  "a log line deleted"
grep -q "repeat 2 of ${ids}_dt0.02_r1 damaged, left out of the medians: runs/${ids}_dt0.02_r2/tension.csv: no line at the sample time t = 0.04 s" "$tmp/merge.out" ||
  fail "a damaged repeat not named: $(grep repeat "$tmp/merge.out")"
[ "$(grep "^backward-euler,fixed,dt,0.02," "$c/work_precision.csv" | cut -d, -f8)" = 1 ] ||
  fail "a damaged repeat counted among the repeats"
fresh; sed -i '4{h;d};5G' "$c/runs/${ids}_dt0.02_r1/energy.csv"
merged_row 0.02 "runs/${ids}_dt0.02_r1/energy.csv:5: t = 0.04 s after t = 0.06 s on the line before; expected increasing times" \
  "log lines out of order"
fresh; e=$c/runs/${ids}_dt0.01_r1/energy.csv
awk -F, -v OFS=, 'END { for (k = 1; k <= 200000; k++) { $1 = 0.2 + k * 0.01; print } }' "$e" >"$tmp/more"
cat "$tmp/more" >>"$e"
merged_row 0.01 "runs/${ids}_dt0.01_r1/energy.csv:23: t = 0.21 s is after the planned end 0.2 s" \
  "200000 log lines appended"
fresh; sed -i 's/"wall_time_s": .*/"wall_time_s": -1e308,/' "$c/runs/${ids}_dt0.02_r1/summary.json"
merged_row 0.02 "runs/${ids}_dt0.02_r1/summary.json:[0-9]+: wall_time_s is -1e308; expected a number >= 0" \
  "wall_time_s: -1e308"
fresh; sed -i 's/"cpu_time_s": .*/"cpu_time_s": nan,/' "$c/runs/${ids}_dt0.02_r1/summary.json"
merged_row 0.02 "runs/${ids}_dt0.02_r1/summary.json:[0-9]+: cpu_time_s is nan; expected a number >= 0" \
  "cpu_time_s: nan"
fresh; head -3 "$tmp/bench0/runs/wp_reference/energy.csv" >"$c/runs/wp_reference/energy.csv"
"$sinew" bench --merge "$c" --no-charts >"$tmp/merge.out" 2>"$tmp/merge.err" && fail "a cut reference: exit 0"
grep -q 'the reference run wp_reference damaged (damaged data): no errors can be measured (logs/wp_reference.log; runs/wp_reference/energy.csv:3: the log ends at t = 0.01 s; expected the planned end 0.2 s)' "$tmp/merge.err" ||
  fail "a reference log cut to 3 lines: $(cat "$tmp/merge.err")"
grep -q '^reference: cvode:q5 rtol 1e-10 damaged; ida:q5 rtol 1e-10 ok: NOT CONFIRMED, nothing measured$' "$tmp/merge.out" ||
  fail "a reference log cut to 3 lines: $(head -3 "$tmp/merge.out")"
[ -z "$(cut -d, -f21-26 "$c/work_precision.csv" | tail -n +2 | tr -d ,)" ] || fail "errors against a cut reference"
fresh; echo timeout >"$c/logs/wp_reference.exit"; sed -i 's/^timeout = .*/timeout = 5/' "$c/bench_work_precision.cfg"
"$sinew" bench --merge "$c" --no-charts >"$tmp/merge.out" 2>&1 && fail "a timed-out reference: exit 0"
grep -q '^reference: cvode:q5 rtol 1e-10 timed out (5 s); ida:q5 rtol 1e-10 ok: NOT CONFIRMED, nothing measured$' "$tmp/merge.out" ||
  fail "a timed-out reference: $(grep reference: "$tmp/merge.out")"
fresh; sed -i 's/^reference_rtol = .*/reference_rtol = banana/' "$c/bench_work_precision.cfg"
rm "$c/work_precision.csv"
expect_error "reference_rtol = banana" 'bench_work_precision.cfg:10: reference_rtol = banana; expected a number >= 0' \
  "$sinew" bench --merge "$c" --no-charts
[ -e "$c/work_precision.csv" ] && fail "bench --merge wrote its CSV after refusing the settings"
fresh; sed -i "s/^${ids}_dt0.02_r1,run,backward-euler,0,0.02,/${ids}_dt0.02_r1,run,backward-euler,0,-1,/" "$c/plan_work_precision.csv"
rm "$c/work_precision.csv"
expect_error "a plan's dt = -1" "plan_work_precision.csv:4: dt = '-1'; expected a number > 0 \\(s\\)" \
  "$sinew" bench --merge "$c" --no-charts
[ -e "$c/work_precision.csv" ] && fail "bench --merge wrote its CSV after refusing the plan"
rm -rf "$c" "$tmp/bench0" "$tmp/more"

# 5. Messages that say what was found and what was expected, with line:column in a scene.
printf 'mesh: {grid: {size: [1e300, 1e300], vertices: [3, 3]}}\n%s\n' "$MAT" >"$tmp/area_big.yaml"
expect_error "a rest area that overflows" \
  'area_big.yaml:1:7: mesh: face 0 has a rest area that overflows in its \(u,v\) layout \(2 x area = inf m\^2\)' \
  "$sinew" check "$tmp/area_big.yaml"
printf 'mesh: {grid: {size: [1e-300, 1e-300], vertices: [3, 3]}}\n%s\n' "$MAT" >"$tmp/area_tiny.yaml"
expect_error "a zero rest area" 'area_tiny.yaml:1:7: mesh: face 0 has zero rest area' \
  "$sinew" check "$tmp/area_tiny.yaml"
printf 'mesh: {grid: {size: [1, 1], vertices: [3, 2147483648]}}\n%s\n' "$MAT" >"$tmp/int.yaml"
expect_error "2^31 vertices" 'int.yaml:1:43: mesh grid vertices\[1\] is 2147483648; expected an integer in \[2, 2147483647\]' \
  "$sinew" check "$tmp/int.yaml"
printf '%s\n%s\nintegrator: {dt: 1e-320}\n' "$GRID" "$MAT" >"$tmp/dt_sub.yaml"
expect_error "dt: 1e-320" 'dt_sub.yaml:3:18: integrator dt is 1e-320, too small to compute with \(below 2.22507e-308\); expected a number > 0 \(s\)' \
  "$sinew" check "$tmp/dt_sub.yaml"
expect_error "--dt 1e-320" '^sinew: --dt is 1e-320, too small to compute with \(below 2.22507e-308\); expected a positive number' \
  "$sinew" run scenes/hanging_cloth.yaml --dt 1e-320 --out "$tmp/never"
printf '%s\nmaterial: {density: 0.1, membrane: {model: bw98, k_u: 1e308, k_v: 1, k_shear: 1, b_u: 100, b_v: 1}}\nduration: 0.02\n' \
  "$GRID" >"$tmp/bw_inf.yaml"
expect_error "an infinite bw98 energy" 'term bw98 failed at t = 0 s: face 0 \(vertices 0 1 4\): energy inf J' \
  "$sinew" run "$tmp/bw_inf.yaml" --out "$tmp/bw_inf" --quiet

# 6. One run at a time in a folder: a second run into a folder in use is refused with the first
# one's process id and removes nothing; the lock of a killed run (kill -9) is stale and taken
# over; so is a sinew.lock holding a dead process's id; the lock is gone after a run.
lk=$tmp/locked
"$sinew" run scenes/hanging_cloth.yaml --out "$lk" --duration 5 --quiet 2>/dev/null &
pid=$!
for _ in $(seq 1 600); do [ -s "$lk/tension.csv.part" ] && break; sleep 0.05; done
[ "$(cat "$lk/sinew.lock" 2>/dev/null)" = "$pid" ] || fail "sinew.lock does not hold the run's id $pid"
expect_error "a second run into a folder in use" \
  "$lk: the folder is in use by another run \\(process $pid, .*sinew.lock\\)" \
  "$sinew" run scenes/hanging_cloth.yaml --out "$lk" --duration 0.02 --quiet
[ -e "$lk/tension.csv.part" ] && [ -e "$lk/summary.json" ] || fail "the refused run removed the first one's files"
kill -9 "$pid"
wait "$pid" 2>/dev/null
pid=
[ -e "$lk/sinew.lock" ] || fail "a killed run left no sinew.lock (nothing to take over: test void)"
"$sinew" run scenes/hanging_cloth.yaml --out "$lk" --duration 0.02 --quiet 2>"$tmp/err" ||
  fail "the lock of a killed run was not taken over: $(cat "$tmp/err")"
[ -e "$lk/sinew.lock" ] && fail "sinew.lock left after a run"
sh -c 'echo $$ >"$1"' sh "$lk/sinew.lock" # the id of a process that has ended
"$sinew" run scenes/hanging_cloth.yaml --out "$lk" --duration 0.02 --quiet 2>"$tmp/err" ||
  fail "a stale sinew.lock (dead process) was not taken over: $(cat "$tmp/err")"
if command -v flock >/dev/null; then # a lock held by any process counts
  echo 4242 >"$lk/sinew.lock"
  flock "$lk/sinew.lock" sleep 3 &
  fpid=$!
  sleep 0.3
  expect_error "a folder locked by another process" "in use by another run \\(process 4242," \
    "$sinew" run scenes/hanging_cloth.yaml --out "$lk" --duration 0.02 --quiet
  kill "$fpid" 2>/dev/null
  wait "$fpid" 2>/dev/null
fi

# Loading is linear in the scene's size: 100 000 named tendons (a 4.6 MB scene) load in a few
# seconds of CPU at most (measured: 0.8 s, 6.5 s under ASan; names are hashed).  Comparing each name with every
# earlier one took minutes.  CPU time, not wall time: the machine may be shared.
awk 'BEGIN { print "mesh: {grid: {size: [1, 1], vertices: [3, 3]}}"; print "material: {density: 0.1}";
  print "tendons:"; for (k = 0; k < 100000; k++) printf "  - {name: t%d, waypoints: [0, 8], stiffness: 1}\n", k }' \
  >"$tmp/tendons.yaml"
TIMEFORMAT='%U %S'
{ time timeout 60 "$sinew" check "$tmp/tendons.yaml" >"$tmp/out" 2>"$tmp/err"; } 2>"$tmp/cpu"
rc=$?
unset TIMEFORMAT
cpu=$(awk '{ print $1 + $2 }' "$tmp/cpu" | tail -1)
[ $rc -eq 0 ] || fail "100000 tendons: exit $rc $(head -c 300 "$tmp/err")"
awk -v c="$cpu" 'BEGIN { exit !(c < 15) }' || fail "100000 tendons: $cpu s of CPU to load; expected < 15 s"
grep -q "tendons *100000" "$tmp/out" || fail "100000 tendons: 'sinew check' says $(grep -i tendon "$tmp/out")"
sed -i 's/name: t99999,/name: t5,/' "$tmp/tendons.yaml"
expect_error "a duplicate among 100000 tendon names" "tendons\\[99999\\] is named 't5' like tendons\\[5\\]" \
  "$sinew" check "$tmp/tendons.yaml"

# CVODE and IDA fail early on a problem they cannot resolve at their tolerance: a 10 x 10 cloth
# of density 1e-9 kg/m^2 takes internal steps of ~1.5e-8 s (300 000 per output interval);
# after 10 000 steps in a row below 1e-5 x the interval the run fails, saying so, in about a
# second (it crept on for minutes before).
sed 's/^  density: 0.1 /  density: 1e-9 /; s/vertices: \[40, 40\]/vertices: [10, 10]/' \
  scenes/hanging_cloth.yaml >"$tmp/light.yaml"
grep -q "density: 1e-9" "$tmp/light.yaml" && grep -q "vertices: \[10, 10\]" "$tmp/light.yaml" ||
  fail "light cloth: the scene could not be made"
for meth in cvode ida; do
  start=$(date +%s)
  expect_error "$meth on a cloth of density 1e-9" \
    "$meth: .*_TOO_MUCH_WORK: 10000 internal steps in a row below 1e-05 x the output interval .*the problem looks unresolvable at this tolerance \(rtol 1e-06, atol 1e-08\)" \
    "$sinew" run "$tmp/light.yaml" --method $meth --duration 0.1 --out "$tmp/light_$meth" --quiet
  [ $(($(date +%s) - start)) -le 20 ] || fail "$meth: light cloth: took more than 20 s to fail"
  grep -q '"status": "failed"' "$tmp/light_$meth/summary.json" || fail "$meth: light cloth: summary not 'failed'"
done

[ $fails -eq 0 ] && echo "limits: all passed"
exit $((fails > 0))
