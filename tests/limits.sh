#!/usr/bin/env bash
# tests/limits.sh SINEW — hostile inputs that must not hang, exhaust memory or destroy a file
# (docs/reliability.md, "Limits"): sampling intervals far below the step, oversized and endless
# input files, counts beyond the memory budget, `inverse --out` naming an input, damaged run
# folders in `bench --merge`, and the messages of values out of range.  Each case is bounded by
# `timeout` so that a regression fails instead of hanging the suite.
set -u
sinew=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
GRID='mesh: {grid: {size: [1, 1], vertices: [3, 3]}}'
MAT='material: {density: 0.1}'

# expect_error WHAT PATTERN CMD...: CMD exits non-zero within 20 s and its stderr matches PATTERN.
expect_error() {
  local what=$1 pat=$2
  shift 2
  timeout 20 "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [ $rc -eq 124 ] && { fail "$what: still running after 20 s"; return; }
  [ $rc -ne 0 ] || fail "$what: accepted (exit 0)"
  grep -Eq -- "$pat" "$tmp/err" || fail "$what: message '$(head -c 400 "$tmp/err")', expected /$pat/"
}

# 1. A sampling interval far below dt (and below half an ulp of t) samples every step, at once.
for every in 1e-300 1e-12; do
  for opt in --frames-every --positions-every; do
    rm -rf "$tmp/tiny"
    timeout 60 "$sinew" run scenes/hanging_cloth.yaml --duration 0.05 "$opt" "$every" \
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
  printf '%s\n%s\nintegrator: {dt: 0.01}\nduration: 0.03\noutput: {frames_every: %s, positions_every: %s}\n' \
    "$GRID" "$MAT" "$every" "$every" >"$tmp/tiny.yaml"
  timeout 60 "$sinew" run "$tmp/tiny.yaml" --out "$tmp/tiny_scene" --quiet 2>"$tmp/err" ||
    fail "scene frames_every $every: $(cat "$tmp/err")"
  [ "$(grep -c '<DataSet ' "$tmp/tiny_scene/frames.pvd" 2>/dev/null)" = 4 ] ||
    fail "scene frames_every $every: expected 4 frames"
done

[ $fails -eq 0 ] && echo "limits: all passed"
exit $((fails > 0))
