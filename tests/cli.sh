#!/usr/bin/env bash
# tests/cli.sh SINEW — the command line end to end: help and version, check, a short run of the
# default scene with every output in place and complete, and bad input refused with
# file:line:column, a non-zero exit and nothing written.
. "$(dirname "$0")/lib.sh"

"$sinew" --version | grep -q '^sinew [0-9]' || fail "--version"
"$sinew" --help | grep -q 'backward-euler' || fail "--help lists the methods"
"$sinew" run --help | grep -q -- '--duration' || fail "run --help"
# every subcommand has its own help page, exit 0
for cmd in run check inverse bench render; do
  "$sinew" $cmd --help >"$tmp/help" 2>&1 || fail "$cmd --help exits $?"
  grep -q "^usage: sinew $cmd" "$tmp/help" || fail "$cmd --help: $(head -1 "$tmp/help")"
done
"$sinew" check --help | grep -q -- '--duration' && fail "check --help shows run's options"
"$sinew" frobnicate >/dev/null 2>&1 && fail "unknown command accepted"

out=$("$sinew" check scenes/hanging_cloth.yaml) || fail "check of the default scene"
grep -q 'vertices    1600 (2 pinned)' <<<"$out" || fail "check: vertices ($out)"
grep -q 'free DOFs   4794' <<<"$out" || fail "check: free DOFs"
grep -q 'terms       bw98 gravity' <<<"$out" || fail "check: terms"
grep -Eq 'system nnz  [0-9]+' <<<"$out" || fail "check: nnz"

# A short run: t = 0 and three steps logged, frames and summary complete, no .part left.
"$sinew" run scenes/hanging_cloth.yaml --out "$tmp/run" --duration 0.03 --quiet 2>"$tmp/err" ||
  fail "short run: $(cat "$tmp/err")"
[ "$(wc -l <"$tmp/run/tension.csv")" -eq 5 ] || fail "tension.csv has header + 4 lines"
[ "$(wc -l <"$tmp/run/energy.csv")" -eq 5 ] || fail "energy.csv has header + 4 lines"
head -1 "$tmp/run/tension.csv" | grep -q '^time,txy_max,txy_mean,txy_p95' || fail "tension header"
grep -q '"status": "ok"' "$tmp/run/summary.json" || fail "summary status ok"
ls "$tmp/run"/*.part >/dev/null 2>&1 && fail ".part files left after a complete run"
ls "$tmp/run/frames/"*.vtu >/dev/null 2>&1 || fail "no frames"
grep -q '<VTKFile type="Collection"' "$tmp/run/frames.pvd" || fail "frames.pvd"
tail -1 "$tmp/run/tension.csv" | grep -q '^0.03' || fail "last line at t = 0.03"
# summary.json: step wall time, peak memory and the factor's nonzeros, all > 0 for backward Euler
for key in time_step_s max_rss_mb factor_nnz; do
  grep -Eq "\"$key\": [0-9.e+-]+,?\$" "$tmp/run/summary.json" || fail "summary has no number $key"
  v=$(sed -n "s/.*\"$key\": \([0-9.e+-]*\).*/\1/p" "$tmp/run/summary.json")
  awk -v v="$v" 'BEGIN { exit !(v + 0 > 0) }' || fail "summary $key = '$v', expected > 0"
done

# --frames-every: a frame every 0.01 s (t = 0, 0.01, 0.02, 0.03); --no-frames: neither frames nor
# frames.pvd nor frames/, and summary.json lists none.
"$sinew" run scenes/hanging_cloth.yaml --out "$tmp/fe" --duration 0.03 --frames-every 0.01 --quiet \
  2>"$tmp/err" || fail "--frames-every run: $(cat "$tmp/err")"
[ "$(ls "$tmp/fe/frames/"*.vtu | wc -l)" -eq 4 ] || fail "--frames-every 0.01: 4 frames"
[ "$(grep -c '<DataSet ' "$tmp/fe/frames.pvd")" -eq 4 ] || fail "--frames-every 0.01: frames.pvd"
"$sinew" run scenes/hanging_cloth.yaml --out "$tmp/fe" --duration 0.03 --no-frames --quiet \
  2>"$tmp/err" || fail "--no-frames run: $(cat "$tmp/err")"
[ -e "$tmp/fe/frames.pvd" ] && fail "--no-frames wrote frames.pvd"
ls "$tmp/fe/frames/"*.vtu >/dev/null 2>&1 && fail "--no-frames left frames (of the earlier run)"
grep -q 'frame' "$tmp/fe/summary.json" && fail "--no-frames: summary lists frames"
[ "$(wc -l <"$tmp/fe/tension.csv")" -eq 5 ] || fail "--no-frames: the logs are complete"
"$sinew" run scenes/hanging_cloth.yaml --out "$tmp/nf" --duration 0.03 --no-frames --quiet \
  2>/dev/null || fail "--no-frames run in a new folder"
[ -e "$tmp/nf/frames" ] && fail "--no-frames made frames/"

# --positions-every 0.02 to 0.03 s: records at t = 0, 0.02 and 0.03 (the final time), each
# 8 + 1600 x 3 x 8 bytes after a 16-byte header SWPOS001, nv = 1600, dim = 3.
"$sinew" run scenes/hanging_cloth.yaml --out "$tmp/pos" --duration 0.03 --positions-every 0.02 \
  --no-frames --quiet 2>"$tmp/err" || fail "--positions-every run: $(cat "$tmp/err")"
[ "$(head -c 8 "$tmp/pos/positions.bin")" = SWPOS001 ] || fail "positions.bin magic"
[ "$(od -An -t d4 -j 8 -N 8 "$tmp/pos/positions.bin" | tr -s ' ')" = " 1600 3" ] ||
  fail "positions.bin nv, dim: $(od -An -t d4 -j 8 -N 8 "$tmp/pos/positions.bin")"
[ "$(stat -c %s "$tmp/pos/positions.bin")" -eq $((16 + 3 * (8 + 1600 * 3 * 8))) ] ||
  fail "positions.bin: 3 records, size $(stat -c %s "$tmp/pos/positions.bin")"
grep -q '"positions.bin"' "$tmp/pos/summary.json" || fail "summary lists positions.bin"
"$sinew" run scenes/hanging_cloth.yaml --out "$tmp/pos" --duration 0.01 --quiet 2>/dev/null ||
  fail "run without positions"
[ -e "$tmp/pos/positions.bin" ] && fail "positions.bin of an earlier run left behind"

# A failed run with --no-frames still writes its last good state as the one frame.
cat >"$tmp/f.yaml" <<'EOF'
mesh: {grid: {size: [1, 1], vertices: [4, 4]}}
material: {density: 0.1, membrane: {k_u: 100, k_v: 100, k_shear: 1}}
gravity: [0, 0, -9.81]
integrator: {newton: {max_iterations: 1, tol: 1e-12}, max_halvings: 1}
EOF
"$sinew" run "$tmp/f.yaml" --out "$tmp/nff" --no-frames --quiet 2>/dev/null &&
  fail "failing run exited 0"
[ "$(ls "$tmp/nff/frames/"*.vtu | wc -l)" -eq 1 ] || fail "--no-frames failed run: one frame"
grep -q '"status": "failed"' "$tmp/nff/summary.json" || fail "--no-frames failed run: status"

# --grid replaces the grid's vertices (boxes select on the new grid); --stiffness-scale shows in
# check and summary.json; a mesh that is not a grid and index pins out of range are refused.
box='{select: {box: [[-0.01, 0.99, -1], [1.01, 1.01, 1]]}}'
sed "s/{select: {grid: \[\[0, -1\], \[-1, -1\]\]}}/$box/" scenes/hanging_cloth.yaml >"$tmp/boxpins.yaml"
grep -q 'box: ' "$tmp/boxpins.yaml" || fail "boxpins.yaml: the pins were not replaced"
out=$("$sinew" check "$tmp/boxpins.yaml" --grid 7x5) || fail "check --grid 7x5"
grep -q 'vertices    35 (7 pinned)' <<<"$out" || fail "check --grid 7x5: $out"
grep -q 'faces       48' <<<"$out" || fail "check --grid 7x5: faces"
grep -q '^stiffness' <<<"$out" && fail "check prints a stiffness scale of 1"
out=$("$sinew" check "$tmp/boxpins.yaml" --stiffness-scale 2.5) || fail "check --stiffness-scale"
grep -q '^stiffness   x 2.5 ' <<<"$out" || fail "check --stiffness-scale 2.5: $out"
"$sinew" run "$tmp/boxpins.yaml" --grid 6x4 --stiffness-scale 2 --duration 0.02 --out "$tmp/g" \
  --quiet 2>"$tmp/err" || fail "run --grid --stiffness-scale: $(cat "$tmp/err")"
grep -q '"vertices": 24,' "$tmp/g/summary.json" || fail "run --grid 6x4: vertices in summary"
grep -q '"stiffness_scale": 2,' "$tmp/g/summary.json" || fail "summary stiffness_scale"
grep -q '"stiffness_scale": 1,' "$tmp/run/summary.json" || fail "summary stiffness_scale 1"
"$sinew" check scenes/skirt.yaml --grid 7x5 >/dev/null 2>"$tmp/err" && fail "--grid on an OBJ"
grep -q 'skirt.yaml:[0-9]*:[0-9]*: mesh is an OBJ file (obj), not mesh: {grid: ...}' "$tmp/err" ||
  fail "--grid on an OBJ: $(cat "$tmp/err")"
sed "s/{select: {grid: \[\[0, -1\], \[-1, -1\]\]}}/{select: {vertices: [1560, 1599]}}/" \
  scenes/hanging_cloth.yaml >"$tmp/indexpins.yaml"
grep -q 'vertices: \[1560' "$tmp/indexpins.yaml" || fail "indexpins.yaml: the pins were not replaced"
if "$sinew" run "$tmp/indexpins.yaml" --grid 7x5 --out "$tmp/x" 2>"$tmp/err" >/dev/null; then
  fail "--grid with pins by index out of range"
fi
want='pins\[0\] select vertices\[0\] is 1560; expected an integer in \[0, 34\]'
grep -q "indexpins.yaml:[0-9]*:[0-9]*: $want" "$tmp/err" ||
  fail "--grid index pins message: $(cat "$tmp/err")"
# Pins by index under --grid: loaded (1560 and 1599 are interior vertices of an 80 x 80 grid),
# with a warning naming where; the shipped scene's grid selection keeps the two corners.
"$sinew" check "$tmp/indexpins.yaml" --grid 80x80 >/dev/null 2>"$tmp/err" || fail "check indexpins"
want='sinew: warning: .*indexpins.yaml:24:25: the scene selects vertices by index, and the grid'
grep -q "$want override (--grid 80x80) keeps indices" "$tmp/err" ||
  fail "--grid index warning: $(cat "$tmp/err")"
"$sinew" check "$tmp/indexpins.yaml" 2>"$tmp/err" >/dev/null
[ -s "$tmp/err" ] && fail "a warning without --grid: $(cat "$tmp/err")"
out=$("$sinew" check scenes/hanging_cloth.yaml --grid 7x5 2>"$tmp/err") || fail "check --grid 7x5"
grep -q 'vertices    35 (2 pinned)' <<<"$out" || fail "grid pins under --grid 7x5: $out"
[ -s "$tmp/err" ] && fail "a warning for grid pins: $(cat "$tmp/err")"
for bad in 7 7x 1x5 7x5x 0x0 ax5 -3x5 7x99999999999; do
  "$sinew" run scenes/hanging_cloth.yaml --grid "$bad" --out "$tmp/x" 2>"$tmp/err" >/dev/null &&
    fail "--grid $bad accepted"
  grep -q -- "--grid expects NXxNY" "$tmp/err" || fail "--grid $bad message: $(cat "$tmp/err")"
done
"$sinew" run "$tmp/boxpins.yaml" --grid 2000x2000 --out "$tmp/x" 2>"$tmp/err" >/dev/null &&
  fail "--grid 2000x2000 accepted"
grep -q 'boxpins.yaml: the grid override (--grid) is 2000 x 2000 vertices; expected at most' \
  "$tmp/err" || fail "--grid 2000x2000 message: $(cat "$tmp/err")"
for bad in 0 -1 nan x; do
  "$sinew" run scenes/hanging_cloth.yaml --stiffness-scale "$bad" --out "$tmp/x" 2>"$tmp/err" \
    >/dev/null && fail "--stiffness-scale $bad accepted"
  grep -q -- "--stiffness-scale expects a positive number" "$tmp/err" ||
    fail "--stiffness-scale $bad message: $(cat "$tmp/err")"
done
"$sinew" check scenes/hanging_cloth.yaml --quiet >/dev/null 2>&1 && fail "check --quiet accepted"

# Overrides are validated.
"$sinew" run scenes/hanging_cloth.yaml --dt -1 --out "$tmp/x" >/dev/null 2>&1 && fail "--dt -1"
"$sinew" run scenes/hanging_cloth.yaml --method nope --out "$tmp/x" >/dev/null 2>&1 && fail "--method nope"
"$sinew" run scenes/hanging_cloth.yaml --frames-every -1 --out "$tmp/x" >/dev/null 2>&1 &&
  fail "--frames-every -1"
"$sinew" run scenes/hanging_cloth.yaml --positions-every abc --out "$tmp/x" 2>"$tmp/err" \
  >/dev/null && fail "--positions-every abc"
grep -q -- "--positions-every expects a non-negative number, got 'abc'" "$tmp/err" ||
  fail "--positions-every message: $(cat "$tmp/err")"
"$sinew" run scenes/hanging_cloth.yaml --frames-format vtk --out "$tmp/x" 2>"$tmp/err" \
  >/dev/null && fail "--frames-format vtk"
grep -q -- "--frames-format expects one of: binary binary32 ascii; got 'vtk'" "$tmp/err" ||
  fail "--frames-format message: $(cat "$tmp/err")"
"$sinew" run scenes/hanging_cloth.yaml --no-frames --frames-every 1 --out "$tmp/x" 2>"$tmp/err" \
  >/dev/null && fail "--no-frames with --frames-every"
grep -q -- "--no-frames and --frames-every" "$tmp/err" || fail "--no-frames conflict message"
[ -e "$tmp/x" ] && fail "a refused run wrote $tmp/x"

# Bad scene: file:line:column, non-zero exit, nothing written.
printf 'mesh: {grid: {size: [1, 1], vertices: [4, 4]}}\nmaterial: {density: -0.1}\noutput: {dir: %s}\n' \
  "$tmp/bad_out" >"$tmp/bad.yaml"
if "$sinew" run "$tmp/bad.yaml" 2>"$tmp/err" >/dev/null; then fail "bad scene accepted"; fi
grep -Eq "bad.yaml:2:[0-9]+: " "$tmp/err" || fail "bad scene message: $(cat "$tmp/err")"
[ -e "$tmp/bad_out" ] && fail "a bad scene wrote its output folder"

# An output folder that cannot be created: clear message, non-zero exit.
touch "$tmp/file"
if "$sinew" run scenes/hanging_cloth.yaml --out "$tmp/file/sub" --duration 0.01 --quiet 2>"$tmp/err"; then
  fail "run into an impossible folder succeeded"
fi
grep -q "$tmp/file" "$tmp/err" || fail "impossible folder message: $(cat "$tmp/err")"

# A run that cannot go on: Newton allowed one iteration with an unreachable tolerance.  It says
# when, which method and why, exits 1, keeps its logs (renamed, complete up to the failure),
# writes the last good state as a frame and a summary saying "failed".
sed -e 's/newton: {max_iterations: 50, tol: 1e-2}/newton: {max_iterations: 1, tol: 1e-12}/' \
    -e 's/max_halvings: 8 /max_halvings: 2 /' scenes/hanging_cloth.yaml >"$tmp/failing.yaml"
if "$sinew" run "$tmp/failing.yaml" --out "$tmp/fail" --quiet 2>"$tmp/err"; then
  fail "a failing run exited 0"
fi
grep -q 't = 0 s: backward-euler: Newton did not converge in 1 iterations' "$tmp/err" ||
  fail "failure message: $(cat "$tmp/err")"
grep -q 'halved 2 times' "$tmp/err" || fail "failure message names the halvings"
grep -q '"status": "failed"' "$tmp/fail/summary.json" || fail "summary says failed"
grep -q '"retries": 3' "$tmp/fail/summary.json" || fail "summary counts 3 tries that failed"
[ "$(wc -l <"$tmp/fail/tension.csv")" -eq 2 ] || fail "logs kept up to the failure (t = 0)"
ls "$tmp/fail"/*.part >/dev/null 2>&1 && fail ".part files left after a failed run"
[ "$(ls "$tmp/fail/frames/"*.vtu | wc -l)" -eq 2 ] || fail "initial frame and last good state"

# The run loop's automatic energy bound counts what actuated tendons store: the 2D membrane starts
# with no energy at all, and its contracting cables are not an explicit blow-up (they were, with
# a bound of 1 mJ, until sinew bench showed it).  Two halvings: at t = 0.49 s a 10 ms step's
# Newton needs more than 50 iterations (it needs 49 with linear keyframes); an energy bound
# would fail every halving alike.
"$sinew" run scenes/bench/membrane_crush_2d.yaml --method bdf2 --dt 0.01 --duration 1.0 \
  --max-halvings 2 --no-frames --out "$tmp/tm" --quiet 2>"$tmp/err" ||
  fail "tendon membrane under bdf2 stopped: $(cat "$tmp/err")"

# --max-order N (adaptive methods): summary.json records it and counts every step at its BDF
# order, none above N; out-of-range orders are refused.
for q in 2 5; do
  "$sinew" run tests/data/bench_tiny.yaml --method cvode --max-order $q --duration 0.1 --no-frames \
    --out "$tmp/q$q" --quiet 2>"$tmp/err" || fail "--max-order $q run: $(cat "$tmp/err")"
  grep -q "\"max_order\": $q," "$tmp/q$q/summary.json" || fail "--max-order $q: summary max_order"
done
o2=$(sed -n 's/.*"steps_by_order": \[\(.*\)\].*/\1/p' "$tmp/q2/summary.json")
o5=$(sed -n 's/.*"steps_by_order": \[\(.*\)\].*/\1/p' "$tmp/q5/summary.json")
n2=$(sed -n 's/.*"steps": \([0-9]*\).*/\1/p' "$tmp/q2/summary.json")
/usr/bin/python3 -c "import sys; a = [$o2]; b = [$o5]; sys.exit(not (sum(a) == $n2 and a[2:] == [0, 0, 0] and sum(b[2:]) > 0))" ||
  fail "--max-order: steps by order [$o2] ($n2 steps) with 2, [$o5] with 5"
grep -q '"steps_by_order"' "$tmp/run/summary.json" && fail "a fixed-step run has steps_by_order"
# auto (the default): CVODE at most order 2 at rtol 1e-3, 5 at 1e-6 (summary: the order in use)
for r in 1e-3 1e-6; do
  "$sinew" run tests/data/bench_tiny.yaml --method cvode --max-order auto --rtol $r --duration 0.1 \
    --no-frames --out "$tmp/qa$r" --quiet 2>"$tmp/err" || fail "--max-order auto run: $(cat "$tmp/err")"
done
grep -q '"max_order": 2,' "$tmp/qa1e-3/summary.json" || fail "auto at rtol 1e-3 is not order 2"
grep -q '"max_order": 5,' "$tmp/qa1e-6/summary.json" || fail "auto at rtol 1e-6 is not order 5"
for bad in 0 6 x; do
  "$sinew" run tests/data/bench_tiny.yaml --method cvode --max-order $bad --out "$tmp/x" \
    2>"$tmp/err" >/dev/null && fail "--max-order $bad accepted"
  grep -q -- "--max-order expects auto or an integer 1..5, got '$bad'" "$tmp/err" ||
    fail "--max-order $bad message: $(cat "$tmp/err")"
done

# Every shipped scene loads.
for f in scenes/*.yaml scenes/models/*.yaml scenes/bench/*.yaml; do
  "$sinew" check "$f" >/dev/null 2>"$tmp/err" || fail "check $f: $(cat "$tmp/err")"
done

# A tendon scene: tendons.csv, one line per tendon per logged state, whole lines.
"$sinew" run scenes/tendon_membrane_2d.yaml --out "$tmp/tm" --duration 0.05 --quiet 2>"$tmp/err" ||
  fail "tendon run: $(cat "$tmp/err")"
head -1 "$tmp/tm/tendons.csv" | grep -qx 'time,tendon,length,delta,tension' || fail "tendons header"
[ "$(wc -l <"$tmp/tm/tendons.csv")" -eq $((1 + 6 * 3)) ] || fail "tendons.csv: 3 tendons x 6 states"
grep -Evq '^[0-9.e-]+,(left|middle|right),[^,]+,[^,]+,[^,]+$' <(tail -n +2 "$tmp/tm/tendons.csv") &&
  fail "tendons.csv lines: $(head -3 "$tmp/tm/tendons.csv")"
grep -q '"tendons.csv"' "$tmp/tm/summary.json" || fail "summary lists tendons.csv"

# The shipped 2D membrane is smooth by design (its header): the whole run at dt 10 ms needs no
# halving, every cable stays taut once pretensioned (t > 0.05 s), and no face is crushed (shear
# angle below 0.6 rad; the 80 % contraction of scenes/bench/membrane_crush_2d.yaml reaches 1.57).
"$sinew" run scenes/tendon_membrane_2d.yaml --out "$tmp/tm4" --no-frames --quiet 2>"$tmp/err" ||
  fail "tendon membrane, whole run: $(cat "$tmp/err")"
grep -q '"retries": 0,' "$tmp/tm4/summary.json" || fail "tendon membrane: a step was halved"
awk -F, 'NR > 1 && $1 > 0.05 && $5 <= 0 { bad = 1 } END { exit bad }' "$tmp/tm4/tendons.csv" ||
  fail "tendon membrane: a cable went slack"
awk -F, 'NR > 1 && $7 > 0.6 { bad = 1 } END { exit bad }' "$tmp/tm4/tension.csv" ||
  fail "tendon membrane: a face sheared past 0.6 rad"

# A static run of a stiff chain (tests/data/static_chain.yaml): its forces stop at their
# round-off floor, far above the default tolerance; the run succeeds (exit 0, status ok) and
# writes the equilibrium, whose middle node sags q l^2 / (8 T) = 0.613125 um.
"$sinew" run tests/data/static_chain.yaml --out "$tmp/sc" --positions-every 1 --quiet \
  2>"$tmp/err" || fail "static run of a stiff chain: $(cat "$tmp/err")"
grep -q '"status": "ok"' "$tmp/sc/summary.json" || fail "static chain: summary status"
[ "$(stat -c %s "$tmp/sc/positions.bin")" -eq $((16 + 8 * (1 + 11 * 2))) ] ||
  fail "static chain: positions.bin holds one record"
y5=$(od -An -t f8 -j $((16 + 8 * 12)) -N 8 "$tmp/sc/positions.bin")  # vertex 5, y
awk -v y="$y5" 'BEGIN { e = (-y - 6.13125e-7) / 6.13125e-7; exit !(e < 1e-6 && e > -1e-6) }' ||
  fail "static chain: middle node at y = $y5 m, expected -6.13125e-07 m"

# The gathered two-panel garment (bw98 + StVK panels, dihedral bending, Rayleigh damping, the
# drawstring pulling): Newton converges at every step of the scene's own dt, no halving.
"$sinew" run scenes/garment_drawstring.yaml --duration 0.6 --max-halvings 0 --no-frames \
  --out "$tmp/garment" --quiet 2>"$tmp/err" || fail "garment to 0.6 s without halving: $(cat "$tmp/err")"
grep -q '"status": "ok"' "$tmp/garment/summary.json" || fail "garment: status not ok"
grep -q '"retries": 0,' "$tmp/garment/summary.json" || fail "garment: a step was retried"

# Contact scenes: the skirt falls onto the body without a step halved; the cloth drapes over the
# sphere (one step of its wrapping is halved, docs/contact.md); contact.csv logs contacts (some)
# and the smallest distance (always positive).
for sc in skirt_body:0.6:0 drape_sphere:0.45:8; do
  IFS=: read -r name dur halvings <<<"$sc"
  "$sinew" run "scenes/$name.yaml" --duration "$dur" --max-halvings "$halvings" --no-frames \
    --out "$tmp/$name" --quiet 2>"$tmp/err" || fail "$name to $dur s: $(cat "$tmp/err")"
  awk -F, 'NR > 1 { n += $2; if (!($3 > 0)) bad = 1 } END { exit !(n > 0 && !bad) }' \
    "$tmp/$name/contact.csv" || fail "$name: contact.csv has no contact or a distance <= 0"
  grep -q '"self_intersections": [0-9]' "$tmp/$name/summary.json" ||
    fail "$name: summary.json has no self_intersections"
done
# the skirt does not fold onto itself; the draped cloth's folds have self-contact and do not cross
for name in skirt_body drape_sphere; do
  grep -q '"self_intersections": 0,' "$tmp/$name/summary.json" || fail "$name: the cloth crossed itself"
done

# Self-contact: the upright cloth folds onto itself from 0.2 s on; no face pair crosses at the
# end (exact test), self-contact pairs are logged and their smallest gap is always positive.
"$sinew" run scenes/fold_self.yaml --duration 0.3 --no-frames --out "$tmp/fold" --quiet \
  2>"$tmp/err" || fail "fold_self to 0.3 s: $(cat "$tmp/err")"
grep -q '"self_intersections": 0,' "$tmp/fold/summary.json" || fail "fold_self: the cloth crossed itself"
grep -q '"pattern_growths": [1-9]' "$tmp/fold/summary.json" || fail "fold_self: the pattern never grew"
awk -F, 'NR == 1 { for (k = 1; k <= NF; k++) col[$k] = k }
         NR > 1 { n += $(col["self_contacts"]); if (!($(col["self_min_gap"]) > 0)) bad = 1 }
         END { exit !(n > 0 && !bad) }' "$tmp/fold/contact.csv" ||
  fail "fold_self: contact.csv has no self-contact or a gap <= 0"

# A mesh obstacle (scenes/drape_mesh.yaml: a cloth on an icosphere OBJ standing on a floor): the
# whole run, which ends at rest with no triangle of the cloth crossing the sphere's or its own
# (the cloth starts outside and is connected, so a vertex inside would need a crossing), and the
# obstacles holding the cloth's weight (0.036 kg x 9.81 m/s^2) to 1 %: the barriers' vertical
# force plus friction's (the sphere has friction too).
"$sinew" run scenes/drape_mesh.yaml --no-frames --out "$tmp/drape_mesh" --quiet 2>"$tmp/err" ||
  fail "drape_mesh: $(cat "$tmp/err")"
for key in self_intersections obstacle_intersections; do
  grep -q "\"$key\": 0," "$tmp/drape_mesh/summary.json" || fail "drape_mesh: $key is not 0"
done
tail -1 "$tmp/drape_mesh/contact.csv" | awk -F, '{ w = 0.036 * 9.81; e = ($6 + $10 - w) / w
  exit !($3 > 0 && e < 0.01 && e > -0.01) }' || fail "drape_mesh: the final contact force is not the weight"

# --newton-norm: the two norms, and a bad one refused
for n in rms max; do
  "$sinew" run scenes/hanging_cloth.yaml --newton-norm $n --duration 0.02 --no-frames \
    --out "$tmp/norm" --quiet 2>/dev/null || fail "--newton-norm $n"
done
"$sinew" run scenes/hanging_cloth.yaml --newton-norm l2 --out "$tmp/x" >/dev/null 2>"$tmp/err" &&
  fail "--newton-norm l2 accepted"
grep -q -- "--newton-norm" "$tmp/err" || fail "--newton-norm l2 message: $(cat "$tmp/err")"

echo "$fails failure(s)"
[ "$fails" -eq 0 ]
