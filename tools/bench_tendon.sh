#!/bin/sh
# Fill and time of a tendon's Hessian, dense stencil against low-rank (docs/tendons.md):
# a 60 x 60 hanging cloth with one tendon of 2 ... 200 waypoints; writes
# docs/bench/tendon_fill.csv.  Run from the source root after `ninja -C build`.
set -e
out=docs/bench/tendon_fill.csv
./build/bench/bench_tendon --header > "$out.tmp"
for w in 2 8 16 32 48 64 128 200 400; do
  ./build/bench/bench_tendon 60 "$w" 3 >> "$out.tmp"
done
mv "$out.tmp" "$out"
cat "$out"
