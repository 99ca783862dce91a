#!/usr/bin/env bash
# tests/load_signal.sh SINEW — SIGTERM while a scene with a large mesh obstacle (a generated
# 2 x 700 x 700-triangle OBJ) loads: exit code 143, a message saying the load was stopped, and
# no file in the run folder.
set -euo pipefail
sinew=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
n=700
awk -v n=$n 'BEGIN {
  for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %.6f %.6f 0\n", 4 * i / n - 2, 4 * j / n - 2
  for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
    a = j * (n + 1) + i + 1; b = a + 1; c = a + n + 2; d = a + n + 1
    printf "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d } }' >"$work/big.obj"
cat >"$work/scene.yaml" <<YAML
name: cloth above a large mesh obstacle
dimension: 3
mesh:
  grid: {size: [0.2, 0.2], vertices: [5, 5], plane: xy}
material:
  density: 0.1
  membrane: {model: bw98, k_u: 5000, k_v: 5000, k_shear: 100}
gravity: [0, 0, -9.81]
obstacles:
  - {mesh: big.obj, translate: [0.1, 0.1, -0.01]}
contact:
  distance: 2e-3
YAML
"$sinew" run "$work/scene.yaml" --out "$work/run" --duration 0.01 >"$work/out" 2>"$work/err" &
pid=$!
# once the OBJ is open (the handlers are installed before the scene loads; a sanitizer's
# start-up alone can take longer than a fixed wait), then 0.1 s into reading it
for _ in $(seq 200); do
  ls -l "/proc/$pid/fd" 2>/dev/null | grep -q 'big\.obj' && break
  sleep 0.05
done
sleep 0.1
kill -TERM $pid
rc=0
wait $pid || rc=$?
cat "$work/err"
[ "$rc" = 143 ] || { echo "FAIL: exit code $rc, expected 143"; exit 1; }
grep -q "stopped by SIGTERM while loading the scene" "$work/err" || { echo "FAIL: no message"; exit 1; }
grep -q "nothing written" "$work/err" || { echo "FAIL: no 'nothing written'"; exit 1; }
[ ! -e "$work/run" ] || { echo "FAIL: run folder written:"; ls -la "$work/run"; exit 1; }
echo "ok: SIGTERM while loading -> 143, nothing written"
