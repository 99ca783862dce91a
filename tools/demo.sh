#!/usr/bin/env bash
# tools/demo.sh — set up when needed, then run the default scene (a hanging cloth) and say where
# the results are.  Extra arguments go to `sinew run`, e.g. --duration 0.5.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
./build/sinew run scenes/hanging_cloth.yaml "$@"
