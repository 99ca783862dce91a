#!/usr/bin/env bash
# tools/readme_pictures.sh [SINEW] — the README's picture of scenes/cloth_drawstring.yaml,
# redrawn from the shipped scene: runs it to its end (t = 2 s, a few seconds), renders the last
# frame into docs/images/cloth_drawstring_tension.png and writes the numbers the picture shows
# and the README quotes into docs/images/cloth_drawstring_tension.txt (tests/readme_picture.sh
# fails when a fresh run no longer gives them: then run this and update the README's sentence).
set -eu
cd "$(dirname "$0")/.."
sinew=${1:-build/sinew}
run=$(mktemp -d)
trap 'rm -rf "$run"' EXIT
"$sinew" run scenes/cloth_drawstring.yaml --out "$run/ds" --frames-every 0.5 --quiet
"$sinew" render "$run/ds" --last --out "$run/render" --quiet
cp "$(ls "$run"/render/*.png | tail -1)" docs/images/cloth_drawstring_tension.png
/usr/bin/python3 - "$run/ds" >docs/images/cloth_drawstring_tension.txt <<'PY'
import csv, sys
d = sys.argv[1]
tension = list(csv.DictReader(open(f"{d}/tension.csv")))[-1]
tendon = [r for r in csv.DictReader(open(f"{d}/tendons.csv")) if r["tendon"] == "drawstring"][-1]
print("# the numbers of docs/images/cloth_drawstring_tension.png (tools/readme_pictures.sh),")
print("# quoted in README.md and checked against a fresh run by tests/readme_picture.sh")
print("scene = scenes/cloth_drawstring.yaml")
print(f"time_s = {float(tension['time']):g}")
print(f"drawstring_tension_N = {float(tendon['tension']):.3g}")
print(f"txy_max_N_per_m = {float(tension['txy_max']):.3g}")
PY
cat docs/images/cloth_drawstring_tension.txt
