#!/usr/bin/env bash
# tools/bench_frames.sh — size and write time of one frame at 512x512 in each frames format:
# scenes/bench/scaling_cloth.yaml --grid 512x512, one step (frames at t = 0 and t = dt), wall
# time against the same run with --no-frames, interleaved ROUNDS times (the median of each).
# Usage: tools/bench_frames.sh [SINEW] [ROUNDS]   (prints a markdown table; docs/scenes.md)
set -euo pipefail
cd "$(dirname "$0")/.."
sinew=${1:-build/sinew}
rounds=${2:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
formats=(none binary binary32 ascii)
for r in $(seq "$rounds"); do
  for f in "${formats[@]}"; do
    args=(--frames-format "${f/none/binary}")
    [ "$f" = none ] && args+=(--no-frames)
    s=$(date +%s.%N)
    "$sinew" run scenes/bench/scaling_cloth.yaml --grid 512x512 --duration 0.001 --quiet \
      --out "$tmp/$f" "${args[@]}" 2>/dev/null
    e=$(date +%s.%N)
    echo "$f $(echo "$e - $s" | bc)" >>"$tmp/times"
  done
done
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
base=$(awk '$1=="none"{print $2}' "$tmp/times" | median)
echo "| format | frame at t = dt (bytes) | write time per frame (s) |"
echo "| --- | --- | --- |"
for f in binary binary32 ascii; do
  t=$(awk -v f="$f" '$1==f{print $2}' "$tmp/times" | median)
  size=$(stat -c %s "$tmp/$f/frames/frame_000001.vtu")
  printf "| %s | %s | %.2f |\n" "$f" "$size" "$(echo "($t - $base) / 2" | bc -l)"
done
echo "(run without frames: $base s)"
