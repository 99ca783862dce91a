#!/usr/bin/env bash
# tools/valgrind.sh [BUILD_DIR] — the valgrind (memcheck) runs of docs/reliability.md: the default
# scene for 3 steps, then a run that fails (Newton allowed one iteration, 2 halvings), so the
# failure path (logs kept, last good frame, "failed" summary) is checked too.  Uses BUILD_DIR
# (default: build, set up and built when needed).  Any memcheck error or definite/possible leak
# fails (exit 1).  No suppressions: what stays reachable at exit is libgomp's one-time state.
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
command -v valgrind >/dev/null || { echo "valgrind is not installed (apt-get install valgrind)"; exit 1; }
if [ ! -f "$build/build.ninja" ]; then meson setup "$build" >/dev/null || exit 1; fi
ninja -C "$build" >/dev/null || exit 1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0

echo "valgrind: default scene, 3 steps"
valgrind --leak-check=full --error-exitcode=1 "./$build/sinew" run scenes/hanging_cloth.yaml \
  --duration 0.03 --out "$tmp/vg" --quiet 2>"$tmp/log1"
rc=$?
grep -E 'ERROR SUMMARY|definitely lost|indirectly lost|possibly lost|still reachable|in use at exit' "$tmp/log1"
[ "$rc" -eq 0 ] || { echo "FAIL: exit $rc"; cat "$tmp/log1"; status=1; }

echo "valgrind: a run that fails (expected exit 1 from sinew, 99 would be memcheck)"
sed -e 's/newton: {max_iterations: 50, tol: 1e-6}/newton: {max_iterations: 1, tol: 1e-12}/' \
    -e 's/max_halvings: 8 /max_halvings: 2 /' scenes/hanging_cloth.yaml >"$tmp/failing.yaml"
valgrind --leak-check=full --error-exitcode=99 "./$build/sinew" run "$tmp/failing.yaml" \
  --out "$tmp/vgfail" --quiet 2>"$tmp/log2"
rc=$?
grep -E 'run failed|ERROR SUMMARY|definitely lost|indirectly lost|possibly lost' "$tmp/log2"
[ "$rc" -eq 1 ] || { echo "FAIL: exit $rc (expected 1)"; cat "$tmp/log2"; status=1; }
grep -q '"status": "failed"' "$tmp/vgfail/summary.json" || { echo "FAIL: summary"; status=1; }

[ "$status" -eq 0 ] && echo "valgrind: no errors, no leaks"
exit "$status"
