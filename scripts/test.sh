#!/usr/bin/env bash
# Builds clpt and runs the whole test suite on the PoCL CPU device.
# Installs missing dependencies first (idempotent), so it works on a fresh Debian 12.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j "$jobs" "$@"
