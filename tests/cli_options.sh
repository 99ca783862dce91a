#!/usr/bin/env bash
# tests/cli_options.sh SINEW — the command line's option forms and promises (seconds):
#   --opt=value is the same as --opt value (run, bench; a bad value named as such);
#   --quiet prints nothing when a run (or a resumed run) succeeds;
#   the defaults the help pages name are the code's (a run without the option, a bench plan);
#   a resumed run's summary.json has the resumed part's wall time and the total;
#   the progress line (on a terminal) shows the share of the duration and the time left.
. "$(dirname "$0")/lib.sh"
scene=tests/data/bench_tiny.yaml
py=/usr/bin/python3
json() { $py -c "import json,sys; print(json.load(open('$1'))['$2'])"; }

# ------------------------------------------------------------ --opt=value
"$sinew" run $scene --out="$tmp/eq" --method=bdf2 --dt=0.01 --duration=0.03 --frames-format=ascii \
  --grid=4x4 --quiet >"$tmp/out" 2>&1 || fail "run with --opt=value: $(cat "$tmp/out")"
[ "$(json "$tmp/eq/summary.json" method)" = bdf2 ] || fail "--method=bdf2 not taken"
[ "$(json "$tmp/eq/summary.json" steps)" = 3 ] || fail "--dt=0.01 --duration=0.03: $(json "$tmp/eq/summary.json" steps) steps"
[ "$(json "$tmp/eq/summary.json" vertices)" = 16 ] || fail "--grid=4x4 not taken"
grep -q 'format="ascii"' "$tmp/eq/frames/frame_000000.vtu" || fail "--frames-format=ascii not taken"
"$sinew" run $scene --out="$tmp/bad" --dt=abc >"$tmp/out" 2>&1 && fail "--dt=abc accepted"
grep -q -- "--dt expects a positive number, got 'abc'" "$tmp/out" || fail "--dt=abc: $(cat "$tmp/out")"
"$sinew" run $scene --frobnicate=1 >"$tmp/out" 2>&1 && fail "--frobnicate=1 accepted"
grep -q 'unknown option.*--frobnicate' "$tmp/out" || fail "--frobnicate=1: $(cat "$tmp/out")"
"$sinew" bench $scene --out="$tmp/b" --methods=bdf2 --dts=0.02,0.01 --repeat=1 \
  --emit-jobs="$tmp/jobs.txt" >"$tmp/out" 2>&1 || fail "bench with --opt=value: $(cat "$tmp/out")"
[ "$(wc -l <"$tmp/jobs.txt" 2>/dev/null)" = 4 ] || fail "bench --dts=.. --repeat=1: not 4 jobs"
"$sinew" check $scene --grid=5x5 | grep -q 'vertices *25 ' || fail "check --grid=5x5"

# ------------------------------------------------------------ --quiet
"$sinew" run $scene --out "$tmp/q" --duration 0.1 --quiet >"$tmp/q.out" 2>"$tmp/q.err" || fail "quiet run failed"
[ -s "$tmp/q.out" ] || [ -s "$tmp/q.err" ] && fail "--quiet printed: $(cat "$tmp/q.out" "$tmp/q.err")"
"$sinew" run --resume "$tmp/q" --duration 0.2 --quiet >"$tmp/q.out" 2>"$tmp/q.err" || fail "quiet resume failed"
[ -s "$tmp/q.out" ] || [ -s "$tmp/q.err" ] && fail "--quiet resume printed: $(cat "$tmp/q.out" "$tmp/q.err")"
# without it, where the results are
"$sinew" run $scene --out "$tmp/nq" --duration 0.02 2>&1 | grep -q 'results in' || fail "no results line without --quiet"

# ------------------------------------------------------------ resumed wall time
w=$(json "$tmp/q/summary.json" wall_time_s)
wt=$(json "$tmp/q/summary.json" wall_time_total_s)
$py -c "import sys; sys.exit(not (0 < $w < $wt))" || fail "resumed: wall_time_s $w, wall_time_total_s $wt"
w=$(json "$tmp/nq/summary.json" wall_time_s)
wt=$(json "$tmp/nq/summary.json" wall_time_total_s)
[ "$w" = "$wt" ] || fail "a run never resumed: wall_time_s $w != wall_time_total_s $wt"

# ------------------------------------------------------------ help = defaults
# run: the frame format the help names is the one a run without --frames-format writes.
fmt=$("$sinew" run --help | tr '\n' ' ' | grep -o 'output.frames_format; default [a-z0-9]*' | awk '{print $3}')
[ -n "$fmt" ] || fail "run --help names no default frame format"
case "$fmt" in binary32) want=Float32 ;; binary) want=Float64 ;; ascii) want=ascii ;; *) want=? ;; esac
grep -a 'Name="velocity"' "$tmp/q/frames/frame_000000.vtu" | grep -q "$want" ||
  fail "run --help says the default frame format is $fmt; a run writes $(grep -a 'Name="velocity"' "$tmp/q/frames/frame_000000.vtu")"
# bench: each default its help names is the one its settings file records.
"$sinew" bench $scene --out "$tmp/d" --emit-jobs "$tmp/d.txt" >/dev/null 2>&1 || fail "bench --emit-jobs (defaults)"
help=$("$sinew" bench --help | tr '\n' ' ' | tr -s ' ')
cfg=$tmp/d/bench_work_precision.cfg
val() { sed -n "s/^$1 = //p" "$cfg"; }
same() { # key, the value the help names
  $py -c "import sys; a, b = '$2', '$(val "$1")'
try: sys.exit(not float(a) == float(b))
except ValueError: sys.exit(a != b)" || fail "bench --help names $1 '$2'; the default is '$(val "$1")'"
}
same repeat "$(grep -o 'median of --repeat N, default [0-9]*' <<<"$help" | awk '{print $NF}')"
same time "$(grep -o -- '--time cpu|wall the time of the printed table and the charts (default [a-z]*' <<<"$help" | awk '{print $NF}')"
same reference "$(grep -o 'A reference (--reference [a-z0-9:]*' <<<"$help" | awk '{print $NF}')"
same reference_rtol "$(grep -o 'at --reference-rtol [0-9e.-]*)' <<<"$help" | tr -d ')' | awk '{print $NF}')"
same confirm "$(grep -o '(--confirm [a-z0-9:]*' <<<"$help" | awk '{print $NF}')"
same confirm_tol "$(grep -o -- '--confirm-tol ([0-9e.-]*' <<<"$help" | tr -d '(' | awk '{print $NF}')"
same reference_newton_tol "$(grep -o -- '--reference-newton-tol ([0-9e.-]*' <<<"$help" | tr -d '(' | awk '{print $NF}')"
same overdamped "$(grep -o -- '--overdamped [0-9.][0-9.]*' <<<"$help" | awk '{print $NF}')"
same diverged "$(grep -o -- "cloth's size (default [0-9.]*" <<<"$help" | tr -d '(' | awk '{print $NF}')"
same steps "$(grep -o -- '--steps ([0-9]*' <<<"$help" | tr -d '(' | awk '{print $NF}')"
same max_halvings "$(grep -o -- 'times (default [0-9]*: dt means dt' <<<"$help" | awk '{print $3}' | tr -d ':')"
# the default dts (the scene's dt 0.02 x 1, 1/2, 1/4, 1/8) and rtols (1e-3 .. 1e-6) of the plan
grep -q "the scene's dt x 1, 1/2, 1/4, 1/8" <<<"$help" || fail "bench --help: default dts changed; update this test"
grep -q -- "--rtols (default 1e-3 .. 1e-6)" <<<"$help" || fail "bench --help: default rtols changed; update this test"
[ "$(awk -F, '$3 == "backward-euler" && $10 == 1 { printf "%s ", $5 }' "$tmp/d/plan_work_precision.csv")" = "0.02 0.01 0.005 0.0025 " ] ||
  fail "bench: default dts of the plan: $(awk -F, '$3 == "backward-euler" && $10 == 1 { printf "%s ", $5 }' "$tmp/d/plan_work_precision.csv")"
[ "$(awk -F, '$3 == "cvode" && $10 == 1 { printf "%s ", $6 }' "$tmp/d/plan_work_precision.csv")" = "0.001 0.0001 1e-05 1e-06 " ] ||
  fail "bench: default rtols of the plan"
same tension_diverged "$(grep -o -- "largest tension (default [0-9.]*" <<<"$help" | tr -d '(' | awk '{print $NF}')"

# ------------------------------------------------------------ progress line
if command -v script >/dev/null; then
  script -qec "$sinew run scenes/hanging_cloth.yaml --out $tmp/p --duration 0.2 --no-frames" /dev/null \
    | tr '\r' '\n' >"$tmp/p.out" 2>&1 || fail "run under script: $(tail -3 "$tmp/p.out")"
  grep -Eq '\( *[0-9.]+%\)' "$tmp/p.out" || fail "no percentage on the progress line: $(head -3 "$tmp/p.out")"
  grep -q '(100.0%)' "$tmp/p.out" || fail "the last progress line is not at 100%"
  grep -Eq '~[0-9]+ s left' "$tmp/p.out" || fail "no time left on the progress line"
fi

[ "$fails" -eq 0 ] && echo "cli_options: all checks passed"
[ "$fails" -eq 0 ]
