#!/usr/bin/env bash
# tests/cli_inverse.sh SINEW — `sinew inverse` end to end (docs/inverse.md): a reachable target
# on scenes/tendon_inverse_2d.yaml (exit 0, the table, the rewritten scene beside the targets,
# loadable, the forward check passed), an unreachable one (exit 1, the least-squares answer
# still printed), and bad input (exit 2, file:line:column, nothing written).
. "$(dirname "$0")/lib.sh"

scene=scenes/tendon_inverse_2d.yaml
cp scenes/tendon_inverse_2d_targets.csv "$tmp/targets.csv"
"$sinew" --help | grep -q 'sinew inverse SCENE --targets FILE' || fail "--help shows inverse"

# A good run: default output beside the targets.
out=$("$sinew" inverse "$scene" --targets "$tmp/targets.csv" 2>"$tmp/err")
rc=$?
[ $rc -eq 0 ] || fail "good run exit $rc: $out $(cat "$tmp/err")"
grep -Eq '^bottom +cable +1000 +2\.80832 +10\.1749 +2\.79814' <<<"$out" || fail "table: $out"
grep -q 'relative [0-9.e-]*; tolerance 1e-06' <<<"$out" || fail "relative residual: $out"
grep -q 'forward check: static solve converged.*passed' <<<"$out" || fail "check passed: $out"
res="$tmp/tendon_inverse_2d_inverse.yaml"
[ -f "$res" ] || fail "no $res"
[ "$(grep -c 'rest_length: ' "$res")" -eq 4 ] || fail "four rest lengths in $res"
grep -q 'rest_length: 2.798144001804' "$res" || fail "bottom's rest length: $(cat "$res")"
"$sinew" check "$res" >/dev/null 2>&1 || fail "the written scene does not load"
ls "$tmp"/*.yaml.* >/dev/null 2>&1 && fail "a temporary file was left"

# --out, and a second run on the written scene gives the same rest lengths.
"$sinew" inverse "$res" --targets "$tmp/targets.csv" --out "$tmp/again.yaml" >/dev/null 2>&1 ||
  fail "a run on the written scene"
diff <(grep rest_length "$res") <(grep rest_length "$tmp/again.yaml") >/dev/null ||
  fail "the written scene does not reproduce its rest lengths"

# Unreachable: exit 1, the least-squares answer and the reason.
printf 'vertex,fx,fy\n4,0,0\n5,0,-3\n' >"$tmp/far.csv"
out=$("$sinew" inverse "$scene" --targets "$tmp/far.csv" --out "$tmp/far.yaml" 2>&1)
rc=$?
[ $rc -eq 1 ] || fail "unreachable exit $rc"
grep -q 'targets unreachable' <<<"$out" || fail "unreachable message: $out"
grep -q '^top .* 0 ' <<<"$out" || fail "unreachable: the least-squares tensions: $out"
grep -q 'FAILED' <<<"$out" || fail "unreachable: the forward check fails: $out"

# A tension the stiffness cannot give (rest length < 0): refused, exit 1, nothing written.
sed '0,/stiffness: 1000/s//stiffness: 2/' "$scene" >"$tmp/soft.yaml"
"$sinew" inverse "$tmp/soft.yaml" --targets "$tmp/targets.csv" --out "$tmp/soft_out.yaml" \
  >/dev/null 2>"$tmp/err"
rc=$?
[ $rc -eq 1 ] || fail "negative rest length exit $rc"
grep -q 'tendon bottom needs tension .* expected a stiffness of at least' "$tmp/err" ||
  fail "negative rest length message: $(cat "$tmp/err")"
[ -e "$tmp/soft_out.yaml" ] && fail "a negative rest length was written"

# A target on a pinned vertex (0, anchor A): refused with file:line:column naming the vertex.
printf 'vertex,fx,fy\n4,0,0\n0,1,0\n' >"$tmp/pinned.csv"
"$sinew" inverse "$scene" --targets "$tmp/pinned.csv" --out "$tmp/pinned.yaml" >/dev/null \
  2>"$tmp/err"
rc=$?
[ $rc -eq 2 ] || fail "pinned target exit $rc"
grep -q "pinned.csv:3:1: vertex 0 is pinned by the scene; expected a free vertex" "$tmp/err" ||
  fail "pinned target message: $(cat "$tmp/err")"
[ -e "$tmp/pinned.yaml" ] && fail "a target on a pin was written"

# Bad targets: file:line:column, exit 2, nothing written.
printf 'vertex,fx,fy\n4,0,0\n5,x,-3\n' >"$tmp/bad.csv"
"$sinew" inverse "$scene" --targets "$tmp/bad.csv" --out "$tmp/bad.yaml" >/dev/null 2>"$tmp/err"
rc=$?
[ $rc -eq 2 ] || fail "bad targets exit $rc"
grep -q "bad.csv:3:3: fx is 'x'; expected a finite number" "$tmp/err" || fail "bad targets: $(cat "$tmp/err")"
[ -e "$tmp/bad.yaml" ] && fail "bad targets wrote a scene"
printf 'vertex,fx,fy,fz\n4,0,0,0\n' >"$tmp/bad3.csv"
"$sinew" inverse "$scene" --targets "$tmp/bad3.csv" --out "$tmp/bad.yaml" >/dev/null 2>"$tmp/err"
[ $? -eq 2 ] && grep -q 'bad3.csv:1:14: ' "$tmp/err" || fail "3D header in 2D: $(cat "$tmp/err")"

# Bad command lines and scenes.
"$sinew" inverse "$scene" >/dev/null 2>&1; [ $? -eq 2 ] || fail "no --targets"
"$sinew" inverse "$scene" --targets "$tmp/none.csv" >/dev/null 2>&1; [ $? -eq 2 ] || fail "missing targets"
"$sinew" inverse scenes/hanging_cloth.yaml --targets "$tmp/targets.csv" 2>"$tmp/err" >/dev/null
[ $? -eq 2 ] && grep -q 'has no tendons' "$tmp/err" || fail "scene without tendons"

[ $fails -eq 0 ] && echo "cli_inverse: all passed"
exit $((fails > 0))
