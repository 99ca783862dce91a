#!/usr/bin/env bash
# tests/readme_picture.sh SINEW — the README's picture of scenes/cloth_drawstring.yaml is the
# shipped scene's (about 3 s): a fresh run to t = 2 s gives the numbers the picture was drawn
# with (docs/images/cloth_drawstring_tension.txt, written by tools/readme_pictures.sh, to 0.5 %),
# and the README quotes them.  When the scene or the physics changes, run tools/readme_pictures.sh.
. "$(dirname "$0")/lib.sh"
nums=docs/images/cloth_drawstring_tension.txt
get() { sed -n "s/^$1 = //p" "$nums"; }
t=$(get time_s)
"$sinew" run scenes/cloth_drawstring.yaml --out "$tmp/ds" --duration "$t" --no-frames --quiet ||
  fail "the run failed"
fresh_tendon=$(awk -F, '$2 == "drawstring" { v = $5 } END { print v }' "$tmp/ds/tendons.csv")
fresh_txy=$(awk -F, 'NR > 1 { v = $2 } END { print v }' "$tmp/ds/tension.csv")
near() { # what stored fresh
  /usr/bin/python3 -c "import sys; s, f = float('$2'), float('${3:-nan}'); sys.exit(not abs(f - s) <= 5e-3 * abs(s))" ||
    fail "$1: the picture shows $2, a fresh run gives $3 (run tools/readme_pictures.sh and update README.md)"
}
near "drawstring tension (N)" "$(get drawstring_tension_N)" "$fresh_tendon"
near "tension XY max (N/m)" "$(get txy_max_N_per_m)" "$fresh_txy"
grep -q "drawstring, at $(get drawstring_tension_N) N," README.md || fail "README.md does not quote the drawstring's $(get drawstring_tension_N) N"
grep -q "at most $(get txy_max_N_per_m) N/m" README.md || fail "README.md does not quote tension XY at most $(get txy_max_N_per_m) N/m"
[ "$fails" -eq 0 ] && echo "readme_picture: all checks passed"
[ "$fails" -eq 0 ]
