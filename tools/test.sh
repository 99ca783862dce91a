#!/usr/bin/env bash
# tools/test.sh — set up when needed, then build and run the whole test suite (meson test).
# Extra arguments go to `meson test`, e.g. --suite unit or a test name.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
meson test -C build --print-errorlogs "$@"
