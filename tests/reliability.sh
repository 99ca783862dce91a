#!/usr/bin/env bash
# tests/reliability.sh SINEW — what a run leaves behind when it is killed, and that it is
# reproducible (docs/reliability.md):
#   1. `sinew run` killed with SIGKILL (early, and after a few steps and frames): the logs are
#      still *.csv.part, made of whole lines only; summary.json (when there is one) says
#      "running"; frames.pvd lists only frames whose .vtu is complete XML.
#   2. Two runs of the same scene with the same settings: tension.csv, energy.csv (all but the
#      wall-time column step_wall_s), frames.pvd and every frame are bit for bit the same, and
#      summary.json too apart from its timers and the peak memory (max_rss_mb).
. "$(dirname "$0")/lib.sh"
sinew=$(cd "$(dirname "$1")" && pwd)/$(basename "$1") # absolute: one test runs elsewhere
pid=
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$tmp"' EXIT

# A CSV log of whole lines: ends in a newline, every line has the header's number of fields.
# whole_lines FILE [optional]: with "optional", a missing or empty file passes (a run killed
# while opening its logs).
whole_lines() {
  local f=$1
  [ -s "$f" ] || { [ "${2:-}" = optional ] || fail "$f: missing or empty"; return; }
  [ "$(tail -c 1 "$f" | od -An -c | tr -d ' ')" = '\n' ] || fail "$f: last line incomplete"
  awk -F, 'NR == 1 { n = NF } NF != n { print FILENAME ": line " NR ": " NF " fields, header " n; bad = 1 }
           END { exit bad }' "$f" || fail "$f: a line with the wrong number of fields"
}

# Every frame listed in frames.pvd exists and ends with </VTKFile>; so does every .vtu.
frames_complete() {
  local dir=$1 f
  if [ -f "$dir/frames.pvd" ]; then
    [ "$(tail -n 1 "$dir/frames.pvd")" = '</VTKFile>' ] || fail "$dir/frames.pvd incomplete"
    for f in $(grep -o 'file="[^"]*"' "$dir/frames.pvd" | sed 's/file="\(.*\)"/\1/'); do
      [ -f "$dir/$f" ] || { fail "frames.pvd lists $f, which does not exist"; continue; }
    done
  fi
  for f in "$dir"/frames/*.vtu; do
    [ -e "$f" ] || continue
    [ "$(tail -n 1 "$f")" = '</VTKFile>' ] || fail "$f looks complete but is not"
  done
}

# kill_after DIR LINES: start a long run, SIGKILL it once tension.csv.part has LINES lines.
kill_after() {
  local dir=$1 lines=$2 n=0
  "$sinew" run scenes/hanging_cloth.yaml --out "$dir" --duration 5 --quiet 2>"$tmp/kill.err" &
  pid=$!
  for _ in $(seq 1 2400); do # at most 240 s (the ASan build is slow)
    n=$( [ -f "$dir/tension.csv.part" ] && wc -l <"$dir/tension.csv.part" || echo 0)
    [ "$n" -ge "$lines" ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -9 "$pid" 2>/dev/null || fail "the run ended before it was killed: $(cat "$tmp/kill.err")"
  wait "$pid" 2>/dev/null
  pid=
  [ "$n" -ge "$lines" ] || fail "tension.csv.part had $n lines, not $lines, before the kill"
}

for lines in 1 8; do # as soon as the header is there; after t = 0 .. 0.06 (frames at 0, 0.05)
  dir=$tmp/kill$lines
  kill_after "$dir" "$lines"
  for log in tension energy; do
    [ -e "$dir/$log.csv" ] && fail "killed run ($lines): $log.csv looks complete"
    whole_lines "$dir/$log.csv.part" "$([ "$lines" -gt 1 ] || echo optional)"
  done
  if [ -f "$dir/summary.json" ]; then
    grep -q '"status": "running"' "$dir/summary.json" || fail "killed run ($lines): summary status"
  elif [ "$lines" -gt 1 ]; then
    fail "killed run ($lines): no summary.json"
  fi
  frames_complete "$dir"
  if [ "$lines" -gt 1 ]; then
    [ "$(wc -l <"$dir/tension.csv.part")" -ge 8 ] || fail "killed run: fewer lines than seen"
    [ "$(grep -c '<DataSet ' "$dir/frames.pvd")" -ge 2 ] || fail "killed run: frames.pvd lists < 2"
  fi
done

# Killed at arbitrary moments (possibly while a frame or the summary is being written).
for delay in 0.15 0.3 0.45 0.6 0.8 1.1; do
  dir=$tmp/killed_at_$delay
  "$sinew" run scenes/hanging_cloth.yaml --out "$dir" --duration 5 --quiet 2>/dev/null &
  pid=$!
  sleep "$delay"
  kill -9 "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  pid=
  for log in tension energy; do
    [ -e "$dir/$log.csv" ] && fail "killed at $delay s: $log.csv looks complete"
    whole_lines "$dir/$log.csv.part" optional
  done
  if [ -f "$dir/summary.json" ]; then
    grep -q '"status": "running"' "$dir/summary.json" || fail "killed at $delay s: summary status"
  fi
  frames_complete "$dir"
done

# Odd command lines: a clear message and exit 1.
"$sinew" run scenes/hanging_cloth.yaml --out "" --duration 0.01 --quiet 2>"$tmp/err" &&
  fail "--out '' accepted"
grep -q -- '--out expects a folder path of 1..4095 bytes' "$tmp/err" || fail "--out '': $(cat "$tmp/err")"
"$sinew" run "$tmp" --quiet 2>"$tmp/err" && fail "a folder as the scene accepted"
grep -q 'cannot read the scene file: Is a directory' "$tmp/err" || fail "folder scene: $(cat "$tmp/err")"
long=$(printf 'a%.0s' $(seq 1 5000))
(cd "$tmp" && "$sinew" run "$OLDPWD/scenes/hanging_cloth.yaml" --out "$long" --duration 0.01 --quiet) \
  2>"$tmp/err" && fail "a 5000-byte folder name accepted"
grep -q -- '--out expects a folder path of 1..4095 bytes' "$tmp/err" ||
  fail "long --out: $(cat "$tmp/err")"
[ -e "$tmp/$long" ] && fail "a refused --out created its folder"

# Reproducibility: the same run twice.
for r in 1 2; do
  "$sinew" run scenes/hanging_cloth.yaml --out "$tmp/rep$r" --duration 0.1 --quiet 2>"$tmp/err" ||
    fail "reproducibility run $r: $(cat "$tmp/err")"
done
cmp -s "$tmp/rep1/tension.csv" "$tmp/rep2/tension.csv" || fail "tension.csv differs between runs"
cmp -s "$tmp/rep1/frames.pvd" "$tmp/rep2/frames.pvd" || fail "frames.pvd differs between runs"
nframes=0
for f in "$tmp/rep1"/frames/*.vtu; do
  nframes=$((nframes + 1))
  cmp -s "$f" "$tmp/rep2/frames/$(basename "$f")" || fail "$(basename "$f") differs between runs"
done
[ "$nframes" -eq 3 ] || fail "expected 3 frames (t = 0, 0.05, 0.1), found $nframes"
# energy.csv without its wall-time column (found by name)
col=$(head -1 "$tmp/rep1/energy.csv" | tr ',' '\n' | grep -n '^step_wall_s$' | cut -d: -f1)
[ -n "$col" ] || fail "energy.csv has no step_wall_s column"
for r in 1 2; do
  awk -F, -v c="${col:-0}" 'BEGIN { OFS = "," } { $c = "-"; print }' "$tmp/rep$r/energy.csv" \
    >"$tmp/energy$r"
done
[ "$(wc -l <"$tmp/energy1")" -eq 12 ] || fail "energy.csv: header and 11 lines expected"
cmp -s "$tmp/energy1" "$tmp/energy2" || fail "energy.csv differs between runs (beyond step_wall_s)"
timers='"(time_[a-z_]*_s|wall_time_s|wall_time_total_s|cpu_time_s|max_rss_mb)"'
for r in 1 2; do grep -Ev "$timers" "$tmp/rep$r/summary.json" | sed "s|rep$r|rep|" >"$tmp/sum$r"; done
cmp -s "$tmp/sum1" "$tmp/sum2" || fail "summary.json differs between runs (beyond its timers and max_rss_mb)"

echo "$fails failure(s)"
[ "$fails" -eq 0 ]
