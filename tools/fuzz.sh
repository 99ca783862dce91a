#!/usr/bin/env bash
# tools/fuzz.sh [SECONDS] — build the libFuzzer harnesses (clang, ASan + UBSan) in build-fuzz and
# run each for SECONDS (default 300), seeded with the shipped scenes, meshes and regression
# inputs.  A crashing input is written as crash-* in build-fuzz/; copy it into
# tests/fuzz/regress/{obj,scene}/ so the normal suite keeps it (test_mesh, test_scene read them).
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-300}
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang meson setup build-fuzz -Dfuzz=true -Dtests=false -Db_sanitize=address,undefined \
    -Db_lundef=false >/dev/null
fi
ninja -C build-fuzz >/dev/null
for name in obj scene; do
  corpus=build-fuzz/corpus_$name
  mkdir -p "$corpus"
  cp tests/fuzz/regress/$name/* "$corpus"/ 2>/dev/null || true
  if [ $name = scene ]; then cp scenes/*.yaml "$corpus"/; else cp scenes/*.obj "$corpus"/ 2>/dev/null || true; fi
  echo "fuzz_$name: $secs s"
  (cd build-fuzz && ./tests/fuzz/fuzz_$name -max_len=8192 -max_total_time="$secs" -print_final_stats=1 \
    "corpus_$name" 2>&1 | grep -E '^stat::number_of_executed_units|^INFO: -max_total_time|ERROR|SUMMARY' || true)
done
