#!/usr/bin/env bash
# tools/setup.sh — install the Debian packages sinew needs (only those missing; as root or through
# sudo), then configure and build it in ./build.  Idempotent: a second run only rebuilds.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(libsuitesparse-dev libsundials-dev libopenblas-dev libfyaml-dev libcmocka-dev
          meson ninja-build pkg-config gcc python3-matplotlib python3-numpy python3-pytest
          python3-pandas zlib1g-dev python3-pil python3-vtk9 python3-yaml
          python3-ezdxf python3-gmsh python3-scipy python3-mesonpy
          python3-pip python3-venv)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  if [ "$(id -u)" -eq 0 ]; then
    as_root=()
  elif command -v sudo >/dev/null; then
    as_root=(sudo)
  else
    echo "setup: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${as_root[@]}" apt-get update -qq
  "${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ ! -f build/build.ninja ]; then
  meson setup build --buildtype=debugoptimized >/dev/null
fi
ninja -C build >/dev/null
echo "setup: built ./build/sinew ($(./build/sinew --version))"
