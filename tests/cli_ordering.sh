#!/usr/bin/env bash
# tests/cli_ordering.sh SINEW — the fill-reducing ordering (integrator.ordering, --ordering):
# summary.json records the ordering and the factor kind the analysis used and the factor's
# nonzeros; a static solve of a prestressed 2D membrane gives the same equilibrium to
# round-off under amd, metis and nesdis; auto records what it chose; a bad value is refused
# (the scene with file:line:column, the command line naming the choices).  --bending-matrix: a
# hanging cloth with quadratic bending stepped with the compact matrix has the membrane's
# factor (fewer nonzeros than with the exact one) and the exact matrix's positions to Newton's
# tolerance; a bad value is refused, naming the choices, and writes nothing.
. "$(dirname "$0")/lib.sh"
py="/usr/bin/python3 -B"
json() { $py -c "import json,sys; print(json.load(open('$1')).get('$2'))"; }
# last_apart A B LO HI: the largest coordinate difference of two positions.bin files' last
# records, printed, and whether LO <= it < HI (m)
last_apart() {
  $py - "$@" <<'PY'
import sys, numpy as np
sys.path.insert(0, "tools")
from positions_diff import records
a, b = (records(p)[1][-1] for p in sys.argv[1:3])
d = np.abs(a - b).max()
print(f"max |x_a - x_b| = {d:.3g} m")
sys.exit(not float(sys.argv[3]) <= d < float(sys.argv[4]))
PY
}
cat >"$tmp/membrane.yaml" <<'YAML'
name: static membrane
dimension: 2
mesh: {grid: {size: [1, 1], vertices: [12, 12]}}
material:
  density: 0.1
  membrane: {model: bw98, k_u: 5000, k_v: 5000, k_shear: 100, b_u: 0.99, b_v: 0.99}
gravity: [0, -9.81]
pins: [{select: {grid: [[0, 0], [-1, 0], [0, -1], [-1, -1]]}}]
integrator: {method: static, ordering: amd}
YAML
for o in amd metis nesdis; do
  "$sinew" run "$tmp/membrane.yaml" --ordering "$o" --out "$tmp/$o" --positions-every 1 --quiet \
    2>"$tmp/err" || fail "static membrane, ordering $o: $(cat "$tmp/err")"
  [ "$(json "$tmp/$o/summary.json" status)" = ok ] || fail "ordering $o: status not ok"
  [ "$(json "$tmp/$o/summary.json" ordering)" = "$o" ] ||
    fail "ordering $o: summary.json records $(json "$tmp/$o/summary.json" ordering)"
  [ "$(json "$tmp/$o/summary.json" factorization)" = simplicial ] ||
    fail "ordering $o: factorization $(json "$tmp/$o/summary.json" factorization)"
  [ "$(json "$tmp/$o/summary.json" factor_nnz)" -gt 0 ] || fail "ordering $o: no factor_nnz"
done
# the scene's key alone (no --ordering)
"$sinew" run "$tmp/membrane.yaml" --out "$tmp/scene" --no-frames --quiet 2>"$tmp/err" ||
  fail "static membrane, the scene's ordering: $(cat "$tmp/err")"
[ "$(json "$tmp/scene/summary.json" ordering)" = amd ] || fail "integrator.ordering: amd not taken"
# the same equilibrium: positions within 1e-12 m (the sag is ~1e-4 m)
for o in metis nesdis; do
  last_apart "$tmp/amd/positions.bin" "$tmp/$o/positions.bin" 0 1e-12 || fail "amd and $o differ"
done
# nested dissection orders a larger pattern differently from AMD: other factor nonzeros
[ "$(json "$tmp/amd/summary.json" factor_nnz)" != "$(json "$tmp/metis/summary.json" factor_nnz)" ] ||
  fail "metis and amd factors of the same size: was the ordering applied?"
# auto: records the ordering it chose
"$sinew" run "$tmp/membrane.yaml" --ordering auto --out "$tmp/auto" --no-frames --quiet ||
  fail "ordering auto"
case $(json "$tmp/auto/summary.json" ordering) in amd|metis|nesdis) ;; *)
  fail "ordering auto: recorded $(json "$tmp/auto/summary.json" ordering)" ;; esac
# bad values
sed 's/ordering: amd/ordering: colamd/' "$tmp/membrane.yaml" >"$tmp/bad.yaml"
"$sinew" run "$tmp/bad.yaml" --out "$tmp/bad" >"$tmp/out" 2>&1 && fail "ordering: colamd accepted"
grep -q "bad.yaml:9:40: .*auto, amd, metis, nesdis" "$tmp/out" ||
  fail "ordering: colamd: $(cat "$tmp/out")"
"$sinew" run "$tmp/membrane.yaml" --ordering natural --out "$tmp/bad" >"$tmp/out" 2>&1 &&
  fail "--ordering natural accepted"
grep -q -- "--ordering expects one of: auto amd metis nesdis; got 'natural'" "$tmp/out" ||
  fail "--ordering natural: $(cat "$tmp/out")"
# --bending-matrix: the compact matrix (the couplings beyond a face moved onto the diagonal)
# has a smaller factor and the same answer to Newton's tolerance (1e-6 m/s x 10 ms steps)
cat >"$tmp/bend.yaml" <<'YAML'
name: bending cloth
dimension: 3
mesh: {grid: {size: [0.5, 0.5], vertices: [14, 14]}}
material:
  density: 0.1
  membrane: {model: bw98, k_u: 500, k_v: 500, k_shear: 10}
  bending: {model: quadratic, stiffness: 1e-4}
gravity: [0, 0, -9.81]
pins: [{select: {grid: [[0, -1], [-1, -1]]}}]
integrator: {method: backward-euler, dt: 0.01, newton: {tol: 1e-6}}
duration: 0.2
YAML
for b in exact compact; do
  "$sinew" run "$tmp/bend.yaml" --bending-matrix "$b" --out "$tmp/b_$b" --positions-every 1 \
    --quiet 2>"$tmp/err" || fail "bending cloth, --bending-matrix $b: $(cat "$tmp/err")"
done
[ "$(json "$tmp/b_compact/summary.json" factor_nnz)" -lt "$(json "$tmp/b_exact/summary.json" factor_nnz)" ] ||
  fail "--bending-matrix compact: factor not smaller than exact's"
last_apart "$tmp/b_exact/positions.bin" "$tmp/b_compact/positions.bin" 1e-300 1e-5 ||
  fail "compact and exact differ"
"$sinew" run "$tmp/bend.yaml" --bending-matrix wide --out "$tmp/b_bad" >"$tmp/out" 2>&1
rc=$?
[ "$rc" -eq 2 ] || fail "--bending-matrix wide: exit $rc, expected 2"
grep -q -- "--bending-matrix expects one of: exact compact auto; got 'wide'" "$tmp/out" ||
  fail "--bending-matrix wide: $(cat "$tmp/out")"
[ ! -e "$tmp/b_bad" ] || fail "--bending-matrix wide: wrote $tmp/b_bad"
[ "$fails" -eq 0 ] || exit 1
echo "ok"
