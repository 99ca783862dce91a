#!/usr/bin/env bash
# tools/fuzz.sh [SECONDS] — build the libFuzzer harnesses (clang, ASan + UBSan) in build-fuzz and
# run each for SECONDS (default 300), seeded with the shipped scenes, meshes and regression
# inputs.  A crashing input is written as crash-* in build-fuzz/; copy it into
# tests/fuzz/regress/{obj,scene}/ so the normal suite keeps it (test_mesh, test_scene read them).
# With SW_FUZZ_ALLOC=1 the harnesses are built with -DSW_FUZZ_ALLOC in build-fuzz-alloc: the
# first input byte b makes allocation b+1 fail, to fuzz the out-of-memory paths for leaks (its
# crash inputs start with that byte; strip it before keeping one as a regression input).
# Run it niced on a shared machine: nice -n 19 tools/fuzz.sh 600.
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-300}
dir=build-fuzz
cargs=()
if [ "${SW_FUZZ_ALLOC:-0}" = 1 ]; then
  dir=build-fuzz-alloc
  cargs=(-Dc_args=-DSW_FUZZ_ALLOC)
fi
if [ ! -f $dir/build.ninja ]; then
  CC=clang meson setup $dir -Dfuzz=true -Dtests=false -Db_sanitize=address,undefined \
    -Db_lundef=false "${cargs[@]}" >/dev/null
fi
ninja -C $dir >/dev/null
for name in obj scene targets bench; do
  corpus=$dir/corpus_$name
  mkdir -p "$corpus"
  cp tests/fuzz/regress/$name/* "$corpus"/ 2>/dev/null || true
  if [ $name = scene ]; then cp scenes/*.yaml "$corpus"/; fi
  if [ $name = obj ]; then cp scenes/*.obj "$corpus"/ 2>/dev/null || true; fi
  echo "fuzz_$name: $secs s"
  (cd $dir && ./tests/fuzz/fuzz_$name -max_len=8192 -max_total_time="$secs" -print_final_stats=1 \
    "corpus_$name" 2>&1 | grep -E '^stat::number_of_executed_units|^INFO: -max_total_time|ERROR|SUMMARY' || true)
done
