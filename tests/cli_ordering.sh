#!/usr/bin/env bash
# tests/cli_ordering.sh SINEW — the fill-reducing ordering (integrator.ordering, --ordering):
# summary.json records the ordering and the factor kind the analysis used and the factor's
# nonzeros; a static solve of a prestressed 2D membrane gives the same equilibrium to
# round-off under amd, metis and nesdis; auto records what it chose; a bad value is refused
# (the scene with file:line:column, the command line naming the choices).
. "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
json() { $py -c "import json,sys; print(json.load(open('$1')).get('$2'))"; }
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
  $py - "$tmp/amd/positions.bin" "$tmp/$o/positions.bin" <<'PY' || fail "amd and $o differ"
import sys, numpy as np
def last(p):
    raw = open(p, "rb").read()
    nv, dim = np.frombuffer(raw[8:16], dtype=np.int32)
    rec = 1 + int(nv) * int(dim)
    return np.frombuffer(raw[16:], dtype=np.float64).reshape(-1, rec)[-1, 1:]
a, b = last(sys.argv[1]), last(sys.argv[2])
d = np.abs(a - b).max()
print(f"max |x_amd - x_other| = {d:.3g} m")
sys.exit(not d < 1e-12)
PY
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
[ "$fails" -eq 0 ] || exit 1
echo "ok"
